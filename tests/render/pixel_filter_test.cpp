// Pixel filters sampled by importance: the box's uniform jitter, the truncated Gaussian's
// exact inverse CDF (its mean, variance and support), and erf_inverse.
#include "render/pixel_filter.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "simd/splitmix64.h"

namespace lancer {
namespace {

TEST(PixelFilter, BoxOffsetsAreTheUniformJitter) {
  const PixelFilter box = PixelFilter::box();
  EXPECT_EQ(box.type(), PixelFilterType::Box);
  EXPECT_EQ(box.sample_offset({0.0f, 0.0f}), glm::vec2(-0.5f, -0.5f));
  const glm::vec2 top = box.sample_offset({1.0f - 0x1p-24f, 0.75f});
  EXPECT_LT(top.x, 0.5f);
  EXPECT_EQ(top.y, 0.25f);
  // Every 24-bit u at a stride, exactly u - 1/2, inside [-0.5, 0.5).
  for (std::uint32_t bits = 0; bits < (1u << 24); bits += 4099) {
    const float u = static_cast<float>(bits) * 0x1p-24f;
    const glm::vec2 o = box.sample_offset({u, 1.0f - u - 0x1p-24f});
    ASSERT_EQ(static_cast<double>(o.x), static_cast<double>(u) - 0.5) << u;
    ASSERT_TRUE(o.y >= -0.5f && o.y < 0.5f) << o.y;
  }
  // Random u: a uniform distribution on the square (mean 0, variance 1/12, even cells).
  SplitMix64 rng(3);
  constexpr int kN = 200000;
  double mean = 0, var = 0;
  std::vector<double> cells(16, 0.0);
  for (int i = 0; i < kN; ++i) {
    const glm::vec2 o = box.sample_offset({rng.uniform(), rng.uniform()});
    mean += o.x;
    var += double(o.y) * o.y;
    cells[static_cast<std::size_t>((o.x + 0.5f) * 4) * 4 + static_cast<std::size_t>((o.y + 0.5f) * 4)] += 1;
  }
  EXPECT_NEAR(mean / kN, 0.0, 5 * std::sqrt(1.0 / 12 / kN));
  EXPECT_NEAR(var / kN, 1.0 / 12, 5 * std::sqrt(1.0 / 180 / kN));
  for (double c : cells) EXPECT_NEAR(c, kN / 16.0, 5 * std::sqrt(kN / 16.0));
}

TEST(PixelFilter, ErfInverseInvertsErf) {
  EXPECT_EQ(erf_inverse(0.0), 0.0);
  for (double y = -0.999999; y < 1.0; y += 0.0123457) {
    const double x = erf_inverse(y);
    EXPECT_NEAR(std::erf(x), y, 1e-15) << y;
    EXPECT_EQ(erf_inverse(-y), -x) << "odd function";
  }
  for (double y : {1e-12, 0.5, 0.9, 0.99, 0.9999, 0.99999999}) EXPECT_NEAR(std::erf(erf_inverse(y)), y, 1e-15) << y;
  EXPECT_NEAR(erf_inverse(0.5), 0.4769362762044699, 1e-15);  // a tabulated value
  EXPECT_TRUE(std::isinf(erf_inverse(1.0)));
  EXPECT_TRUE(std::isnan(erf_inverse(NAN)));
}

// Moments of a normal (mean 0, sd sigma) truncated to [-r, r]:
//   Var = sigma^2 (1 - 2 a phi(a) / (2 Phi(a) - 1)),  a = r / sigma,
// with phi, Phi the standard normal density and distribution.
double truncated_variance(double sigma, double r) {
  const double a = r / sigma;
  const double phi = std::exp(-0.5 * a * a) / std::sqrt(2 * std::numbers::pi);
  const double mass = std::erf(a / std::numbers::sqrt2);  // 2 Phi(a) - 1
  return sigma * sigma * (1.0 - 2.0 * a * phi / mass);
}

void check_gaussian(float sigma, float radius) {
  const PixelFilter g = PixelFilter::gaussian(sigma, radius);
  EXPECT_EQ(g.type(), PixelFilterType::Gaussian);
  EXPECT_EQ(g.radius(), radius);
  const double want_var = truncated_variance(sigma, radius);

  // The inverse CDF over a fine midpoint grid of u: its mean and second moment are the
  // distribution's (to the grid's O(1/N^2) error); it is monotone, inside the support, and
  // really the inverse of the truncated normal's CDF.
  constexpr int kN = 200000;
  double mean = 0, second = 0;
  float previous = -radius;
  const double bound = std::erf(radius / (sigma * std::numbers::sqrt2));
  for (int i = 0; i < kN; ++i) {
    const float u = static_cast<float>((i + 0.5) / kN);
    const float x = g.sample_offset({u, 0.5f}).x;
    ASSERT_TRUE(x >= -radius && x <= radius) << x;
    ASSERT_GE(x, previous) << "monotone at u = " << u;
    previous = x;
    const double cdf = 0.5 * (1.0 + std::erf(x / (sigma * std::numbers::sqrt2)) / bound);
    ASSERT_NEAR(cdf, u, 2e-7) << "F(x(u)) = u at u = " << u;
    mean += x;
    second += double(x) * x;
  }
  EXPECT_NEAR(mean / kN, 0.0, 1e-6);
  EXPECT_NEAR(second / kN, want_var, 1e-5 * want_var) << "truncated variance " << want_var;
  EXPECT_NEAR(g.sample_offset({0.0f, 0.5f}).x, -radius, 1e-6f);
  EXPECT_EQ(g.sample_offset({0.5f, 0.5f}), glm::vec2(0.0f));

  // Random u in both axes: the sample moments agree within their standard errors, and
  // the axes are independent.
  SplitMix64 rng(17);
  constexpr int kR = 200000;
  double mx = 0, my = 0, vx = 0, vy = 0, xy = 0;
  for (int i = 0; i < kR; ++i) {
    const glm::vec2 o = g.sample_offset({rng.uniform(), rng.uniform()});
    ASSERT_TRUE(std::abs(o.x) <= radius && std::abs(o.y) <= radius);
    mx += o.x;
    my += o.y;
    vx += double(o.x) * o.x;
    vy += double(o.y) * o.y;
    xy += double(o.x) * o.y;
  }
  const double se_mean = std::sqrt(want_var / kR), se_var = want_var * std::sqrt(2.0 / kR) * 1.5;
  EXPECT_NEAR(mx / kR, 0.0, 5 * se_mean);
  EXPECT_NEAR(my / kR, 0.0, 5 * se_mean);
  EXPECT_NEAR(vx / kR, want_var, 5 * se_var);
  EXPECT_NEAR(vy / kR, want_var, 5 * se_var);
  EXPECT_NEAR(xy / kR, 0.0, 5 * want_var / std::sqrt(double(kR)));
}

TEST(PixelFilter, GaussianDefaultIsSigmaHalfRadiusOneAndAHalf) {
  const PixelFilter g = PixelFilter::gaussian();
  EXPECT_EQ(g.sigma(), 0.5f);
  EXPECT_EQ(g.radius(), 1.5f);
  // Truncation at three sigma removes 0.27 % of the mass and shrinks the variance by 2.9 %.
  EXPECT_NEAR(truncated_variance(0.5, 1.5), 0.25 * (1 - 6 * std::exp(-4.5) / std::sqrt(2 * std::numbers::pi) / 0.9973002),
              1e-7);
  check_gaussian(0.5f, 1.5f);
}

TEST(PixelFilter, GaussianOtherWidths) {
  check_gaussian(1.0f, 2.0f);    // truncated at two sigma: a clearly smaller variance
  check_gaussian(0.3f, 0.5f);
}

TEST(PixelFilter, GaussianRejectsBadParameters) {
  EXPECT_THROW(PixelFilter::gaussian(0.0f, 1.5f), std::invalid_argument);
  EXPECT_THROW(PixelFilter::gaussian(-0.5f, 1.5f), std::invalid_argument);
  EXPECT_THROW(PixelFilter::gaussian(0.5f, 0.0f), std::invalid_argument);
  EXPECT_THROW(PixelFilter::gaussian(NAN, 1.5f), std::invalid_argument);
  EXPECT_THROW(PixelFilter::gaussian(0.5f, INFINITY), std::invalid_argument);
}

}  // namespace
}  // namespace lancer
