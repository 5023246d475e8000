// The counter-based sampler: deterministic, in [0, 1), uniform, and keyed by all inputs.
#include "render/sampler.h"

#include <array>
#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace lancer {
namespace {

TEST(Sampler, SameKeyGivesSameValues) {
  PixelSampler a(3, 7, 2, 42), b(3, 7, 2, 42);
  for (int d = 0; d < 100; ++d) EXPECT_EQ(a.next(), b.next());
}

TEST(Sampler, GetMatchesNext) {
  PixelSampler s(5, 9, 1, 7);
  const PixelSampler fixed = s;
  for (std::uint32_t d = 0; d < 20; ++d) {
    EXPECT_EQ(s.dimension(), d);
    EXPECT_EQ(s.next(), fixed.get(d));
  }
}

TEST(Sampler, EveryKeyComponentChangesTheStream) {
  const float base = PixelSampler(3, 7, 2, 42).get(0);
  EXPECT_NE(PixelSampler(4, 7, 2, 42).get(0), base);
  EXPECT_NE(PixelSampler(3, 8, 2, 42).get(0), base);
  EXPECT_NE(PixelSampler(7, 3, 2, 42).get(0), base);  // x and y are not interchangeable
  EXPECT_NE(PixelSampler(3, 7, 3, 42).get(0), base);
  EXPECT_NE(PixelSampler(3, 7, 2, 43).get(0), base);
  EXPECT_NE(PixelSampler(3, 7, 2, 42).get(1), base);
}

TEST(Sampler, ValuesAreDistinctAcrossManyKeys) {
  std::set<float> seen;
  for (std::uint32_t x = 0; x < 64; ++x)
    for (std::uint32_t s = 0; s < 16; ++s) seen.insert(PixelSampler(x, 0, s, 0).get(0));
  // 1024 draws from 2^24 values: a few collisions are possible, many mean a broken hash.
  EXPECT_GT(seen.size(), 1015u);
}

TEST(Sampler, ToUnitFloatStaysBelowOne) {
  EXPECT_EQ(to_unit_float(0), 0.0f);
  EXPECT_LT(to_unit_float(~0ull), 1.0f);
  EXPECT_GT(to_unit_float(~0ull), 0.9999999f);
}

// Pearson's chi-square statistic of `counts` against a uniform expectation.
double chi_square(const std::vector<int>& counts, double expected) {
  double chi2 = 0.0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

TEST(Sampler, OneDimensionIsUniform) {
  // 100 bins, 200000 values over pixels, samples and dimensions, seed fixed.
  // Critical value of chi-square with 99 degrees of freedom at p = 0.001: 148.2.
  std::vector<int> bins(100, 0);
  int n = 0;
  for (std::uint32_t y = 0; y < 50; ++y)
    for (std::uint32_t x = 0; x < 50; ++x)
      for (std::uint32_t s = 0; s < 8; ++s) {
        PixelSampler sampler(x, y, s, 1234);
        for (int d = 0; d < 10; ++d) {
          const float u = sampler.next();
          ASSERT_GE(u, 0.0f);
          ASSERT_LT(u, 1.0f);
          ++bins[static_cast<int>(u * 100.0f)];
          ++n;
        }
      }
  EXPECT_LT(chi_square(bins, n / 100.0), 148.2);
}

TEST(Sampler, PairsOfDimensionsAreUniform) {
  // (dim 0, dim 1) is the pixel jitter and (dim 3, dim 4) a light sample: a 16 x 16 grid
  // of bins; 255 degrees of freedom, critical value at p = 0.001: 330.5.
  for (std::uint32_t first : {0u, 3u}) {
    std::vector<int> bins(256, 0);
    int n = 0;
    for (std::uint32_t y = 0; y < 128; ++y)
      for (std::uint32_t x = 0; x < 128; ++x)
        for (std::uint32_t s = 0; s < 4; ++s) {
          const PixelSampler sampler(x, y, s, 99);
          const int bx = static_cast<int>(sampler.get(first) * 16.0f);
          const int by = static_cast<int>(sampler.get(first + 1) * 16.0f);
          ++bins[by * 16 + bx];
          ++n;
        }
    EXPECT_LT(chi_square(bins, n / 256.0), 330.5) << "dimensions " << first << ", " << first + 1;
  }
}

TEST(Sampler, ChiSquareDetectsABiasedStream) {
  // The test above can fail: squaring the values (density 1/(2 sqrt(u))) is far from uniform.
  std::vector<int> bins(100, 0);
  int n = 0;
  for (std::uint32_t x = 0; x < 20000; ++x) {
    const float u = PixelSampler(x, 0, 0, 1234).get(0);
    ++bins[static_cast<int>(u * u * 100.0f)];
    ++n;
  }
  EXPECT_GT(chi_square(bins, n / 100.0), 148.2);
}

}  // namespace
}  // namespace lancer
