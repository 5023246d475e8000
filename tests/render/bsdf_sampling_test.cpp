// Statistical tests of the BSDF's sampling (render/bsdf.h), per material and incident angle:
// - chi-square goodness of fit of sample()'s directions against pdf() integrated over bins
//   of the sphere (as pbrt-v4 and Mitsuba test theirs), Sidak-corrected over all cases, and
//   the rate of failed samples against the mass pdf() leaves out;
// - white furnace: the directional albedo from the sample weights (Monte Carlo) against
//   the integral of eval() by adaptive quadrature, and against 1.
// Every sample must be a finite unit direction with a finite, non-negative weight, and the
// quadrature must come back finite, within its evaluation budget, and with an error estimate
// small enough not to move the statistic (chi2_support.h). Each case prints its statistic,
// albedos (the energy figures quoted in bsdf.h) and the quadrature's worst bin error as a
// fraction of what the chi-square test tolerates / the albedo quadrature's error.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "chi2_support.h"
#include "render/bsdf.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr int kSamples = 500000;
constexpr double kFamilySignificance = 0.01;

struct SamplingCase {
  std::string name;
  BsdfInputs in;
  bool entering = true;   // wo above the outward normal (true) or below it (false)
  float theta_deg = 0.0f;  // angle between wo and the normal on its side
  bool lossless = false;   // the albedo must be 1, not just at most 1
  // False where the spec's own model reflects more than it receives: fresnel_mix weights the
  // diffuse base by 1 - F(V.H) of each diffuse pair, not by what the specular layer took
  // (see bsdf.h and BsdfSpec.FresnelMixGainsEnergyAtGrazingAngles).
  bool at_most_one = true;
};

std::string angle_name(float theta_deg) { return std::to_string(static_cast<int>(theta_deg)) + "deg"; }
std::string roughness_name(float r) { return "r" + std::to_string(static_cast<int>(std::lround(r * 100))); }

std::vector<SamplingCase> sampling_cases() {
  std::vector<SamplingCase> cases;
  const float angles[] = {0.0f, 30.0f, 60.0f, 85.0f};
  for (float a : angles)
    cases.push_back({"lambert_" + angle_name(a), {glm::vec3(1.0f), 0.0f, 0.7f, 1.5f, 0.0f}, true, a, true});
  for (float r : {0.1f, 0.3f, 0.6f, 1.0f}) {
    for (float a : angles) {
      const std::string suffix = "_" + roughness_name(r) + "_" + angle_name(a);
      cases.push_back({"metal" + suffix, {glm::vec3(1.0f), 1.0f, r}, true, a});
      cases.push_back({"plastic" + suffix, {glm::vec3(1.0f), 0.0f, r}, true, a, false, a < 60.0f});
      const BsdfInputs glass{glm::vec3(1.0f), 0.0f, r, 1.5f, 1.0f, glm::vec3(1.0f), 1.0f};
      cases.push_back({"glass_in" + suffix, glass, true, a});
      cases.push_back({"glass_out" + suffix, glass, false, a});  // beyond 41.8 degrees: TIR at the macro normal
    }
  }
  // Everything at once: partly metallic, partly transmissive, tinted specular.
  const BsdfInputs mixed{glm::vec3(0.9f, 0.6f, 0.8f), 0.25f, 0.45f, 1.33f, 0.8f, glm::vec3(1.0f, 0.6f, 0.3f), 0.5f};
  for (float a : angles) {
    cases.push_back({"mixed_in_" + angle_name(a), mixed, true, a});
    cases.push_back({"mixed_out_" + angle_name(a), mixed, false, a});
  }
  return cases;
}

float average(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

// A seed from the case name that is the same with every standard library (std::hash is not).
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char ch : s) h = (h ^ ch) * 0x100000001B3ull;
  return h;
}

struct SampleStats {
  std::vector<double> histogram;  // successful samples per bin
  double failed = 0.0;
  int invalid = 0;  // samples with a direction that is not a finite unit vector, or a bad weight
  int delta = 0;
  double sum_w = 0.0, sum_w2 = 0.0;  // of the channel average of the weights
  glm::dvec3 sum_rgb{0.0};

  SampleStats operator+(const SampleStats& o) const {
    SampleStats r = *this;
    for (size_t i = 0; i < r.histogram.size(); ++i) r.histogram[i] += o.histogram[i];
    r.failed += o.failed;
    r.invalid += o.invalid;
    r.delta += o.delta;
    r.sum_w += o.sum_w;
    r.sum_w2 += o.sum_w2;
    r.sum_rgb += o.sum_rgb;
    return r;
  }
};

SampleStats draw_samples(const Bsdf& bsdf, const glm::vec3& wo, const ShadingFrame& frame, const test::SphereBins& bins,
                         int n, std::uint64_t seed) {
  SampleStats st;
  st.histogram.assign(bins.size(), 0.0);
  SplitMix64 rng(seed);
  for (int i = 0; i < n; ++i) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const auto s = bsdf.sample(wo, u_split, u);
    if (!s) {
      st.failed += 1.0;
      continue;
    }
    if (s->delta) ++st.delta;
    const int bin = bins.index(frame.to_local(s->wi));
    const bool finite_weight = std::isfinite(s->weight.x) && std::isfinite(s->weight.y) && std::isfinite(s->weight.z);
    if (bin < 0 || std::abs(glm::length(s->wi) - 1.0f) > 1e-4f || !finite_weight ||
        std::min({s->weight.x, s->weight.y, s->weight.z}) < 0.0f) {
      ++st.invalid;
      continue;
    }
    st.histogram[bin] += 1.0;
    const double w = average(s->weight);
    st.sum_w += w;
    st.sum_w2 += w * w;
    st.sum_rgb += glm::dvec3(s->weight);
  }
  return st;
}

// ---- The chi-square helper itself -------------------------------------------------------

TEST(Chi2Support, IncompleteGammaAndQuadrature) {
  using test::chi2_survival;
  for (double x : {0.1, 1.0, 3.0, 30.0}) EXPECT_NEAR(test::regularized_gamma_q(1.0, x), std::exp(-x), 1e-12);
  EXPECT_NEAR(chi2_survival(3.841459, 1), 0.05, 1e-6);   // textbook critical values
  EXPECT_NEAR(chi2_survival(23.209251, 10), 0.01, 1e-6);
  EXPECT_NEAR(chi2_survival(124.342113, 100), 0.05, 1e-6);
  EXPECT_NEAR(chi2_survival(10.0, 10), 0.4404933, 1e-6);  // the series branch (x < a + 1)
  const auto sine = [](double x) { return std::sin(x); };
  EXPECT_NEAR(test::adaptive_simpson(sine, 0.0, std::numbers::pi, 1e-10, 0.0), 2.0, 1e-9);
  // A peak of width 1e-4 at a cut point is found; the uniform sphere integrates to 1 per bin area.
  const test::SphereBins bins;
  const auto area = test::integrate_bins([](const glm::vec3&) { return 1.0f; }, bins, {}, 1e-9);
  for (double a : area) EXPECT_NEAR(a, 4.0 * std::numbers::pi / bins.size(), 1e-7);
  const glm::vec3 peak = glm::normalize(glm::vec3(0.5f, 0.2f, 0.7f));
  const auto narrow = test::integrate_bins(
      [&](const glm::vec3& d) {
        const float k = 1e-8f + glm::dot(d - peak, d - peak);
        return 1e-8f / (std::numbers::pi * k * k);  // about 1 in total, almost all within 1e-4 of the peak
      },
      bins, {peak}, 1e-6);
  double total = 0.0;
  for (double a : narrow) total += a;
  EXPECT_NEAR(total, 1.0, 1e-3);
}

// The quadrature stops on a non-finite integrand and within its budget on one that never
// converges, instead of recursing through 2^34 evaluations of nested adaptive Simpson.
TEST(Chi2Support, QuadratureEndsOnNaNAndOnNoise) {
  const test::SphereBins bins;
  const auto nan_below = test::integrate_bins_checked(
      [](const glm::vec3& d) { return d.z < -0.5f ? std::numeric_limits<float>::quiet_NaN() : 1.0f; }, bins, {}, 1e-9);
  EXPECT_FALSE(nan_below.report.finite);
  EXPECT_LT(nan_below.non_finite_at.z, -0.5f);
  EXPECT_LT(nan_below.report.evaluations, 1000);
  EXPECT_NE(nan_below.problem().find("not finite"), std::string::npos) << nan_below.problem();
  EXPECT_THROW(test::integrate_bins([](const glm::vec3&) { return std::numeric_limits<float>::infinity(); }, bins, {},
                                    1e-9),
               std::runtime_error);

  // 1% multiplicative noise, far above the relative tolerances: no segment converges.
  const auto noisy = [](const glm::vec3& d) {
    std::uint32_t bits[3];
    std::memcpy(bits, &d, sizeof bits);
    SplitMix64 rng(bits[0] ^ (std::uint64_t{bits[1]} << 21) ^ (std::uint64_t{bits[2]} << 42));
    return 1.0f + 0.01f * rng.uniform();
  };
  const auto exhausted = test::integrate_bins_checked(noisy, bins, {}, 1e-9, 200'000);
  EXPECT_TRUE(exhausted.report.exhausted);
  EXPECT_LE(exhausted.report.evaluations, 200'000 + 16);  // a few nodes past it, no more
  EXPECT_NE(exhausted.problem().find("budget"), std::string::npos) << exhausted.problem();
}

// The error estimate covers the true error where the integrand jumps inside a bin (the
// depth limit then accepts unconverged segments along the jump).
TEST(Chi2Support, ErrorEstimateCoversAJump) {
  const test::SphereBins bins;
  const auto cap = test::integrate_bins_checked([](const glm::vec3& d) { return d.x > 0.3f ? 1.0f : 0.0f; }, bins, {},
                                                1e-7);
  ASSERT_TRUE(cap.problem().empty()) << cap.problem();
  double total = 0.0, error = 0.0;
  for (int i = 0; i < bins.size(); ++i) {
    total += cap.value[i];
    error += cap.error[i];
  }
  const double exact = 2.0 * std::numbers::pi * (1.0 - 0.3);  // area of the cap x > 0.3
  EXPECT_LE(std::abs(total - exact), error) << "estimate " << error;
  EXPECT_LT(error, 1e-3);
}

// ---- Per-case sampling tests ------------------------------------------------------------

class BsdfSampling : public ::testing::TestWithParam<SamplingCase> {};

TEST_P(BsdfSampling, ChiSquareAndWhiteFurnace) {
  const SamplingCase& c = GetParam();
  // The bins live in the shading frame. With n = z the frame is the identity and exact: a
  // tilted one would round directions within 1e-7 of the horizon across it, and the pdf's
  // jump there would turn into noise along a whole bin edge, which adaptive quadrature
  // chases forever. bsdf_test.cpp covers tilted frames.
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f));
  const float theta = c.theta_deg * std::numbers::pi_v<float> / 180.0f;
  const glm::vec3 lo(std::sin(theta), 0.0f, c.entering ? std::cos(theta) : -std::cos(theta));
  const glm::vec3 wo = frame.to_world(lo);
  const Bsdf bsdf(c.in, frame, c.entering);
  ASSERT_FALSE(bsdf.has_delta());

  // Draw the samples on two threads (fixed seeds, so the run is deterministic): histogram of
  // directions (local frame), the failures, and the moments of the weight for the furnace.
  const test::SphereBins bins;
  std::array<SampleStats, 2> parts;
  {
    std::vector<std::thread> workers;
    for (size_t k = 0; k < parts.size(); ++k)
      workers.emplace_back([&, k] {
        parts[k] = draw_samples(bsdf, wo, frame, bins, kSamples / 2, fnv1a(c.name) + k);
      });
    for (std::thread& w : workers) w.join();
  }
  const SampleStats stats = parts[0] + parts[1];
  ASSERT_EQ(stats.delta, 0);
  ASSERT_EQ(stats.invalid, 0) << "sample() returned non-finite or non-unit directions, or bad weights";
  const std::vector<double>& observed = stats.histogram;

  // Quadrature nodes at the lobes' peaks: the mirror and refraction directions.
  std::vector<glm::vec3> peaks = {glm::vec3(-lo.x, -lo.y, lo.z)};
  const glm::vec3 up(lo.x, lo.y, std::abs(lo.z));
  if (const auto t = refract_about(up, glm::vec3(0.0f, 0.0f, 1.0f), bsdf.eta()))
    peaks.push_back(lo.z > 0.0f ? *t : glm::vec3(t->x, t->y, -t->z));

  const test::BinIntegrals pdf_bins = test::integrate_bins_checked(
      [&](const glm::vec3& d) { return bsdf.pdf(wo, frame.to_world(d)); }, bins, peaks, 1e-7);
  ASSERT_TRUE(pdf_bins.problem().empty()) << "pdf(): " << pdf_bins.problem();
  const std::vector<double>& probability = pdf_bins.value;
  double total = 0.0;
  for (double p : probability) total += p;
  // Directions given success: pdf() integrates to the probability that sample() succeeds
  // (1 - total is the mass it discards below the horizon). Test that rate on its own (the
  // quadrature is good to ~1e-5 in total), and the histogram of the successes against pdf().
  EXPECT_LT(total, 1.0 + 1e-4) << "pdf integrates to more than 1";
  const double failed = stats.failed;
  const double fail_rate = std::max(0.0, 1.0 - total);
  EXPECT_NEAR(failed / kSamples, fail_rate, 5.0 * std::sqrt(std::max(fail_rate, 1.0 / kSamples) / kSamples) + 1e-4)
      << "sample() fails more or less often than pdf() implies";
  std::vector<double> expected(bins.size());
  for (int i = 0; i < bins.size(); ++i) expected[i] = (kSamples - failed) * probability[i] / total;
  // The quadrature must be exact enough not to move the statistic: a bin's expected count
  // may be off by at most 5% of its standard deviation (sqrt(E), at least that of the
  // pooled minimum of 5), which changes Pearson's sum by well under 0.1 per cell.
  double worst_error_ratio = 0.0;
  for (int i = 0; i < bins.size(); ++i) {
    const double count_error = (kSamples - failed) * pdf_bins.error[i] / total;
    const double ratio = count_error / (0.05 * std::sqrt(std::max(expected[i], 5.0)));
    ASSERT_LE(ratio, 1.0) << "bin " << i << ": quadrature error " << pdf_bins.error[i]
                          << " too large for the chi-square test";
    worst_error_ratio = std::max(worst_error_ratio, ratio);
  }
  const int tests = static_cast<int>(sampling_cases().size());
  const double significance = test::sidak_significance(kFamilySignificance, tests);
  const test::Chi2Result chi2 = test::chi2_test(observed, expected, significance);
  EXPECT_TRUE(chi2.message.empty()) << chi2.message;

  // White furnace.
  const double mc = stats.sum_w / kSamples;
  const double sigma = std::sqrt(std::max(0.0, stats.sum_w2 / kSamples - mc * mc) / kSamples);
  const glm::dvec3 mc_rgb = stats.sum_rgb / static_cast<double>(kSamples);
  const test::SphereBins coarse{5, 8};
  const test::BinIntegrals albedo_bins = test::integrate_bins_checked(
      [&](const glm::vec3& d) { return average(bsdf.eval(wo, frame.to_world(d))); }, coarse, peaks, 1e-6);
  ASSERT_TRUE(albedo_bins.problem().empty()) << "eval(): " << albedo_bins.problem();
  double quadrature = 0.0, quadrature_error = 0.0;
  for (int i = 0; i < coarse.size(); ++i) {
    quadrature += albedo_bins.value[i];
    quadrature_error += albedo_bins.error[i];
  }
  // Two-sided z-test at the same family-wise 1% as the chi-square tests (z = 4 for 76 cases),
  // plus 1e-4 for the quadrature's own error, which must indeed be below that.
  ASSERT_LT(quadrature_error, 1e-4) << "albedo quadrature not accurate enough";
  EXPECT_NEAR(mc, quadrature, 4.0 * sigma + 1e-4) << "Monte Carlo and quadrature albedos differ";
  if (c.at_most_one) {
    EXPECT_LE(std::max({mc_rgb.x, mc_rgb.y, mc_rgb.z}), 1.0 + 3.0 * sigma) << "albedo above 1";
  }
  if (c.lossless) {
    EXPECT_NEAR(mc, 1.0, 3.0 * sigma + 1e-5);
  }
  std::printf("%-24s chi2 %7.1f dof %3d p %.3f  albedo mc %.4f +- %.4f quad %.4f  failed %.4f  quad err %.0e/%.0e\n",
              c.name.c_str(), chi2.statistic, chi2.dof, chi2.p_value, mc, sigma, quadrature, failed / kSamples,
              worst_error_ratio, quadrature_error);
}

INSTANTIATE_TEST_SUITE_P(Cases, BsdfSampling, ::testing::ValuesIn(sampling_cases()),
                         [](const ::testing::TestParamInfo<SamplingCase>& param) { return param.param.name; });

}  // namespace
}  // namespace lancer
