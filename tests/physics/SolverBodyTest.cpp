// The solver's 4-wide helpers (SolverBody.h) give, to the bit, what the 3-wide Eigen expressions they replace
// gave: the step's results must not move when they are taken a register at a time.
#include "physics/body/SolverBody.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace strata::test {
namespace {

bool SameBits(const Vec4& a, const Vec4& b) {
  return std::memcmp(a.data(), b.data(), sizeof(float) * 4) == 0;
}

// x, y and z the same to the bit, w zero (a product of the zero w lane with a negative entry is -0).
bool SameLanes(const Vec4& a, const Vec4& b) {
  return std::memcmp(a.data(), b.data(), sizeof(float) * 3) == 0 && a.w() == 0.0f && b.w() == 0.0f;
}

Vec3 RandomVector(std::mt19937& random, float scale) {
  std::uniform_real_distribution<float> coordinate(-scale, scale);
  return {coordinate(random), coordinate(random), coordinate(random)};
}

Quat RandomRotation(std::mt19937& random) {
  std::normal_distribution<float> coordinate(0.0f, 1.0f);
  return Quat(coordinate(random), coordinate(random), coordinate(random), coordinate(random)).normalized();
}

TEST(SolverBody, ToVec4KeepsTheLanesAndZeroesW) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 v = RandomVector(random, 1e3f);
    const Vec4 wide = ToVec4(v);
    EXPECT_TRUE(SameBits(wide, Vec4(v.x(), v.y(), v.z(), 0.0f)));
    EXPECT_EQ(ToVec3(wide), v);
  }
}

TEST(SolverBody, CrossIsTheScalarCrossProductToTheBit) {
  std::mt19937 random(12);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 a = RandomVector(random, 10.0f), b = RandomVector(random, 10.0f);
    const Vec4 expected = ToVec4(a.cross(b));
    EXPECT_TRUE(SameBits(Cross(ToVec4(a), ToVec4(b)), expected)) << "trial " << trial;
  }
}

TEST(SolverBody, InverseInertiaColumnsAreTheRotatedInverseInertiaToTheBit) {
  std::mt19937 random(13);
  for (int trial = 0; trial < 1000; ++trial) {
    const Mat3 rotation = RandomRotation(random).toRotationMatrix();
    // Diagonal (boxes, spheres) and full (hulls off their principal axes) inverse inertias.
    Mat3 inverse_local = Mat3::Zero();
    if (trial % 2 == 0) {
      inverse_local.diagonal() = RandomVector(random, 5.0f).cwiseAbs();
    } else {
      const Mat3 turn = RandomRotation(random).toRotationMatrix();
      inverse_local = turn * Vec3(RandomVector(random, 5.0f).cwiseAbs()).asDiagonal() * turn.transpose();
    }
    const Mat3 world = rotation * inverse_local * rotation.transpose();
    Vec4 columns[3];
    InverseInertiaColumns(rotation, inverse_local, columns);
    for (int j = 0; j < 3; ++j)
      EXPECT_TRUE(SameLanes(columns[j], ToVec4(world.col(j)))) << "trial " << trial << " column " << j;
    const Vec3 torque = RandomVector(random, 100.0f);
    EXPECT_TRUE(SameLanes(ColumnsTimes(columns, torque), ToVec4(world * torque))) << "trial " << trial;
  }
}

TEST(SolverBody, TurnByIsTheFirstOrderQuaternionStepToTheBit) {
  std::mt19937 random(14);
  for (int trial = 0; trial < 1000; ++trial) {
    const Quat start = RandomRotation(random);
    const Vec3 turn = RandomVector(random, 0.5f);
    // What integration did before: a half-turn quaternion from four scalars.
    Quat expected = start;
    const Quat half_turn(0.0f, 0.5f * turn.x(), 0.5f * turn.y(), 0.5f * turn.z());
    expected.coeffs() += (half_turn * expected).coeffs();
    expected.normalize();
    Quat turned = start;
    TurnBy(turned, ToVec4(turn));
    EXPECT_TRUE(SameBits(turned.coeffs(), expected.coeffs())) << "trial " << trial;
  }
}

}  // namespace
}  // namespace strata::test
