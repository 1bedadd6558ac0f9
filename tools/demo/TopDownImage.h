// TopDownImage: a top-down (x-z) picture of a level, its navmesh tiles, polygons and paths, written as PNG
// with stb_image_write. Plain RGB raster; one thread at a time.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "physics/core/Result.h"
#include "physics/math/AABB.h"

namespace strata::demo {

using Color = std::array<std::uint8_t, 3>;

/// An image of the x-z rectangle of `bounds`, +x to the right and +z down, `pixels_per_metre` wide, or
/// fewer where that would make a side longer than kMaxSide pixels (a level kilometres wide, one far
/// triangle).
class TopDownImage {
 public:
  static constexpr int kMaxSide = 4096;
  TopDownImage(const AABB& bounds, float pixels_per_metre);

  int width() const { return width_; }
  int height() const { return height_; }
  float pixels_per_metre() const { return scale_; }
  /// Fills a triangle, blending `color` over what is there by `alpha` (0..1).
  void FillTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Color& color, float alpha = 1.0f);
  void DrawLine(const Vec3& a, const Vec3& b, const Color& color);
  void DrawDot(const Vec3& center, int radius_pixels, const Color& color);
  Status SavePng(const std::filesystem::path& path) const;

 private:
  struct Pixel {
    float x, y;
  };
  Pixel ToPixel(const Vec3& point) const;
  void Blend(int x, int y, const Color& color, float alpha);

  AABB bounds_;
  float scale_;
  int width_;
  int height_;
  std::vector<std::uint8_t> rgb_;
};

}  // namespace strata::demo
