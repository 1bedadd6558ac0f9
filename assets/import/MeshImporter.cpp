#include "assets/import/MeshImporter.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <assimp/Importer.hpp>
#include <map>
#include <new>
#include <string>

#include "assets/import/DeclaredCounts.h"
#include "physics/core/InputFile.h"

namespace strata {

namespace {

Error ImportError(const std::filesystem::path& path, const std::string& why) {
  return MakeError(ErrorCode::kParseError, path.string() + ": " + why);
}

void AppendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
                const MeshImportOptions& options, ImportedMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      Vec3 vertex(p.x, p.y, p.z);
      if (options.z_up) vertex = Vec3(p.x, p.z, -p.y);
      out.vertices.push_back(vertex * options.scale);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left over after triangulation
      out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    AppendNode(scene, *node.mChildren[c], transform, options, out);
}

/// Merges vertices at exactly the same position (assimp welds within one mesh only) and drops triangles
/// that collapse to zero area, keeping the others in file order.
void WeldAndDropDegenerates(ImportedMesh& mesh) {
  constexpr std::uint32_t kUnused = 0xffffffffu;
  std::map<std::array<float, 3>, std::uint32_t> unique;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  std::vector<Vec3> welded;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    const auto [it, inserted] =
        unique.try_emplace({v.x(), v.y(), v.z()}, static_cast<std::uint32_t>(welded.size()));
    if (inserted) welded.push_back(v);
    remap[i] = it->second;
  }
  // Drop zero-area triangles, then the vertices only they used.
  std::vector<TriangleMeshShape::Indices> kept;
  std::vector<std::uint32_t> compact(welded.size(), kUnused);
  std::vector<Vec3> used;
  for (const auto& triangle : mesh.triangles) {
    const TriangleMeshShape::Indices t{remap[triangle[0]], remap[triangle[1]], remap[triangle[2]]};
    const Vec3 normal = (welded[t[1]] - welded[t[0]]).cross(welded[t[2]] - welded[t[0]]);
    if (normal.squaredNorm() <= 1e-12f) continue;
    TriangleMeshShape::Indices renumbered;
    for (int k = 0; k < 3; ++k) {
      if (compact[t[k]] == kUnused) {
        compact[t[k]] = static_cast<std::uint32_t>(used.size());
        used.push_back(welded[t[k]]);
      }
      renumbered[k] = compact[t[k]];
    }
    kept.push_back(renumbered);
  }
  mesh.vertices = std::move(used);
  mesh.triangles = std::move(kept);
}

// The import itself, once the file passed the input policy.
Result<ImportedMesh> Import(const std::filesystem::path& path, const MeshImportOptions& options) {
  Assimp::Importer importer;
  // Drop normals, colours and UVs before welding so vertices differing only in those still merge.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS |
                                                          aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS);
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | aiProcess_RemoveComponent | aiProcess_JoinIdenticalVertices |
                         aiProcess_FindDegenerates | aiProcess_SortByPType);
  // No aiProcess_FindInvalidData: it silently drops meshes with NaN vertices, and we want to say so.
  if (!scene || !scene->mRootNode)
    return ImportError(path, std::string("cannot import: ") + importer.GetErrorString());
  ImportedMesh mesh;
  AppendNode(*scene, *scene->mRootNode, aiMatrix4x4(), options, mesh);
  for (const Vec3& v : mesh.vertices)
    if (!IsFinite(v)) return ImportError(path, "has non-finite vertex coordinates");
  WeldAndDropDegenerates(mesh);
  if (mesh.triangles.empty()) return ImportError(path, "contains no triangles");
  return mesh;
}

}  // namespace

Result<ImportedMesh> ImportMesh(const std::filesystem::path& path, const MeshImportOptions& options) {
  if (!IsFinite(options.scale) || options.scale <= 0.0f)
    return ImportError(path, "scale must be a positive number");
  const Result<std::uint64_t> size = CheckInputFile(path, kMaxMeshFileBytes);
  if (!size) return size.error();
  if (Status counts = CheckDeclaredCounts(path, *size); !counts) return counts.error();
  // Assimp reports most bad files through its error string, but throws on some (and allocation fails on
  // others): an import never takes the process down.
  try {
    return Import(path, options);
  } catch (const std::bad_alloc&) {
    return ImportError(path, "cannot import: it needs more memory than there is (a corrupt count?)");
  } catch (const std::exception& exception) {
    return ImportError(path, std::string("cannot import: ") + exception.what());
  }
}

}  // namespace strata
