// Bsdf::delta_probability: the probability that sample() returns a delta sample, and
// Bsdf::picks_delta, the event itself for given sample values; which the
// photon mapper uses to split a visible point's BSDF into the delta part it follows and the
// non-delta part it gathers with. Checked against the frequency of delta samples over many
// draws, for every kind of delta lobe, alone and mixed with non-delta lobes.
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/bsdf.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

struct Case {
  std::string name;
  BsdfInputs in;
  float expected_min = 0.0f, expected_max = 1.0f;  // where the probability must lie at all
};

BsdfInputs dielectric(float roughness) {
  BsdfInputs in;
  in.base_color = glm::vec3(0.7f, 0.5f, 0.3f);
  in.metallic = 0.0f;
  in.roughness = roughness;
  return in;
}

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({"smooth plastic", dielectric(0.0f), 0.01f, 0.99f});
  c.push_back({"rough plastic", dielectric(0.5f), 0.0f, 0.0f});
  BsdfInputs metal = dielectric(0.0f);
  metal.metallic = 1.0f;
  c.push_back({"mirror", metal, 1.0f, 1.0f});
  BsdfInputs glass = dielectric(0.0f);
  glass.transmission = 1.0f;
  c.push_back({"glass", glass, 1.0f, 1.0f});
  glass.transmission = 0.5f;
  c.push_back({"half glass", glass, 0.01f, 0.99f});
  BsdfInputs matched = dielectric(0.4f);
  matched.transmission = 1.0f;
  matched.ior = 1.0f;  // index-matched: the transmission is a delta lobe, the reflection rough
  c.push_back({"index-matched", matched, 0.01f, 1.0f});
  BsdfInputs thin = dielectric(0.0f);
  thin.transmission = 0.7f;
  thin.thin_walled = true;
  c.push_back({"thin pane", thin, 0.01f, 0.99f});
  BsdfInputs coat = dielectric(0.6f);
  coat.clearcoat = 1.0f;
  coat.clearcoat_roughness = 0.0f;
  c.push_back({"smooth coat on rough plastic", coat, 0.01f, 0.99f});
  coat.roughness = 0.0f;
  coat.sheen_color = glm::vec3(0.5f);
  coat.sheen_roughness = 0.5f;
  c.push_back({"smooth coat, sheen, smooth plastic", coat, 0.01f, 0.99f});
  coat.clearcoat_roughness = 0.5f;
  coat.roughness = 0.5f;
  c.push_back({"rough coat, sheen, rough plastic", coat, 0.0f, 0.0f});
  return c;
}

float uniform(std::uint64_t& state) {
  state += 0x9E3779B97F4A7C15ull;
  return float(splitmix64_mix(state) >> 40) * 0x1p-24f;
}

TEST(BsdfDeltaProbability, IsTheFrequencyOfDeltaSamples) {
  constexpr int kDraws = 40000;
  const ShadingFrame frame = ShadingFrame::from_normal(glm::normalize(glm::vec3(0.1f, 0.2f, 1.0f)));
  for (const Case& c : cases()) {
    for (bool entering : {true, false}) {
      const Bsdf bsdf(c.in, frame, entering);
      for (float cos_o : {0.95f, 0.5f, 0.1f}) {
        const float sin_o = std::sqrt(1.0f - cos_o * cos_o);
        const glm::vec3 wo = frame.to_world(glm::vec3(sin_o * 0.6f, sin_o * 0.8f, cos_o));
        const Bsdf::Outgoing out = bsdf.outgoing(wo);
        const float p = bsdf.delta_probability(out);
        const std::string what = c.name + (entering ? ", entering" : ", leaving") + ", cos " + std::to_string(cos_o);
        EXPECT_GE(p, c.expected_min) << what;
        EXPECT_LE(p, c.expected_max) << what;
        std::uint64_t state = 12345;
        int delta = 0, failed = 0, picked = 0;
        for (int k = 0; k < kDraws; ++k) {
          const float u_split = uniform(state);
          const glm::vec2 u(uniform(state), uniform(state));
          const std::optional<BsdfSample> s = bsdf.sample(out, u_split, u);
          const bool picks = bsdf.picks_delta(out, u_split, u);
          picked += picks;
          if (!s)
            ++failed;
          else if (s->delta)
            ++delta;
          // picks_delta is sample()'s own choice: a delta sample exactly when it says so.
          if (s) {
            ASSERT_EQ(s->delta, picks) << what << ", draw " << k;
          }
        }
        EXPECT_NEAR(double(picked) / kDraws, p, 5.0 * std::sqrt(double(p) * (1.0 - p) / kDraws) + 1e-4) << what;
        // Binomial: five standard deviations, or 1 draw in 10^4 where p is 0 or 1 (a failed
        // non-delta sample is no delta sample; none of these delta lobes can fail).
        const double sd = std::sqrt(double(p) * (1.0 - p) / kDraws);
        EXPECT_NEAR(double(delta) / kDraws, p, 5.0 * sd + 1e-4) << what << " (" << failed << " failed)";
      }
    }
  }
}

}  // namespace
}  // namespace lancer
