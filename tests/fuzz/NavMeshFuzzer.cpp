// libFuzzer target: navmesh files (RecastDemo's MSET set). Any input must load or give an error, never a
// crash or sanitizer report, and whatever loads must be safe to query (paths, raycasts, islands).
#include <cstddef>
#include <cstdint>

#include "FuzzInput.h"
#include "navmesh/NavMesh.h"
#include "navmesh/NavMeshQuery.h"
#include "navmesh/Validation.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = strata::fuzz::WriteInput(data, size, "strata_fuzz_navmesh", ".bin");
  const auto loaded = strata::navmesh::NavMesh::Load(path);
  if (!loaded) return 0;
  const auto query = strata::navmesh::NavMeshQuery::Create(**loaded);
  if (!query) return 0;
  (void)(*query)->FindPath(strata::Vec3(2, 0, 2), strata::Vec3(23, 0, 23));
  (void)(*query)->Raycast(strata::Vec3(2, 0, 2), strata::Vec3(23, 0, 2));
  (void)strata::navmesh::CountIslands(**loaded);
  (void)(*loaded)->WalkableArea();
  return 0;
}
