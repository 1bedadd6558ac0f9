#include "physics/body/GyroscopicTorque.h"

#include <algorithm>
#include <cmath>

namespace strata {

namespace {
constexpr int kMaxNewtonIterations = 8;
constexpr float kMaxTurnPerStep = 0.5f;  // radians per midpoint step

Mat3 CrossMatrix(const Vec3& v) {
  Mat3 m;
  m << 0.0f, -v.z(), v.y(), v.z(), 0.0f, -v.x(), -v.y(), v.x(), 0.0f;
  return m;
}
}  // namespace

bool HasGyroscopicTorque(const Mat3& inertia) {
  const float mean = inertia.trace() / 3.0f;
  return (inertia - mean * Mat3::Identity()).norm() > 1e-5f * std::abs(mean);
}

namespace {
// One implicit midpoint step of the body-frame spin. The unknown is the midpoint spin m = (w0 + w1) / 2 with
// f(m) = 2 I (m - w0) + h m x (I m) = 0, solved by Newton from m = w0 (converges fast while h |w| is small;
// the caller keeps it below kMaxTurnPerStep).
Vec3 MidpointStep(const Mat3& inertia, const Vec3& start, float h) {
  Vec3 middle = start;
  for (int iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    const Vec3 momentum = inertia * middle;
    const Vec3 residual = 2.0f * inertia * (middle - start) + h * middle.cross(momentum);
    const Mat3 jacobian = 2.0f * inertia + h * (CrossMatrix(middle) * inertia - CrossMatrix(momentum));
    const Vec3 change = jacobian.inverse() * residual;  // closed-form 3x3 inverse
    middle -= change;
    if (change.squaredNorm() <= 1e-12f * start.squaredNorm()) break;
  }
  return 2.0f * middle - start;
}
}  // namespace

Vec3 SpinWithoutTorque(const Mat3& inertia, const Quat& rotation, const Vec3& angular_velocity, float dt) {
  Vec3 spin = rotation.conjugate() * angular_velocity;
  // Fast spin is split into pieces of at most kMaxTurnPerStep radians, where Newton converges.
  const int pieces = std::max(1, static_cast<int>(std::ceil(spin.norm() * dt / kMaxTurnPerStep)));
  const float h = dt / static_cast<float>(pieces);
  for (int piece = 0; piece < pieces; ++piece) spin = MidpointStep(inertia, spin, h);
  return rotation * spin;
}

}  // namespace strata
