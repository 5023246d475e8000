// Owen-scrambled Sobol' sampler: the generator matrices, the scramble, net stratification
// of every padded set, decorrelation across pixels and sets, and faster convergence than
// independent random numbers on a smooth integrand.
#include "render/sobol_sampler.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "simd/splitmix64.h"

namespace lancer {
namespace {

// Rows of the k x k matrix that maps the low k index bits to the top k output bits.
std::uint32_t matrix_row(const std::array<std::uint32_t, 32>& columns, int row, int k) {
  std::uint32_t mask = 0;
  for (int i = 0; i < k; ++i)
    if ((columns[static_cast<std::size_t>(i)] >> (31 - row)) & 1u) mask |= 1u << i;
  return mask;
}

int gf2_rank(std::vector<std::uint32_t> rows) {
  int rank = 0;
  for (int bit = 0; bit < 32; ++bit) {
    std::size_t pivot = static_cast<std::size_t>(rank);
    while (pivot < rows.size() && !((rows[pivot] >> bit) & 1u)) ++pivot;
    if (pivot == rows.size()) continue;
    std::swap(rows[pivot], rows[static_cast<std::size_t>(rank)]);
    for (std::size_t r = 0; r < rows.size(); ++r)
      if (r != static_cast<std::size_t>(rank) && ((rows[r] >> bit) & 1u)) rows[r] ^= rows[static_cast<std::size_t>(rank)];
    ++rank;
  }
  return rank;
}

TEST(SobolSampler, SecondDimensionDirectionNumbers) {
  // m_k = 1, 3, 5, 15, 17 for Joe & Kuo's dimension 2 (polynomial x + 1, m_1 = 1).
  const auto v = sobol::second_dimension_directions();
  EXPECT_EQ(v[0], 0x80000000u);
  EXPECT_EQ(v[1], 0xC0000000u);
  EXPECT_EQ(v[2], 0xA0000000u);
  EXPECT_EQ(v[3], 0xF0000000u);
  EXPECT_EQ(v[4], 0x88000000u);
  // The first eight points of the unscrambled sequence in natural index order.
  const double want0[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double want1[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (std::uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(sobol::sobol_dimension0(i), static_cast<std::uint32_t>(want0[i] * 4294967296.0)) << i;
    EXPECT_EQ(sobol::sobol_dimension1(i), static_cast<std::uint32_t>(want1[i] * 4294967296.0)) << i;
  }
}

// Dimensions 0 and 1 form a (0,2)-sequence in all 32 bits: for every k and every split
// a + b = k, the first a rows of C0 with the first b rows of C1 are non-singular over GF(2).
TEST(SobolSampler, GeneratorMatricesFormA02Sequence) {
  std::array<std::uint32_t, 32> c0{};
  for (std::size_t i = 0; i < 32; ++i) c0[i] = sobol::sobol_dimension0(1u << i);
  const auto c1 = sobol::second_dimension_directions();
  for (std::size_t i = 0; i < 32; ++i) EXPECT_EQ(sobol::sobol_dimension1(1u << i), c1[i]);
  for (int k = 1; k <= 32; ++k)
    for (int a = 0; a <= k; ++a) {
      std::vector<std::uint32_t> rows;
      for (int r = 0; r < a; ++r) rows.push_back(matrix_row(c0, r, k));
      for (int r = 0; r < k - a; ++r) rows.push_back(matrix_row(c1, r, k));
      EXPECT_EQ(gf2_rank(rows), k) << "k = " << k << ", a = " << a;
    }
}

TEST(SobolSampler, OwenScrambleIsNestedAndBijective) {
  SplitMix64 rng(7);
  for (int trial = 0; trial < 8; ++trial) {
    const auto seed = static_cast<std::uint32_t>(rng.next());
    // Bijective on the top 16 bits.
    std::set<std::uint32_t> seen;
    for (std::uint32_t x = 0; x < 65536; ++x) seen.insert(sobol::owen_scramble(x << 16, seed) >> 16);
    EXPECT_EQ(seen.size(), 65536u);
    // Values sharing their top j bits still share them after the scramble.
    for (int j = 1; j < 32; ++j) {
      const auto x = static_cast<std::uint32_t>(rng.next());
      const std::uint32_t y = (x & ~(0xFFFFFFFFu >> j)) | (static_cast<std::uint32_t>(rng.next()) >> j);
      EXPECT_EQ(sobol::owen_scramble(x, seed) >> (32 - j), sobol::owen_scramble(y, seed) >> (32 - j)) << j;
    }
  }
}

// The byte tables give the matrix product bit for bit: against the direct xor of the
// columns of the set bits, on indices random in all 32 bits.
TEST(SobolSampler, ByteTablesGiveTheGeneratorMatrixProduct) {
  const auto columns = sobol::second_dimension_directions();
  SplitMix64 rng(7);
  for (int n = 0; n < 100000; ++n) {
    const auto index = static_cast<std::uint32_t>(rng.next());
    std::uint32_t want = 0;
    for (std::size_t bit = 0; bit < 32; ++bit)
      if ((index >> bit) & 1u) want ^= columns[bit];
    ASSERT_EQ(sobol::sobol_dimension1(index), want) << index;
    ASSERT_EQ(sobol::reversed_sobol_dimension1(sobol::reverse_bits(index)), sobol::reverse_bits(want)) << index;
  }
}

// The sampler's values, pinned as float bits: they were computed by the direct definitions
// (a 32-step loop for dimension 1, owen_scramble's two reversals each), before the sampler
// was rewritten in the bit-reversed domain with byte tables. A change here changes every
// image.
TEST(SobolSampler, ValuesAreThoseOfTheDefinitions) {
  struct Pinned {
    std::uint32_t x, y, index;
    std::uint64_t seed;
    std::uint32_t bits[6];  // next2, next1, next2, next1
  };
  const Pinned pinned[] = {
      {0, 0, 0, 0x0ull, {0x3CAE4EE0u, 0x3F702CA0u, 0x3F0EA69Cu, 0x3E8CF2CCu, 0x3EF37E74u, 0x3F7C430Au}},
      {3, 7, 1, 0x0ull, {0x3ED94794u, 0x3F3DA299u, 0x3F33701Du, 0x3F121C02u, 0x3EEA3462u, 0x3E9ABB98u}},
      {17, 33, 255, 0x5ull, {0x3F04E776u, 0x3E0BD4C0u, 0x3F40DB48u, 0x3F2A0787u, 0x3F2A97DEu, 0x3F5DCC03u}},
      {1023, 767, 65537, 0xDEADBEEFull, {0x3E76D8B8u, 0x3F160B3Eu, 0x3E121380u, 0x3E883B90u, 0x3F5E12A3u, 0x3F74BED8u}},
      {4, 2000, 1000003, 0x1ull, {0x3F2BC302u, 0x3EE3814Eu, 0x3F5EDAC2u, 0x3E6A7290u, 0x3E9D52E0u, 0x3F4A31ABu}},
  };
  for (const Pinned& p : pinned) {
    SobolSampler s(p.x, p.y, p.index, p.seed);
    const glm::vec2 a = s.next2();
    const float one = s.next1();
    const glm::vec2 b = s.next2();
    const float two = s.next1();
    const float got[6] = {a.x, a.y, one, b.x, b.y, two};
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(std::bit_cast<std::uint32_t>(got[i]), p.bits[i]) << "pixel " << p.x << "," << p.y << " index "
                                                                 << p.index << " value " << i;
  }
}

TEST(SobolSampler, UnitFloatNeverReachesOne) {
  EXPECT_LT(sobol::to_unit_float(0xFFFFFFFFu), 1.0f);
  EXPECT_EQ(sobol::to_unit_float(0xFFFFFFFFu), 1.0f - 0x1p-24f);
  EXPECT_EQ(sobol::to_unit_float(0u), 0.0f);
}

struct PixelCase {
  std::uint32_t x, y;
  std::uint64_t seed;
};
const PixelCase kPixels[] = {{0, 0, 0}, {1, 0, 0}, {17, 33, 5}, {1023, 767, 0xDEADBEEFull}, {4, 2000, 1}};

// Draws, in order, set A = next2 (dims 0,1), a next1 (dim 2), set B = next2 (dims 3,4).
struct Draw {
  glm::vec2 a;
  float one;
  glm::vec2 b;
};
Draw draw(const PixelCase& p, std::uint32_t index) {
  SobolSampler s(p.x, p.y, index, p.seed);
  Draw d;
  d.a = s.next2();
  d.one = s.next1();
  d.b = s.next2();
  EXPECT_EQ(s.dimension(), 5u);
  return d;
}

// Every elementary interval [i 2^-a, (i+1) 2^-a) x [j 2^-b, (j+1) 2^-b), a + b = k, holds
// exactly one of the 2^k points.
void expect_02_net(const std::vector<glm::vec2>& pts, int k, const std::string& what) {
  ASSERT_EQ(pts.size(), std::size_t{1} << k);
  for (int a = 0; a <= k; ++a) {
    const int b = k - a;
    std::vector<int> count(pts.size(), 0);
    for (const glm::vec2& p : pts) {
      const auto i = static_cast<std::size_t>(std::floor(p.x * std::ldexp(1.0, a)));
      const auto j = static_cast<std::size_t>(std::floor(p.y * std::ldexp(1.0, b)));
      ++count[(i << b) + j];
    }
    int bad = 0;
    for (int c : count) bad += c != 1;
    EXPECT_EQ(bad, 0) << what << ": k = " << k << ", intervals 2^-" << a << " x 2^-" << b;
  }
}

TEST(SobolSampler, EveryPaddedPairIsA02Net) {
  for (const PixelCase& p : kPixels) {
    std::vector<Draw> draws;
    for (std::uint32_t i = 0; i < 2048; ++i) draws.push_back(draw(p, i));
    const std::string where = "pixel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ")";
    for (int k = 4; k <= 10; ++k) {
      std::vector<glm::vec2> a, b;
      for (std::size_t i = 0; i < (std::size_t{1} << k); ++i) {
        a.push_back(draws[i].a);
        b.push_back(draws[i].b);
      }
      expect_02_net(a, k, where + " set A");
      expect_02_net(b, k, where + " set B");
    }
    // The second block of 1024 samples is a net too (the shuffle moves whole blocks).
    std::vector<glm::vec2> second;
    for (std::size_t i = 1024; i < 2048; ++i) second.push_back(draws[i].b);
    expect_02_net(second, 10, where + " set B, samples 1024..2047");
  }
}

TEST(SobolSampler, OneDimensionalValuesAreStratified) {
  for (const PixelCase& p : kPixels)
    for (int k = 0; k <= 10; ++k) {
      const std::size_t n = std::size_t{1} << k;
      std::vector<int> ones(n, 0), ax(n, 0), by(n, 0);
      for (std::uint32_t i = 0; i < n; ++i) {
        const Draw d = draw(p, i);
        ++ones[static_cast<std::size_t>(d.one * static_cast<float>(n))];
        ++ax[static_cast<std::size_t>(d.a.x * static_cast<float>(n))];
        ++by[static_cast<std::size_t>(d.b.y * static_cast<float>(n))];
      }
      for (std::size_t c = 0; c < n; ++c) {
        ASSERT_EQ(ones[c], 1) << "next1, k = " << k << ", stratum " << c;
        ASSERT_EQ(ax[c], 1) << "set A x, k = " << k << ", stratum " << c;
        ASSERT_EQ(by[c], 1) << "set B y, k = " << k << ", stratum " << c;
      }
    }
}

TEST(SobolSampler, MeanOfXIsOneHalf) {
  for (const PixelCase& p : kPixels) {
    double one = 0, ax = 0, ay = 0, by = 0;
    for (std::uint32_t i = 0; i < 1024; ++i) {
      const Draw d = draw(p, i);
      one += d.one;
      ax += d.a.x;
      ay += d.a.y;
      by += d.b.y;
    }
    EXPECT_NEAR(one / 1024, 0.5, 1.0 / 1024);
    EXPECT_NEAR(ax / 1024, 0.5, 1.0 / 1024);
    EXPECT_NEAR(ay / 1024, 0.5, 1.0 / 1024);
    EXPECT_NEAR(by / 1024, 0.5, 1.0 / 1024);
  }
}

TEST(SobolSampler, DeterministicAndKeyedByEveryInput) {
  const PixelCase p{12, 34, 99};
  for (std::uint32_t i = 0; i < 64; ++i) {
    const Draw d1 = draw(p, i), d2 = draw(p, i);
    EXPECT_EQ(d1.a, d2.a);
    EXPECT_EQ(d1.one, d2.one);
    EXPECT_EQ(d1.b, d2.b);
  }
  auto first16 = [](std::uint32_t x, std::uint32_t y, std::uint64_t seed) {
    std::vector<float> v;
    for (std::uint32_t i = 0; i < 16; ++i) {
      SobolSampler s(x, y, i, seed);
      const glm::vec2 u = s.next2();
      v.push_back(u.x);
      v.push_back(u.y);
    }
    return v;
  };
  const auto base = first16(12, 34, 99);
  EXPECT_NE(first16(13, 34, 99), base);
  EXPECT_NE(first16(12, 35, 99), base);
  EXPECT_NE(first16(34, 12, 99), base);
  EXPECT_NE(first16(12, 34, 100), base);
}

TEST(SobolSampler, ValuesStayInTheUnitInterval) {
  for (std::uint32_t y = 0; y < 16; ++y)
    for (std::uint32_t x = 0; x < 16; ++x)
      for (std::uint32_t i = 0; i < 64; ++i) {
        SobolSampler s(x, y, i * 997u + 0xFFFF0000u, 3);
        for (int d = 0; d < 8; ++d) {
          const glm::vec2 u = s.next2();
          const float v = s.next1();
          ASSERT_TRUE(u.x >= 0.0f && u.x < 1.0f && u.y >= 0.0f && u.y < 1.0f && v >= 0.0f && v < 1.0f);
        }
      }
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Neighbouring pixels, and the padded sets within one pixel, pair their samples up like
// independent streams: the correlation over 1024 samples is that of a random pairing
// (standard deviation 1/32), not the near +-1 an unshuffled sequence would give.
TEST(SobolSampler, PixelsAndSetsAreDecorrelated) {
  double sum_abs_pixels = 0, sum_abs_sets = 0;
  int pairs = 0;
  for (std::uint32_t x = 0; x < 64; ++x) {
    std::vector<double> here, right, set_a, set_b;
    for (std::uint32_t i = 0; i < 1024; ++i) {
      const Draw d = draw({x, 5, 11}, i);
      here.push_back(d.a.x);
      set_a.push_back(d.a.y);
      set_b.push_back(d.b.y);
      right.push_back(draw({x + 1, 5, 11}, i).a.x);
    }
    sum_abs_pixels += std::abs(pearson(here, right));
    sum_abs_sets += std::abs(pearson(set_a, set_b));
    ++pairs;
  }
  // E|r| = sqrt(2/pi)/32 = 0.025 for independent pairings.
  EXPECT_LT(sum_abs_pixels / pairs, 0.04);
  EXPECT_LT(sum_abs_sets / pairs, 0.04);

  // The first sample of 4096 pixels is spread evenly, not repeated.
  std::vector<int> bins(16, 0);
  std::set<float> distinct;
  for (std::uint32_t y = 0; y < 64; ++y)
    for (std::uint32_t x = 0; x < 64; ++x) {
      SobolSampler s(x, y, 0, 0);
      const glm::vec2 u = s.next2();
      distinct.insert(u.x);
      ++bins[static_cast<std::size_t>(u.x * 4) * 4 + static_cast<std::size_t>(u.y * 4)];
    }
  EXPECT_GT(distinct.size(), 4000u);
  double chi2 = 0;
  for (int c : bins) chi2 += (c - 256.0) * (c - 256.0) / 256.0;
  EXPECT_LT(chi2, 45.0) << "15 degrees of freedom: p < 1e-4";
}

// Owen-scrambled Sobol' on a smooth integrand converges like N^-1.5 (Owen 1997); random
// sampling like N^-0.5. The integrand is a Gaussian bump with a closed-form integral.
double bump(double x, double y) {
  constexpr double kS = 0.15;
  const double dx = x - 0.45, dy = y - 0.55;
  return std::exp(-(dx * dx + dy * dy) / (2 * kS * kS));
}
double bump_integral() {
  constexpr double kS = 0.15;
  const double c = kS * std::sqrt(M_PI / 2);
  auto axis = [&](double mu) { return c * (std::erf((1 - mu) / (kS * std::sqrt(2.0))) + std::erf(mu / (kS * std::sqrt(2.0)))); };
  return axis(0.45) * axis(0.55);
}

double rms_sobol(std::uint32_t n, int seeds, bool second_set) {
  const double exact = bump_integral();
  double sum_sq = 0;
  for (int s = 0; s < seeds; ++s) {
    double sum = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      SobolSampler sampler(static_cast<std::uint32_t>(s), 7, i, 2024);
      glm::vec2 u = sampler.next2();
      if (second_set) {
        sampler.next1();
        u = sampler.next2();
      }
      sum += bump(u.x, u.y);
    }
    const double err = sum / n - exact;
    sum_sq += err * err;
  }
  return std::sqrt(sum_sq / seeds);
}

double rms_random(std::uint32_t n, int seeds) {
  const double exact = bump_integral();
  double sum_sq = 0;
  for (int s = 0; s < seeds; ++s) {
    SplitMix64 rng(static_cast<std::uint64_t>(s) + 1000);
    double sum = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const float x = rng.uniform();
      sum += bump(x, rng.uniform());
    }
    const double err = sum / n - exact;
    sum_sq += err * err;
  }
  return std::sqrt(sum_sq / seeds);
}

TEST(SobolSampler, ConvergesFasterThanRandomOnASmoothIntegrand) {
  constexpr int kSeeds = 32;
  const double random_4096 = rms_random(4096, kSeeds);
  for (bool second_set : {false, true}) {
    const double sobol_256 = rms_sobol(256, kSeeds, second_set);
    const double sobol_4096 = rms_sobol(4096, kSeeds, second_set);
    RecordProperty(second_set ? "sobol_setB_4096" : "sobol_setA_4096", std::to_string(sobol_4096));
    // Expected ratio about sqrt(N) = 64; assert a conservative 4.
    EXPECT_LT(4 * sobol_4096, random_4096) << "sobol " << sobol_4096 << " vs random " << random_4096;
    // 16x the samples: N^-0.5 gives 4x less error, N^-1.5 gives 64x; ask for more than 16x.
    EXPECT_GT(sobol_256 / sobol_4096, 16.0) << "rms at 256: " << sobol_256 << ", at 4096: " << sobol_4096;
  }
  // The random reference behaves as N^-0.5 (the comparison is against a sane baseline).
  const double random_256 = rms_random(256, kSeeds);
  EXPECT_GT(random_256 / random_4096, 2.0);
  EXPECT_LT(random_256 / random_4096, 8.0);
}

}  // namespace
}  // namespace lancer
