// The batch Sobol' draw (sobol_batch.h) against SobolSampler itself: every ISA must leave in
// each sampler the very values its get1 and get2 compute, bit for bit, for samplers of many
// pixels, sample indices and seeds, at any dimensions (counts that are not a multiple of the
// vector width included); and a sampler returns them for those dimensions only.
// Runs per ISA (AllIsas/SobolBatch.<Test>/<isa>).
#include "render/sobol_batch.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "simd/isa.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

class SobolBatch : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!cpu_supports(GetParam())) GTEST_SKIP() << "this CPU does not support " << isa_name(GetParam());
  }
};

bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST_P(SobolBatch, LeavesTheSamplersOwnValues) {
  SplitMix64 rng(0xB00 + static_cast<std::uint64_t>(GetParam()));
  for (const int count : {1, 7, 64, 133}) {
    std::vector<SobolSampler> samplers, fresh;
    std::vector<AheadRequest> requests;
    for (int i = 0; i < count; ++i) {
      const auto x = static_cast<std::uint32_t>(rng.next() % 4096), y = static_cast<std::uint32_t>(rng.next() % 4096);
      const auto index = static_cast<std::uint32_t>(rng.next());
      samplers.emplace_back(x, y, index, rng.next());
      fresh.push_back(samplers.back());
    }
    for (int i = 0; i < count; ++i) {
      AheadRequest r;
      r.sampler = &samplers[static_cast<std::size_t>(i)];
      for (int k = 0; k < 2; ++k) {
        r.dim1[k] = static_cast<std::uint32_t>(rng.next() % 600);
        r.dim2[k] = static_cast<std::uint32_t>(rng.next() % 600);
      }
      requests.push_back(r);
    }
    draw_ahead(requests.data(), count, GetParam());
    int mismatches = 0;
    for (int i = 0; i < count; ++i) {
      const AheadRequest& r = requests[static_cast<std::size_t>(i)];
      const SobolSampler& want = fresh[static_cast<std::size_t>(i)];
      for (int k = 0; k < 2; ++k) {
        const glm::vec2 got2 = r.sampler->get2(r.dim2[k]), want2 = want.get2(r.dim2[k]);
        if (!same(r.sampler->get1(r.dim1[k]), want.get1(r.dim1[k])) || !same(got2.x, want2.x) ||
            !same(got2.y, want2.y))
          ++mismatches;
      }
      // Other dimensions are computed as before.
      EXPECT_TRUE(same(r.sampler->get1(700), want.get1(700)));
    }
    EXPECT_EQ(mismatches, 0) << count << " samplers";
  }
}

// A value drawn ahead is returned for its own dimension and kind only: get1 at a pair's
// dimension, or get2 at a single one's, is computed (they differ: one is a van der Corput
// value, the other a Sobol' pair under another scramble).
TEST(SobolBatchScalar, AheadValuesServeTheirDimensionsOnly) {
  SobolSampler s(3, 4, 5, 6);
  const SobolSampler plain = s;
  const std::uint32_t dim1[2] = {10, 11}, dim2[2] = {20, 30};
  const float v1[2] = {0.25f, 0.5f};
  const glm::vec2 v2[2] = {glm::vec2(0.125f), glm::vec2(0.75f)};
  s.take_ahead(dim1, v1, dim2, v2);
  EXPECT_EQ(s.get1(10), 0.25f);
  EXPECT_EQ(s.get1(11), 0.5f);
  EXPECT_EQ(s.get2(30), glm::vec2(0.75f));
  EXPECT_TRUE(same(s.get1(20), plain.get1(20)));
  EXPECT_TRUE(same(s.get2(10).x, plain.get2(10).x));
  EXPECT_TRUE(same(s.get1(12), plain.get1(12)));
  // The marker of an empty entry is computed like any dimension, not taken for a value.
  const SobolSampler fresh(3, 4, 5, 6);
  EXPECT_NE(fresh.get1(SobolSampler::kNoDimension), 0.0f);
}

INSTANTIATE_TEST_SUITE_P(AllIsas, SobolBatch, ::testing::Values(Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512),
                         [](const ::testing::TestParamInfo<Isa>& p) { return std::string(isa_name(p.param)); });

}  // namespace
}  // namespace lancer
