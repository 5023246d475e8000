// Piecewise-constant distributions: inversion lands in the right bin with the right
// density, zero bins are never drawn, all-zero weights fall back to uniform, bad weights
// are refused.
#include "render/piecewise_constant.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "simd/splitmix64.h"

namespace lancer {
namespace {

TEST(PiecewiseConstant, OneDimensionalInversion) {
  const std::vector<float> w = {1.0f, 0.0f, 3.0f, 4.0f};
  const Distribution1D d(w);
  EXPECT_EQ(d.size(), 4u);
  EXPECT_DOUBLE_EQ(d.mean_weight(), 2.0);
  EXPECT_FLOAT_EQ(d.pdf(0), 0.5f);  // 4 * 1/8
  EXPECT_EQ(d.pdf(1), 0.0f);
  EXPECT_FLOAT_EQ(d.pdf(2), 1.5f);
  EXPECT_FLOAT_EQ(d.pdf(3), 2.0f);
  EXPECT_EQ(d.pdf(4), 0.0f) << "out of range";
  // CDF 0, 1/8, 1/8, 1/2, 1: u = 1/16 is halfway through bin 0, u = 0.75 halfway through bin 3.
  Distribution1D::Sample s = d.sample(1.0f / 16);
  EXPECT_EQ(s.bin, 0u);
  EXPECT_FLOAT_EQ(s.x, 0.125f);
  EXPECT_FLOAT_EQ(s.pdf, 0.5f);
  s = d.sample(0.125f);  // exactly the CDF step at the empty bin: skips it
  EXPECT_EQ(s.bin, 2u);
  EXPECT_FLOAT_EQ(s.x, 0.5f);
  s = d.sample(0.75f);
  EXPECT_EQ(s.bin, 3u);
  EXPECT_FLOAT_EQ(s.x, 0.875f);
  s = d.sample(1.0f - 0x1p-24f);
  EXPECT_EQ(s.bin, 3u);
  EXPECT_LT(s.x, 1.0f);

  SplitMix64 rng(1);
  std::vector<double> count(4, 0.0);
  constexpr int kN = 100000;
  for (int i = 0; i < kN; ++i) {
    const Distribution1D::Sample r = d.sample(rng.uniform());
    ASSERT_EQ(r.bin, static_cast<std::size_t>(r.x * 4.0f));
    ASSERT_EQ(r.pdf, d.pdf(r.bin));
    count[r.bin] += 1;
  }
  EXPECT_EQ(count[1], 0.0);
  for (std::size_t b : {0u, 2u, 3u}) {
    const double p = w[b] / 8.0;
    EXPECT_NEAR(count[b] / kN, p, 5 * std::sqrt(p * (1 - p) / kN)) << b;
  }
}

TEST(PiecewiseConstant, AllZeroIsUniformAndBadWeightsAreRefused) {
  const Distribution1D zero(std::vector<float>(5, 0.0f));
  for (std::size_t b = 0; b < 5; ++b) EXPECT_FLOAT_EQ(zero.pdf(b), 1.0f);
  EXPECT_EQ(zero.sample(0.5f).bin, 2u);
  EXPECT_THROW(Distribution1D(std::vector<float>{}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{1.0f, -1.0f}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{1.0f, NAN}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{INFINITY}), std::invalid_argument);
  EXPECT_THROW(Distribution2D(std::vector<float>(6, 1.0f), 4, 2), std::invalid_argument);
  EXPECT_THROW(Distribution2D(std::vector<float>(6, 1.0f), 0, 6), std::invalid_argument);
}

TEST(PiecewiseConstant, TwoDimensionalDensity) {
  // 3 x 2 grid, one empty row.
  const std::vector<float> w = {1, 2, 3, 0, 0, 0};
  const Distribution2D d(w, 3, 2);
  EXPECT_EQ(d.width(), 3u);
  EXPECT_EQ(d.height(), 2u);
  double total = 0;
  for (std::size_t r = 0; r < 2; ++r)
    for (std::size_t c = 0; c < 3; ++c) total += d.pdf(c, r) / 6.0;
  EXPECT_NEAR(total, 1.0, 1e-6);
  EXPECT_FLOAT_EQ(d.pdf(2, 0), 3.0f / 6.0f * 6.0f);  // probability 1/2 over a cell of area 1/6
  EXPECT_EQ(d.pdf(1, 1), 0.0f);
  SplitMix64 rng(8);
  for (int i = 0; i < 10000; ++i) {
    const Distribution2D::Sample s = d.sample({rng.uniform(), rng.uniform()});
    ASSERT_EQ(s.row, 0u);
    ASSERT_EQ(s.column, static_cast<std::size_t>(s.p.x * 3.0f));
    ASSERT_EQ(s.row, static_cast<std::size_t>(s.p.y * 2.0f));
    ASSERT_EQ(s.pdf, d.pdf(s.column, s.row));
  }
}

}  // namespace
}  // namespace lancer
