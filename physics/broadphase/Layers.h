// Layers: object layers (what a body is: static level, moving, debris, sensor, ...) map onto a few
// broad-phase layers (which tree holds it), and a pair filter says which object layers collide.
// The defaults here never test static against static. Filters are immutable; safe from any thread.
#pragma once

#include <cstdint>

namespace strata {

using ObjectLayer = std::uint16_t;
using BroadPhaseLayer = std::uint8_t;

/// The two layers every world has; games add their own after these.
namespace layers {
inline constexpr ObjectLayer kNonMoving = 0;
inline constexpr ObjectLayer kMoving = 1;
inline constexpr BroadPhaseLayer kBroadPhaseNonMoving = 0;
inline constexpr BroadPhaseLayer kBroadPhaseMoving = 1;
}  // namespace layers

/// Maps object layers to broad-phase layers and decides which object layer pairs collide.
class LayerSetup {
 public:
  virtual ~LayerSetup() = default;
  /// Number of object layers; a body with a layer at or above it is rejected.
  virtual ObjectLayer ObjectLayerCount() const = 0;
  virtual BroadPhaseLayer BroadPhaseLayerCount() const = 0;
  virtual BroadPhaseLayer ToBroadPhaseLayer(ObjectLayer layer) const = 0;
  virtual bool ShouldCollide(ObjectLayer a, ObjectLayer b) const = 0;
};

/// Two layers: non-moving (static level) and moving; non-moving never collides with non-moving.
class DefaultLayerSetup final : public LayerSetup {
 public:
  ObjectLayer ObjectLayerCount() const override { return 2; }
  BroadPhaseLayer BroadPhaseLayerCount() const override { return 2; }
  BroadPhaseLayer ToBroadPhaseLayer(ObjectLayer layer) const override {
    return layer == layers::kNonMoving ? layers::kBroadPhaseNonMoving : layers::kBroadPhaseMoving;
  }
  bool ShouldCollide(ObjectLayer a, ObjectLayer b) const override {
    return !(a == layers::kNonMoving && b == layers::kNonMoving);
  }
};

/// Which bodies a query reports: a bit per object layer (layers >= 64 always pass) and one body to skip.
/// World queries leave sensors (trigger volumes) out unless `sensors` is set; the broad phase does not know
/// which bodies are sensors.
struct QueryFilter {
  std::uint64_t object_layers = ~0ull;
  std::uint32_t ignore_body_index = 0xffffffffu;
  bool sensors = false;

  bool AcceptsLayer(ObjectLayer layer) const { return layer >= 64 || (object_layers >> layer) & 1u; }
  /// A filter that only passes the listed layer.
  static QueryFilter OnlyLayer(ObjectLayer layer) { return {1ull << layer, 0xffffffffu, false}; }
};

}  // namespace strata
