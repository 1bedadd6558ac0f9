#include "navmesh/TileData.h"

#include <DetourAlloc.h>

#include <cstring>

namespace strata::navmesh {

TileData& TileData::operator=(TileData&& other) noexcept {
  if (this == &other) return *this;
  if (bytes_) dtFree(bytes_);
  bytes_ = other.bytes_;
  size_ = other.size_;
  other.bytes_ = nullptr;
  other.size_ = 0;
  return *this;
}

TileData::~TileData() {
  if (bytes_) dtFree(bytes_);
}

TileData TileData::CopyOf(std::span<const unsigned char> bytes) {
  if (bytes.empty()) return {};
  auto* copy = static_cast<unsigned char*>(dtAlloc(static_cast<int>(bytes.size()), DT_ALLOC_PERM));
  if (!copy) return {};
  std::memcpy(copy, bytes.data(), bytes.size());
  return {copy, static_cast<int>(bytes.size())};
}

unsigned char* TileData::Release() {
  unsigned char* bytes = bytes_;
  bytes_ = nullptr;
  size_ = 0;
  return bytes;
}

}  // namespace strata::navmesh
