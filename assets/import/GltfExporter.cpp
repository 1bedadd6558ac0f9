#include "assets/import/GltfExporter.h"

#include <assimp/scene.h>

#include <assimp/Exporter.hpp>
#include <memory>

#include "physics/core/OutputFile.h"

namespace strata {

namespace {

Status CheckLayer(const GltfLayer& layer) {
  const std::string what = "layer '" + layer.name + "'";
  const std::size_t per_primitive = layer.lines ? 2 : 3;
  if (layer.indices.size() % per_primitive != 0)
    return MakeError(ErrorCode::kInvalidArgument, what + ": " + std::to_string(layer.indices.size()) +
                                                      " indices are not whole " +
                                                      (layer.lines ? "segments" : "triangles"));
  if (!layer.colors.empty() && layer.colors.size() != layer.vertices.size())
    return MakeError(ErrorCode::kInvalidArgument, what + ": colours must be one per vertex");
  for (const Vec3& v : layer.vertices)
    if (!v.allFinite()) return MakeError(ErrorCode::kInvalidArgument, what + ": a vertex is not finite");
  for (const std::uint32_t index : layer.indices)
    if (index >= layer.vertices.size())
      return MakeError(ErrorCode::kInvalidArgument, what + ": index " + std::to_string(index) + " is past " +
                                                        std::to_string(layer.vertices.size()) + " vertices");
  return Status::Ok();
}

/// `layer` as an aiMesh that owns its arrays the way assimp's destructors expect (new[]).
aiMesh* MakeMesh(const GltfLayer& layer, unsigned material) {
  auto* mesh = new aiMesh();
  mesh->mName = aiString(layer.name);
  mesh->mMaterialIndex = material;
  mesh->mPrimitiveTypes = layer.lines ? aiPrimitiveType_LINE : aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = static_cast<unsigned>(layer.vertices.size());
  mesh->mVertices = new aiVector3D[layer.vertices.size()];
  for (std::size_t i = 0; i < layer.vertices.size(); ++i)
    mesh->mVertices[i] = aiVector3D(layer.vertices[i].x(), layer.vertices[i].y(), layer.vertices[i].z());
  if (!layer.colors.empty()) {
    mesh->mColors[0] = new aiColor4D[layer.colors.size()];
    for (std::size_t i = 0; i < layer.colors.size(); ++i) {
      const Vec4& c = layer.colors[i];
      mesh->mColors[0][i] = aiColor4D(c.x(), c.y(), c.z(), c.w());
    }
  }
  const unsigned per_face = layer.lines ? 2 : 3;
  mesh->mNumFaces = static_cast<unsigned>(layer.indices.size() / per_face);
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    aiFace& face = mesh->mFaces[f];
    face.mNumIndices = per_face;
    face.mIndices = new unsigned[per_face];
    for (unsigned k = 0; k < per_face; ++k) face.mIndices[k] = layer.indices[f * per_face + k];
  }
  return mesh;
}

}  // namespace

Status ExportGltf(const std::vector<GltfLayer>& layers, const std::filesystem::path& path) {
  std::vector<const GltfLayer*> kept;
  for (const GltfLayer& layer : layers) {
    if (const Status checked = CheckLayer(layer); !checked)
      return MakeError(checked.error().code, path.string() + ": " + checked.message());
    if (!layer.indices.empty()) kept.push_back(&layer);
  }
  if (kept.empty()) return MakeError(ErrorCode::kInvalidArgument, path.string() + ": nothing to write");
  // A node per layer under the root, each with its mesh, so viewers list the layers by name.
  auto scene = std::make_unique<aiScene>();
  const auto count = static_cast<unsigned>(kept.size());
  scene->mRootNode = new aiNode("strata");
  scene->mRootNode->mNumChildren = count;
  scene->mRootNode->mChildren = new aiNode*[count];
  scene->mNumMeshes = count;
  scene->mMeshes = new aiMesh*[count];
  scene->mNumMaterials = count;
  scene->mMaterials = new aiMaterial*[count];
  for (unsigned i = 0; i < count; ++i) {
    scene->mMaterials[i] = new aiMaterial();
    const aiString material_name(kept[i]->name);
    scene->mMaterials[i]->AddProperty(&material_name, AI_MATKEY_NAME);
    scene->mMeshes[i] = MakeMesh(*kept[i], i);
    auto* node = new aiNode(kept[i]->name);
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{i};
    scene->mRootNode->mChildren[i] = node;
  }
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), "glb2");
  if (blob == nullptr)
    return MakeError(ErrorCode::kParseError,
                     path.string() + ": cannot export glTF: " + exporter.GetErrorString());
  return WriteOutputFile(path, std::string_view(static_cast<const char*>(blob->data), blob->size));
}

}  // namespace strata
