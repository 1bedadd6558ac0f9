// TileData: owns one Detour tile's bytes (allocated with dtAlloc, as Detour expects to free them) until
// they are handed to a dtNavMesh. Move-only value; one owner at a time.
#pragma once

#include <cstddef>
#include <span>

namespace strata::navmesh {

/// Detour tile bytes; empty means "no walkable surface in this tile".
class TileData {
 public:
  TileData() = default;
  /// Takes ownership of `bytes`, which must come from dtAlloc.
  TileData(unsigned char* bytes, int size) : bytes_(bytes), size_(size) {}
  TileData(TileData&& other) noexcept { *this = static_cast<TileData&&>(other); }
  TileData& operator=(TileData&& other) noexcept;
  TileData(const TileData&) = delete;
  TileData& operator=(const TileData&) = delete;
  ~TileData();

  /// A dtAlloc'd copy of `bytes` (for loading from a file).
  static TileData CopyOf(std::span<const unsigned char> bytes);

  bool empty() const { return bytes_ == nullptr; }
  int size() const { return size_; }
  std::span<const unsigned char> bytes() const { return {bytes_, static_cast<std::size_t>(size_)}; }
  /// Gives up ownership (to a dtNavMesh created with DT_TILE_FREE_DATA).
  unsigned char* Release();

 private:
  unsigned char* bytes_ = nullptr;
  int size_ = 0;
};

}  // namespace strata::navmesh
