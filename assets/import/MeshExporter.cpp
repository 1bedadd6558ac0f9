#include "assets/import/MeshExporter.h"

#include <assimp/scene.h>

#include <assimp/Exporter.hpp>

namespace strata {

namespace {

/// A one-mesh scene that owns its arrays the way assimp's destructors expect (new[]).
std::unique_ptr<aiScene> MakeScene(const ImportedMesh& mesh, bool z_up) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode();
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh* [1] { new aiMesh() };
  aiMesh& out = *scene->mMeshes[0];
  out.mMaterialIndex = 0;
  out.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out.mNumVertices = static_cast<unsigned>(mesh.vertices.size());
  out.mVertices = new aiVector3D[mesh.vertices.size()];
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    out.mVertices[i] = z_up ? aiVector3D(v.x(), -v.z(), v.y()) : aiVector3D(v.x(), v.y(), v.z());
  }
  out.mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  out.mFaces = new aiFace[mesh.triangles.size()];
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    aiFace& face = out.mFaces[i];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3]{mesh.triangles[i][0], mesh.triangles[i][1], mesh.triangles[i][2]};
  }
  return scene;
}

}  // namespace

Status ExportMesh(const ImportedMesh& mesh, const std::filesystem::path& path, const std::string& format,
                  bool z_up) {
  if (mesh.triangles.empty())
    return MakeError(ErrorCode::kInvalidArgument, path.string() + ": no triangles to write");
  const std::unique_ptr<aiScene> scene = MakeScene(mesh, z_up);
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), format, path.string()) != aiReturn_SUCCESS)
    return MakeError(ErrorCode::kParseError,
                     path.string() + ": cannot export as " + format + ": " + exporter.GetErrorString());
  return Status::Ok();
}

}  // namespace strata
