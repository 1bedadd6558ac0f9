#include "physics/body/GyroscopicTorque.h"

namespace strata {

namespace {
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

Vec3 SpinWithoutTorque(const Mat3& inertia, const Quat& rotation, const Vec3& angular_velocity, float dt) {
  const Vec3 start = rotation.conjugate() * angular_velocity;
  // Unknown: the midpoint spin m = (w0 + w1) / 2, with f(m) = 2 I (m - w0) + dt m x (I m) = 0.
  Vec3 middle = start;
  for (int iteration = 0; iteration < 3; ++iteration) {
    const Vec3 momentum = inertia * middle;
    const Vec3 residual = 2.0f * inertia * (middle - start) + dt * middle.cross(momentum);
    const Mat3 jacobian = 2.0f * inertia + dt * (CrossMatrix(middle) * inertia - CrossMatrix(momentum));
    middle -= jacobian.partialPivLu().solve(residual);
  }
  return rotation * (2.0f * middle - start);
}

}  // namespace strata
