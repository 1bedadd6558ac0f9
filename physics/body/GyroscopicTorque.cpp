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
// f(m) = 2 I (m - w0) + h m x (I m) = 0, solved by Newton (converges fast while h |w| is small; the caller
// keeps it below kMaxTurnPerStep). It starts from the explicit midpoint, already within O(h^2), which saves
// about one iteration.
Vec3 MidpointStep(const Mat3& inertia, const Vec3& start, float h) {
  const Vec3 start_momentum = inertia * start;
  Vec3 middle = start - (0.5f * h) * (inertia.inverse() * start.cross(start_momentum));
  for (int iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    const Vec3 momentum = inertia * middle;
    const Vec3 residual = 2.0f * (momentum - start_momentum) + h * middle.cross(momentum);
    const Mat3 jacobian = 2.0f * inertia + h * (CrossMatrix(middle) * inertia - CrossMatrix(momentum));
    const Vec3 change = jacobian.inverse() * residual;  // closed-form 3x3 inverse
    middle -= change;
    if (change.squaredNorm() <= 1e-12f * start.squaredNorm()) break;
  }
  return 2.0f * middle - start;
}

// The same step for a diagonal inertia (every primitive shape in its principal frame), with the products
// by the inertia written out: about a third fewer operations.
Vec3 DiagonalMidpointStep(const Vec3& inertia, const Vec3& start, float h) {
  const Vec3 start_momentum = inertia.cwiseProduct(start);
  Vec3 middle = start - (0.5f * h) * start.cross(start_momentum).cwiseQuotient(inertia);
  for (int iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    const Vec3 m = middle;
    const Vec3 p = inertia.cwiseProduct(m);
    const Vec3 residual = 2.0f * (p - start_momentum) + h * m.cross(p);
    // 2 I + h ([m]x I - [I m]x), entry by entry.
    Mat3 jacobian;
    jacobian << 2.0f * inertia.x(), h * (p.z() - m.z() * inertia.y()), h * (m.y() * inertia.z() - p.y()),
        h * (m.z() * inertia.x() - p.z()), 2.0f * inertia.y(), h * (p.x() - m.x() * inertia.z()),
        h * (p.y() - m.y() * inertia.x()), h * (m.x() * inertia.y() - p.x()), 2.0f * inertia.z();
    const Vec3 change = jacobian.inverse() * residual;
    middle -= change;
    if (change.squaredNorm() <= 1e-12f * start.squaredNorm()) break;
  }
  return 2.0f * middle - start;
}

// The same step for a diagonal inertia with two equal moments (a capsule, a cylinder, a box with two equal
// sides), in closed form. The spin about the odd axis k is constant, and the rest of it obeys a linear
// equation, so the midpoint rule's answer is the Cayley rotation of that part by the precession rate
// W = (I_k - I_other) / I_other * w_k: by the angle 2 atan(W h / 2), exactly what Newton converges to.
Vec3 SymmetricMidpointStep(const Vec3& inertia, int k, const Vec3& start, float h) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;  // (i, j, k) right-handed
  const float precession = (inertia[k] - inertia[i]) / inertia[i] * start[k];
  const float t = 0.5f * h * precession;
  const float scale = 1.0f / (1.0f + t * t);
  const float cosine = (1.0f - t * t) * scale, sine = 2.0f * t * scale;
  Vec3 spin = start;
  spin[i] = cosine * start[i] - sine * start[j];
  spin[j] = sine * start[i] + cosine * start[j];
  return spin;
}

// The axis whose moment differs from the two equal others, or -1 when no two are equal.
int SymmetryAxis(const Vec3& inertia) {
  if (inertia.x() == inertia.y()) return 2;
  if (inertia.y() == inertia.z()) return 0;
  if (inertia.z() == inertia.x()) return 1;
  return -1;
}

bool IsDiagonal(const Mat3& m) {
  return m(0, 1) == 0.0f && m(0, 2) == 0.0f && m(1, 0) == 0.0f && m(1, 2) == 0.0f && m(2, 0) == 0.0f &&
         m(2, 1) == 0.0f;
}
}  // namespace

int SpinPieces(float spin_speed, float dt) {
  // Pieces of at most kMaxTurnPerStep radians, where Newton converges. NaN fails the comparison.
  const float turns = spin_speed * dt / kMaxTurnPerStep;
  return turns < static_cast<float>(kMaxSpinPieces) ? std::max(1, static_cast<int>(std::ceil(turns)))
                                                    : kMaxSpinPieces;
}

Vec3 SpinWithoutTorque(const Mat3& inertia, const Quat& rotation, const Vec3& angular_velocity, float dt) {
  Vec3 spin = rotation.conjugate() * angular_velocity;
  const int pieces = SpinPieces(spin.norm(), dt);
  const float h = dt / static_cast<float>(pieces);
  if (IsDiagonal(inertia)) {
    const Vec3 diagonal = inertia.diagonal();
    const int axis = SymmetryAxis(diagonal);
    if (axis >= 0)
      for (int piece = 0; piece < pieces; ++piece) spin = SymmetricMidpointStep(diagonal, axis, spin, h);
    else
      for (int piece = 0; piece < pieces; ++piece) spin = DiagonalMidpointStep(diagonal, spin, h);
  } else {
    for (int piece = 0; piece < pieces; ++piece) spin = MidpointStep(inertia, spin, h);
  }
  return rotation * spin;
}

}  // namespace strata
