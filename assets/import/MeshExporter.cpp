#include "assets/import/MeshExporter.h"

#include <assimp/scene.h>

#include <stdlib.h>
#include <assimp/Exporter.hpp>

#include <cstdio>
#include <string>

#include "physics/core/OutputFile.h"

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

// OBJ written here rather than by assimp, whose writer keeps six digits: a level far from the origin
// (1e7 m) would come out as one point. %.9g keeps every float exactly.
std::string ObjText(const ImportedMesh& mesh, bool z_up) {
  std::string text = "# Strata mesh\n";
  char line[128];
  for (const Vec3& v : mesh.vertices) {
    const Vec3 out = z_up ? Vec3(v.x(), -v.z(), v.y()) : v;
    std::snprintf(line, sizeof(line), "v %.9g %.9g %.9g\n", static_cast<double>(out.x()),
                  static_cast<double>(out.y()), static_cast<double>(out.z()));
    text += line;
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(line, sizeof(line), "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    text += line;
  }
  return text;
}

}  // namespace

Status ExportMesh(const ImportedMesh& mesh, const std::filesystem::path& path, const std::string& format,
                  bool z_up) {
  if (mesh.triangles.empty())
    return MakeError(ErrorCode::kInvalidArgument, path.string() + ": no triangles to write");
  if (format == "objnomtl") return WriteOutputFile(path, ObjText(mesh, z_up));
  const std::unique_ptr<aiScene> scene = MakeScene(mesh, z_up);
  Assimp::Exporter exporter;
  // One file (GLB, PLY, STL, FBX): to memory, then written whole or not at all.
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), format);
  if (blob == nullptr)
    return MakeError(ErrorCode::kParseError,
                     path.string() + ": cannot export as " + format + ": " + exporter.GetErrorString());
  if (blob->next == nullptr) return WriteOutputFile(path, {static_cast<const char*>(blob->data), blob->size});
  // Several files (OBJ's .mtl, glTF's .bin), which refer to each other by name: into a private folder beside
  // the target, then each renamed into place.
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  std::string pattern = folder.string();
  pattern += "/.";
  pattern += path.filename().string();
  pattern += ".strata-export-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr)
    return MakeError(ErrorCode::kInvalidArgument, path.string() + ": cannot create a folder beside it");
  const std::filesystem::path staging(pattern);
  Status status = Status::Ok();
  if (exporter.Export(scene.get(), format, (staging / path.filename()).string()) != aiReturn_SUCCESS)
    status = MakeError(ErrorCode::kParseError,
                       path.string() + ": cannot export as " + format + ": " + exporter.GetErrorString());
  std::error_code error;
  for (std::filesystem::directory_iterator it(staging, error), end; status && !error && it != end;
       it.increment(error))
    if (std::rename(it->path().c_str(), (folder / it->path().filename()).c_str()) != 0)
      status =
          MakeError(ErrorCode::kInvalidArgument, path.string() + ": cannot move the written file into place");
  std::filesystem::remove_all(staging, error);
  return status;
}

}  // namespace strata
