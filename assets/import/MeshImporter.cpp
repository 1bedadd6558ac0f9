#include "assets/import/MeshImporter.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <sys/stat.h>

#include <assimp/BaseImporter.h>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/importerdesc.h>
#include <algorithm>
#include <array>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "assets/import/DeclaredCounts.h"
#include "assets/import/ObjReader.h"
#include "assets/import/PlyReader.h"
#include "physics/core/InputFile.h"

namespace strata {

namespace {

// An import that takes longer is abandoned: no level of ours takes a second.
constexpr std::chrono::seconds kMaxImportTime{60};

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

// Every file assimp opens, the named one and those it refers to (an OBJ's mtllib, a glTF buffer's uri), goes
// through the input policy: regular files only, and all of them together within kMaxMeshFileBytes. Each is
// read whole and handed to assimp from memory, so a file cannot change under it either.
class PolicyIOSystem : public Assimp::IOSystem {
 public:
  bool Exists(const char* file) const override {
    struct stat info {};
    return ::stat(file, &info) == 0 && S_ISREG(info.st_mode);
  }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (mode == nullptr || std::strchr(mode, 'w') != nullptr || std::strchr(mode, 'a') != nullptr)
      return nullptr;
    struct stat info {};
    // A missing file is assimp's to judge: an OBJ's absent .mtl is no error.
    if (::lstat(file, &info) != 0 && errno == ENOENT) return nullptr;
    Result<std::string> bytes = ReadInputFile(file, kMaxMeshFileBytes - read_bytes_);
    if (!bytes) {
      if (refusal_.empty()) refusal_ = bytes.error().message;
      return nullptr;
    }
    read_bytes_ += bytes->size();
    auto* copy = new std::uint8_t[std::max<std::size_t>(bytes->size(), 1)];
    std::memcpy(copy, bytes->data(), bytes->size());
    return new Assimp::MemoryIOStream(copy, bytes->size(), /*own=*/true);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }
  /// Why the policy refused a file assimp asked for (empty when it refused none).
  const std::string& refusal() const { return refusal_; }

 private:
  std::uint64_t read_bytes_ = 0;
  std::string refusal_;
};

// Aborts an import that runs past its deadline (assimp asks between its stages and during long reads).
class DeadlineProgress : public Assimp::ProgressHandler {
 public:
  explicit DeadlineProgress(std::chrono::steady_clock::time_point deadline) : deadline_(deadline) {}
  bool Update(float) override { return std::chrono::steady_clock::now() < deadline_; }
  bool expired() const { return std::chrono::steady_clock::now() >= deadline_; }

 private:
  std::chrono::steady_clock::time_point deadline_;
};

ImportedMesh InStrataFrame(ImportedMesh mesh, const MeshImportOptions& options) {
  for (Vec3& v : mesh.vertices) v = (options.z_up ? Vec3(v.x(), v.z(), -v.y()) : v) * options.scale;
  return mesh;
}

Result<ImportedMesh> Finish(const std::filesystem::path& path, ImportedMesh mesh) {
  for (const Vec3& v : mesh.vertices)
    if (!IsFinite(v)) return ImportError(path, "has non-finite vertex coordinates");
  WeldAndDropDegenerates(mesh);
  if (mesh.triangles.empty()) return ImportError(path, "contains no triangles");
  return mesh;
}

// Whether an assimp loader reads a format Strata takes through assimp: glTF/GLB, FBX, STL, Collada.
bool Supported(const aiImporterDesc* description) {
  if (description == nullptr || description->mFileExtensions == nullptr) return false;
  const std::string_view extensions = description->mFileExtensions;
  for (const std::string_view wanted : {"gltf", "glb", "fbx", "stl", "dae"}) {
    for (std::size_t at = extensions.find(wanted); at != std::string_view::npos;
         at = extensions.find(wanted, at + 1)) {
      const std::size_t end = at + wanted.size();
      if ((at == 0 || extensions[at - 1] == ' ') && (end == extensions.size() || extensions[end] == ' '))
        return true;
    }
  }
  return false;
}

// Assimp tries each of its forty-odd loaders on a file it cannot place by extension, by the file's bytes;
// some allocate whatever a corrupt count says (Quick3D asked for 2 TB from a 57-byte file, found by
// fuzz_mesh_glb). Only the loaders of the formats Strata supports stay; OBJ and PLY are read by ObjReader and
// PlyReader. Unregistered, a loader is ours to delete.
void KeepOnlySupportedLoaders(Assimp::Importer& importer) {
  std::vector<Assimp::BaseImporter*> unsupported;
  for (std::size_t i = 0; i < importer.GetImporterCount(); ++i)
    if (!Supported(importer.GetImporterInfo(i))) unsupported.push_back(importer.GetImporter(i));
  for (Assimp::BaseImporter* loader : unsupported)
    if (importer.UnregisterLoader(loader) == aiReturn_SUCCESS) delete loader;
}

// The import itself, once the file passed the input policy.
Result<ImportedMesh> Import(const std::filesystem::path& path, const MeshImportOptions& options) {
  Assimp::Importer importer;
  KeepOnlySupportedLoaders(importer);
  auto* io = new PolicyIOSystem();
  importer.SetIOHandler(io);  // the importer owns both
  auto* progress = new DeadlineProgress(std::chrono::steady_clock::now() + kMaxImportTime);
  importer.SetProgressHandler(progress);
  // Drop normals, colours and UVs before welding so vertices differing only in those still merge.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS |
                                                          aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS);
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | aiProcess_RemoveComponent | aiProcess_JoinIdenticalVertices |
                         aiProcess_FindDegenerates | aiProcess_SortByPType);
  // No aiProcess_FindInvalidData: it silently drops meshes with NaN vertices, and we want to say so.
  if (!io->refusal().empty())
    return ImportError(path, "refers to a file that cannot be read: " + io->refusal());
  if (progress->expired())
    return ImportError(path, "took longer than " + std::to_string(kMaxImportTime.count()) + " s to import");
  if (!scene || !scene->mRootNode)
    return ImportError(path, std::string("cannot import: ") + importer.GetErrorString());
  ImportedMesh mesh;
  AppendNode(*scene, *scene->mRootNode, aiMatrix4x4(), options, mesh);
  return Finish(path, std::move(mesh));
}

bool LooksLikePlyFile(const std::filesystem::path& path) {
  char start[4] = {};
  std::ifstream(path, std::ios::binary).read(start, sizeof(start));
  return LooksLikePly(std::string_view(start, sizeof(start)));
}

bool HasExtension(const std::filesystem::path& path, std::string_view wanted) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == wanted;
}

}  // namespace

Result<ImportedMesh> ImportMesh(const std::filesystem::path& path, const MeshImportOptions& options) {
  if (!IsFinite(options.scale) || options.scale <= 0.0f)
    return ImportError(path, "scale must be a positive number");
  const Result<std::uint64_t> size = CheckInputFile(path, kMaxMeshFileBytes);
  if (!size) return size.error();
  const bool ply = HasExtension(path, ".ply") || LooksLikePlyFile(path);
  if (ply || HasExtension(path, ".obj")) {
    Result<std::string> bytes = ReadInputFile(path, kMaxMeshFileBytes);
    if (!bytes) return bytes.error();
    Result<ImportedMesh> mesh = ply ? ReadPly(*bytes, path) : ReadObj(*bytes, path);
    if (!mesh) return mesh.error();
    return Finish(path, InStrataFrame(std::move(*mesh), options));
  }
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
