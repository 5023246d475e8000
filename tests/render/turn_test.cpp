#include "render/turn.h"

#include <cmath>
#include <cstdint>
#include <numbers>

#include <gtest/gtest.h>

namespace lancer {
namespace {

// Every 24-bit sample value a sampler can give (k / 2^24), in steps, against the double
// cosine and sine: within 2 float ulps of 1 everywhere (the values are at most 1 in size).
TEST(TurnCosSin, WithinTwoUlpsOfOneOverTheSamplersRange) {
  double worst = 0.0;
  for (std::uint32_t k = 0; k < (1u << 24); k += 97) {
    const float u = static_cast<float>(k) * 0x1p-24f;
    const glm::vec2 cs = turn_cos_sin(u);
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(u);
    worst = std::max(worst, std::abs(cs.x - std::cos(angle)));
    worst = std::max(worst, std::abs(cs.y - std::sin(angle)));
  }
  EXPECT_LE(worst, 2.0 * 0x1p-24);
  EXPECT_GT(worst, 0.0);  // the comparison did compare something rounded
}

// Quarter turns are exact, and the quadrant is right on either side of each boundary.
TEST(TurnCosSin, ExactAtQuarterTurnsAndRightQuadrantAround) {
  const float quarter[5][3] = {{0.0f, 1.0f, 0.0f}, {0.25f, 0.0f, 1.0f}, {0.5f, -1.0f, 0.0f},
                               {0.75f, 0.0f, -1.0f}, {1.0f, 1.0f, 0.0f}};
  for (const auto& q : quarter) {
    const glm::vec2 cs = turn_cos_sin(q[0]);
    EXPECT_EQ(cs.x, q[1]) << "u = " << q[0];
    EXPECT_EQ(cs.y, q[2]) << "u = " << q[0];
  }
  for (float u : {0.125f, 0.375f, 0.625f, 0.875f, 0.12499999f, 0.37500003f, 0.6249999f, 0.87500006f}) {
    const glm::vec2 cs = turn_cos_sin(u);
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(u);
    EXPECT_NEAR(cs.x, std::cos(angle), 2.0 * 0x1p-24) << "u = " << u;
    EXPECT_NEAR(cs.y, std::sin(angle), 2.0 * 0x1p-24) << "u = " << u;
  }
}

// The largest value below 1 and negative turns (a lens maps to [-1/8, 3/8]).
TEST(TurnCosSin, EdgesOfTheDomain) {
  for (float u : {0.99999994f, -0.125f, -0.05f, 1e-30f, -1e-30f}) {
    const glm::vec2 cs = turn_cos_sin(u);
    const double angle = 2.0 * std::numbers::pi * static_cast<double>(u);
    EXPECT_NEAR(cs.x, std::cos(angle), 2.0 * 0x1p-24) << "u = " << u;
    EXPECT_NEAR(cs.y, std::sin(angle), 2.0 * 0x1p-24) << "u = " << u;
  }
}

}  // namespace
}  // namespace lancer
