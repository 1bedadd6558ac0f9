#include "tools/demo/TopDownImage.h"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "physics/core/OutputFile.h"

namespace strata::demo {

namespace {
/// `wanted`, or less so that the longer side of `bounds` fits in `max_side` pixels.
float FittingScale(const AABB& bounds, float wanted, int max_side) {
  const float longest = std::max(bounds.Size().x(), bounds.Size().z());
  if (!(longest > 0.0f) || !std::isfinite(longest)) return wanted;
  return std::min(wanted, static_cast<float>(max_side) / longest);
}

/// Pixels along a side `metres` long, in [1, max_side] whatever the input (NaN included).
int SidePixels(float metres, float scale, int max_side) {
  const double pixels = std::ceil(static_cast<double>(metres) * scale);
  if (!(pixels >= 1.0)) return 1;
  return static_cast<int>(std::min(pixels, static_cast<double>(max_side)));
}
}  // namespace

TopDownImage::TopDownImage(const AABB& bounds, float pixels_per_metre)
    : bounds_(bounds),
      scale_(FittingScale(bounds, pixels_per_metre, kMaxSide)),
      width_(SidePixels(bounds.Size().x(), scale_, kMaxSide)),
      height_(SidePixels(bounds.Size().z(), scale_, kMaxSide)),
      rgb_(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3, 255) {}

TopDownImage::Pixel TopDownImage::ToPixel(const Vec3& point) const {
  return {(point.x() - bounds_.min.x()) * scale_, (point.z() - bounds_.min.z()) * scale_};
}

void TopDownImage::Blend(int x, int y, const Color& color, float alpha) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  std::uint8_t* pixel =
      &rgb_[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)) *
            3];
  for (int c = 0; c < 3; ++c)
    pixel[c] = static_cast<std::uint8_t>(
        std::lround((1.0f - alpha) * pixel[c] + alpha * color[static_cast<std::size_t>(c)]));
}

void TopDownImage::FillTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Color& color,
                                float alpha) {
  const Pixel p[3] = {ToPixel(a), ToPixel(b), ToPixel(c)};
  const float area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
  if (std::abs(area) < 1e-6f) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
  const auto edge = [](Pixel u, Pixel v, float x, float y) {
    return (v.x - u.x) * (y - u.y) - (v.y - u.y) * (x - u.x);
  };
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
      const float w0 = edge(p[1], p[2], px, py), w1 = edge(p[2], p[0], px, py), w2 = edge(p[0], p[1], px, py);
      const bool inside = area > 0 ? (w0 >= 0 && w1 >= 0 && w2 >= 0) : (w0 <= 0 && w1 <= 0 && w2 <= 0);
      if (inside) Blend(x, y, color, alpha);
    }
  }
}

void TopDownImage::DrawLine(const Vec3& a, const Vec3& b, const Color& color) {
  const Pixel p = ToPixel(a), q = ToPixel(b);
  const int steps =
      std::max(1, static_cast<int>(std::ceil(std::max(std::abs(q.x - p.x), std::abs(q.y - p.y)))));
  for (int i = 0; i <= steps; ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(steps);
    Blend(static_cast<int>(p.x + t * (q.x - p.x)), static_cast<int>(p.y + t * (q.y - p.y)), color, 1.0f);
  }
}

void TopDownImage::DrawDot(const Vec3& center, int radius_pixels, const Color& color) {
  const Pixel p = ToPixel(center);
  for (int dy = -radius_pixels; dy <= radius_pixels; ++dy)
    for (int dx = -radius_pixels; dx <= radius_pixels; ++dx)
      if (dx * dx + dy * dy <= radius_pixels * radius_pixels)
        Blend(static_cast<int>(p.x) + dx, static_cast<int>(p.y) + dy, color, 1.0f);
}

Status TopDownImage::SavePng(const std::filesystem::path& path) const {
  // Encoded in memory, then written as every result file is (beside the target, renamed over it).
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &png, width_, height_, 3, rgb_.data(), width_ * 3))
    return MakeError(ErrorCode::kInvalidArgument, path.string() + ": cannot encode the PNG");
  return WriteOutputFile(path, png);
}

}  // namespace strata::demo
