// lancer-bench's answer checks and rate statistics: ties only at equal t, the 0.1% limit,
// bit-exact packet comparisons, and the median/min/max of the repetitions.
#include "bench_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bench_results.h"

namespace lancer::bench {
namespace {

Hit hit(std::uint32_t prim, float t) { return Hit{t, prim, 0.25f, 0.5f}; }

// Rays of unit direction; with a scene extent of 0 only the relative tolerance counts.
Agreement compare_closest(const std::vector<Hit>& lancer, const std::vector<Hit>& embree, float scene_extent = 0.0f) {
  return bench::compare_closest(std::vector<Ray>(lancer.size()), lancer, embree, scene_extent);
}

TEST(BenchChecks, SameTriangleSameTIsAgreementOtherTriangleSameTIsATie) {
  const std::vector<Hit> lancer = {hit(3, 2.0f), hit(4, 2.0f), Hit{}, hit(5, 1.0f)};
  const std::vector<Hit> embree = {hit(3, 2.0f * (1.0f + 5e-5f)), hit(9, 2.0f), Hit{}, hit(5, 1.0f)};
  const Agreement a = compare_closest(lancer, embree);
  EXPECT_EQ(a.compared, 4u);
  EXPECT_EQ(a.ties, 1u);
  EXPECT_EQ(a.disagreements, 0u);
  EXPECT_TRUE(a.acceptable());
}

TEST(BenchChecks, OtherTOrAMissIsADisagreement) {
  const std::vector<Hit> lancer = {hit(3, 2.0f), hit(4, 2.0f), Hit{}, hit(6, 1.0f)};
  const std::vector<Hit> embree = {hit(3, 2.01f), hit(7, 3.0f), hit(1, 1.0f), Hit{}};
  const Agreement a = compare_closest(lancer, embree);
  EXPECT_EQ(a.ties, 0u);
  EXPECT_EQ(a.disagreements, 4u);  // same triangle at another t counts too
  EXPECT_EQ(a.first_disagreement, 0u);
  EXPECT_FALSE(a.acceptable());
}

// Near a ray's origin t differs by the coordinates' rounding: on the same triangle, within
// kSameTExtent of the scene's extent (along the ray, so a direction twice as long halves it
// in t) it is the same t. Another triangle that close is not a tie.
TEST(BenchChecks, NearTheOriginTheSameTriangleIsWithinAFractionOfTheScene) {
  const float extent = 30.0f, within = kSameTExtent * extent;  // 3e-5
  const std::vector<Hit> lancer = {hit(3, 0.004f), hit(3, 0.004f), hit(3, 0.004f), hit(3, 0.004f)};
  const std::vector<Hit> embree = {hit(3, 0.004f + 0.5f * within), hit(3, 0.004f + 2.0f * within),
                                   hit(3, 0.004f + 0.75f * within), hit(4, 0.004f + 0.5f * within)};
  std::vector<Ray> rays(4);
  rays[2].dir = {0.0f, 0.0f, 2.0f};  // half the tolerance in t: 0.75 of it is out
  const Agreement a = bench::compare_closest(rays, lancer, embree, extent);
  EXPECT_EQ(a.ties, 0u);
  EXPECT_EQ(a.disagreements, 3u);
  EXPECT_EQ(a.first_disagreement, 1u);
  // Relative to t alone (extent 0), the first is a disagreement too.
  EXPECT_EQ(bench::compare_closest(rays, lancer, embree, 0.0f).disagreements, 4u);
}

TEST(BenchChecks, AtMostOnePerThousandMayDisagree) {
  std::vector<Hit> lancer(2000, hit(1, 1.0f)), embree = lancer;
  embree[10] = Hit{};
  embree[1999] = hit(2, 5.0f);
  Agreement a = compare_closest(lancer, embree);
  EXPECT_EQ(a.disagreements, 2u);
  EXPECT_EQ(a.first_disagreement, 10u);
  EXPECT_TRUE(a.acceptable());  // 2 of 2000 = 0.1%
  embree[500] = Hit{};
  a = compare_closest(lancer, embree);
  EXPECT_EQ(a.disagreements, 3u);
  EXPECT_FALSE(a.acceptable());
}

TEST(BenchChecks, OcclusionAnswersHaveNoTies) {
  const std::vector<std::uint8_t> lancer = {1, 0, 1, 0}, embree = {1, 1, 1, 0};
  const Agreement a = compare_occlusion(lancer, embree);
  EXPECT_EQ(a.disagreements, 1u);
  EXPECT_EQ(a.first_disagreement, 1u);
  EXPECT_EQ(a.ties, 0u);
  EXPECT_THROW(compare_occlusion(lancer, std::vector<std::uint8_t>(3)), std::invalid_argument);
}

TEST(BenchChecks, PacketComparisonIsBitForBit) {
  std::vector<Hit> a = {hit(1, 1.0f), hit(2, 2.0f), Hit{}}, b = a;
  std::size_t first = 0;
  EXPECT_EQ(count_bit_differences(a, b, first), 0u);
  b[1].u = std::nextafter(b[1].u, 1.0f);  // one ulp of a barycentric is a difference
  b[2].t = -0.0f;
  EXPECT_EQ(count_bit_differences(a, b, first), 2u);
  EXPECT_EQ(first, 1u);
  const std::vector<std::uint8_t> x = {0, 1, 1}, y = {0, 1, 0};
  EXPECT_EQ(count_bit_differences(x, y, first), 1u);
  EXPECT_EQ(first, 2u);
  EXPECT_THROW(count_bit_differences(a, std::vector<Hit>(2), first), std::invalid_argument);
}

TEST(BenchStats, MedianMinAndMaxOfTheRates) {
  // 1e6 rays in 1, 2 and 0.5 seconds: 1, 0.5 and 2 Mrays/s.
  RateSummary s = summarize({1.0, 2.0, 0.5}, 1000000);
  EXPECT_DOUBLE_EQ(s.median, 1.0);
  EXPECT_DOUBLE_EQ(s.min, 0.5);
  EXPECT_DOUBLE_EQ(s.max, 2.0);
  s = summarize({1.0, 0.5, 0.25, 2.0}, 1000000);  // rates 1, 2, 4, 0.5: the middle two average
  EXPECT_DOUBLE_EQ(s.median, 1.5);
  EXPECT_DOUBLE_EQ(s.min, 0.5);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  s = summarize({}, 100);
  EXPECT_EQ(s.median, 0.0);
}

}  // namespace
}  // namespace lancer::bench
