// The display transform of PNG output (render/display.h): exposure in stops, the clamp
// curve, and the Khronos PBR Neutral curve's defining properties.
#include "render/display.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace lancer {
namespace {

TEST(Display, ClampIsTheIdentityInRangeAndExposureScalesByPowersOfTwo) {
  const DisplayTransform clamp;
  EXPECT_EQ(display_map({0.25f, 0.5f, 0.75f}, clamp), glm::vec3(0.25f, 0.5f, 0.75f));
  EXPECT_EQ(display_map({2.0f, -1.0f, std::nanf("")}, clamp), glm::vec3(1.0f, 0.0f, 0.0f));
  EXPECT_EQ(display_map({0.25f, 0.5f, 0.125f}, {1.0f, ToneCurve::Clamp}), glm::vec3(0.5f, 1.0f, 0.25f));
  EXPECT_EQ(display_map({0.25f, 0.5f, 0.125f}, {-2.0f, ToneCurve::Clamp}), glm::vec3(0.0625f, 0.125f, 0.03125f));
}

TEST(Display, NeutralKeepsMidtonesAndRollsOffHighlights) {
  const DisplayTransform neutral{0.0f, ToneCurve::Neutral};
  // Below the compression start, with the darkest channel at 0.08 or above, only the
  // 0.04 offset applies: hue and contrast as the material says.
  const glm::vec3 mid = display_map({0.5f, 0.3f, 0.1f}, neutral);
  EXPECT_NEAR(mid.r, 0.46f, 1e-6f);
  EXPECT_NEAR(mid.g, 0.26f, 1e-6f);
  EXPECT_NEAR(mid.b, 0.06f, 1e-6f);
  // Black stays black; the toe is continuous at 0.08 (0.08 - 6.25 0.08^2 = 0.04).
  EXPECT_EQ(display_map(glm::vec3(0.0f), neutral), glm::vec3(0.0f));
  EXPECT_NEAR(display_map(glm::vec3(0.07999f), neutral).r, display_map(glm::vec3(0.08001f), neutral).r, 1e-4f);
  EXPECT_NEAR(display_map(glm::vec3(0.08f), neutral).r, 0.04f, 1e-6f);
  // Highlights: monotone, below 1, approaching white; nothing blows out to a flat 1.
  float previous = 0.0f;
  for (float v = 0.5f; v < 1000.0f; v *= 1.5f) {
    const float out = display_map(glm::vec3(v), neutral).r;
    EXPECT_GT(out, previous) << v;
    EXPECT_LT(out, 1.0f) << v;
    previous = out;
  }
  EXPECT_GT(previous, 0.999f);
  // A saturated highlight desaturates towards white but keeps its order of channels.
  const glm::vec3 hot = display_map({8.0f, 2.0f, 0.5f}, neutral);
  EXPECT_GT(hot.r, hot.g);
  EXPECT_GT(hot.g, hot.b);
  EXPECT_GT(hot.b / hot.r, 0.5f / 8.0f);
  // Continuous at the compression start (peak 0.76 after the offset).
  EXPECT_NEAR(display_map(glm::vec3(0.7999f), neutral).r, display_map(glm::vec3(0.8001f), neutral).r, 1e-3f);
  // Infinite and NaN radiance give white and black, never NaN.
  EXPECT_EQ(display_map(glm::vec3(std::numeric_limits<float>::infinity()), neutral), glm::vec3(1.0f));
  EXPECT_EQ(display_map(glm::vec3(std::nanf("")), neutral), glm::vec3(0.0f));
}

TEST(Display, ParsesTheCurveNames) {
  ToneCurve c = ToneCurve::Clamp;
  EXPECT_TRUE(parse_tone_curve("neutral", c));
  EXPECT_EQ(c, ToneCurve::Neutral);
  EXPECT_TRUE(parse_tone_curve("clamp", c));
  EXPECT_EQ(c, ToneCurve::Clamp);
  EXPECT_FALSE(parse_tone_curve("filmic", c));
}

}  // namespace
}  // namespace lancer
