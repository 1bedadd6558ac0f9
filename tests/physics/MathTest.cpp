// The engine's own math helpers against the standard library.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/math/Math.h"

namespace strata::test {
namespace {

TEST(Math, FastAtan2IsWithinTenMicroradiansOfAtan2InEveryOctantAndScale) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> turn(-M_PI, M_PI), log_scale(-20.0, 20.0);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double angle = turn(random), length = std::exp(log_scale(random));
    const auto y = static_cast<float>(length * std::sin(angle)),
               x = static_cast<float>(length * std::cos(angle));
    const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x));
    worst = std::max(worst, std::abs(FastAtan2(y, x) - exact));
  }
  EXPECT_LT(worst, 1e-5);
  // The axes and the origin exactly.
  EXPECT_EQ(FastAtan2(0.0f, 1.0f), 0.0f);
  EXPECT_FLOAT_EQ(FastAtan2(1.0f, 0.0f), 0.5f * kPi);
  EXPECT_FLOAT_EQ(FastAtan2(-2.0f, 0.0f), -0.5f * kPi);
  EXPECT_FLOAT_EQ(FastAtan2(0.0f, -3.0f), kPi);
  EXPECT_EQ(FastAtan2(0.0f, 0.0f), 0.0f);
}

}  // namespace
}  // namespace strata::test
