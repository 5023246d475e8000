// sRGB transfer functions against published values of IEC 61966-2-1 and against a
// double-precision evaluation of the standard's formulas.
#include "render/color.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

namespace lancer {
namespace {

// The standard's curves in double precision: the oracle for rounding decisions.
double reference_srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

TEST(Srgb, KnownDecodedValues) {
  EXPECT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_NEAR(srgb_to_linear(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404114f, 1e-6f);
  EXPECT_NEAR(srgb8_to_linear(128), 0.21586050f, 1e-6f);
  EXPECT_NEAR(srgb8_to_linear(1), 0.00030352698f, 1e-9f);   // linear segment
  EXPECT_NEAR(srgb8_to_linear(10), 0.0030352698f, 1e-9f);   // last code on the linear segment
  EXPECT_NEAR(srgb8_to_linear(11), 0.0033465358f, 1e-8f);   // first code on the power segment
  EXPECT_EQ(srgb8_to_linear(0), 0.0f);
  EXPECT_NEAR(srgb8_to_linear(255), 1.0f, 1e-6f);
}

TEST(Srgb, KnownEncodedValues) {
  EXPECT_EQ(linear_to_srgb8(0.0f), 0);
  EXPECT_EQ(linear_to_srgb8(1.0f), 255);
  EXPECT_EQ(linear_to_srgb8(0.5f), 188);  // a pure gamma 2.2 would give 186
  EXPECT_EQ(linear_to_srgb8(0.18f), 118);
  EXPECT_EQ(linear_to_srgb8(0.2f), 124);
  EXPECT_EQ(linear_to_srgb8(0.0031308f), 10);  // 12.92 * 0.0031308 * 255 = 10.31
  EXPECT_EQ(linear_to_srgb8(0.001f), 3);       // linear segment; gamma 2.2 would give 11
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.73535698f, 1e-6f);
  EXPECT_NEAR(linear_to_srgb(0.001f), 0.01292f, 1e-7f);
}

TEST(Srgb, SegmentsMeetAtTheBoundary) {
  const float below = 0.0031308f;
  const float above = std::nextafter(below, 1.0f);
  EXPECT_NEAR(linear_to_srgb(below), 0.04045f, 1e-6f);
  EXPECT_NEAR(linear_to_srgb(above), 0.04045f, 1e-6f);
  EXPECT_NEAR(srgb_to_linear(0.04045f), 0.0031308f, 1e-8f);
  EXPECT_NEAR(srgb_to_linear(std::nextafter(0.04045f, 1.0f)), 0.0031308f, 1e-8f);
}

TEST(Srgb, EncodeAndDecodeAreInverse) {
  for (int i = 0; i <= 1000; ++i) {
    const float x = static_cast<float>(i) / 1000.0f;
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(x)), x, 2e-6f + 2e-6f * x) << "x = " << x;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(x)), x, 2e-6f + 2e-6f * x) << "x = " << x;
  }
}

TEST(Srgb, EveryCodeSurvivesDecodeAndEncode) {
  for (int code = 0; code < 256; ++code) {
    const auto c = static_cast<std::uint8_t>(code);
    EXPECT_EQ(linear_to_srgb8(srgb8_to_linear(c)), c) << "code " << code;
    const double exact = reference_srgb_to_linear(code / 255.0);
    EXPECT_NEAR(srgb8_to_linear(c), exact, 0x1p-24 * exact) << "code " << code;  // correctly rounded float
  }
}

// Rounds to nearest: just below the linear value whose encoding is (i + 0.5) / 255 we
// must get code i, just above it code i + 1.
TEST(Srgb, EightBitEncoderRoundsToNearest) {
  for (int code = 0; code < 255; ++code) {
    const double threshold = reference_srgb_to_linear((code + 0.5) / 255.0);
    EXPECT_EQ(linear_to_srgb8(static_cast<float>(threshold * (1.0 - 1e-4))), code) << "code " << code;
    EXPECT_EQ(linear_to_srgb8(static_cast<float>(threshold * (1.0 + 1e-4))), code + 1) << "code " << code;
  }
}

TEST(Srgb, EightBitEncoderClampsAndHandlesNonFinite) {
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(linear_to_srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(linear_to_srgb8(-std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(linear_to_srgb8(inf), 255);
  EXPECT_EQ(linear_to_srgb8(-inf), 0);
  EXPECT_EQ(linear_to_srgb8(-0.5f), 0);
  EXPECT_EQ(linear_to_srgb8(-0.0f), 0);
  EXPECT_EQ(linear_to_srgb8(1.5f), 255);
  EXPECT_EQ(linear_to_srgb8(std::nextafter(1.0f, 0.0f)), 255);
  EXPECT_EQ(linear_to_srgb8(std::numeric_limits<float>::denorm_min()), 0);
}

TEST(Srgb, EightBitEncoderIsMonotonic) {
  int previous = 0;
  for (int i = 0; i <= 100000; ++i) {
    const int code = linear_to_srgb8(static_cast<float>(i) / 100000.0f);
    ASSERT_GE(code, previous) << "at " << i;
    ASSERT_LE(code - previous, 1) << "skipped a code at " << i;
    previous = code;
  }
  EXPECT_EQ(previous, 255);
}

TEST(Luminance, Rec709Weights) {
  EXPECT_NEAR(luminance({1.0f, 1.0f, 1.0f}), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(luminance({1.0f, 0.0f, 0.0f}), 0.2126f);
  EXPECT_FLOAT_EQ(luminance({0.0f, 1.0f, 0.0f}), 0.7152f);
  EXPECT_FLOAT_EQ(luminance({0.0f, 0.0f, 1.0f}), 0.0722f);
  EXPECT_FLOAT_EQ(luminance({2.0f, 4.0f, 8.0f}), 2.0f * 0.2126f + 4.0f * 0.7152f + 8.0f * 0.0722f);
}

}  // namespace
}  // namespace lancer
