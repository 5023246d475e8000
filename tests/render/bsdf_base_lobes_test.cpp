// Each lobe of the glTF base (bsdf_base_lobes.h) on its own, under the tests the whole BSDF
// passes (bsdf_sampling_test.cpp): its sampling procedure against the density its eval()
// claims (chi-square over the sphere, Sidak-corrected over this file's cases, and the rate of
// samples that leave the lobe's domain), and its albedo by Monte Carlo (f / density) against
// the quadrature of its f. A new lobe of the base gets a case here.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "chi2_support.h"
#include "render/bsdf_base.h"
#include "render/bsdf_base_lobes.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr int kSamples = 300000;
constexpr double kFamilySignificance = 0.01;

enum class Lobe { Diffuse, Reflection, ThinWall, Refraction };

struct LobeCase {
  std::string name;
  Lobe lobe;
  BsdfInputs in;
  float theta_deg;
  bool entering = true;
};

BsdfInputs inputs(glm::vec3 color, float metallic, float roughness, float specular, float transmission, bool thin) {
  BsdfInputs in;
  in.base_color = color;
  in.metallic = metallic;
  in.roughness = roughness;
  in.specular = specular;
  in.transmission = transmission;
  in.thin_walled = thin;
  return in;
}

std::vector<LobeCase> lobe_cases() {
  std::vector<LobeCase> cases;
  for (float a : {0.0f, 45.0f, 80.0f}) {
    const std::string angle = "_" + std::to_string(static_cast<int>(a));
    cases.push_back({"diffuse_white" + angle, Lobe::Diffuse, inputs(glm::vec3(1.0f), 0.0f, 0.5f, 0.0f, 0.0f, false), a});
    cases.push_back({"diffuse_under_specular" + angle, Lobe::Diffuse,
                     inputs(glm::vec3(0.8f, 0.4f, 0.2f), 0.0f, 0.5f, 1.0f, 0.0f, false), a});
    for (float r : {0.3f, 0.7f}) {
      const std::string rough = "_r" + std::to_string(static_cast<int>(r * 10)) + angle;
      cases.push_back({"reflection_metal" + rough, Lobe::Reflection,
                       inputs(glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, r, 1.0f, 0.0f, false), a});
      cases.push_back({"reflection_dielectric" + rough, Lobe::Reflection,
                       inputs(glm::vec3(1.0f), 0.0f, r, 1.0f, 0.0f, false), a});
      cases.push_back({"thin_wall" + rough, Lobe::ThinWall, inputs(glm::vec3(1.0f), 0.0f, r, 1.0f, 1.0f, true), a});
      cases.push_back({"refraction_in" + rough, Lobe::Refraction,
                       inputs(glm::vec3(1.0f), 0.0f, r, 1.0f, 1.0f, false), a, true});
      cases.push_back({"refraction_out" + rough, Lobe::Refraction,
                       inputs(glm::vec3(1.0f), 0.0f, r, 1.0f, 1.0f, false), a, false});
    }
  }
  return cases;
}

// One lobe seen through three functions of local directions.
struct LobeProbe {
  std::function<std::optional<glm::vec3>(glm::vec2)> sample;
  std::function<LobeValue(const glm::vec3&)> eval;  // value and density of wi (0 outside the lobe)
};

LobeProbe probe(const LobeCase& c, const BaseFresnel& mix, const GgxDistribution& ggx, const LobeOutgoing& out) {
  const glm::vec3 wo = out.lo;
  const float eta = c.in.thin_walled ? 1.0f : (c.entering ? c.in.ior : 1.0f / c.in.ior);
  switch (c.lobe) {
    case Lobe::Diffuse:
      return {[](glm::vec2 u) { return std::optional<glm::vec3>(DiffuseLobe::sample(u)); },
              [=](const glm::vec3& wi) {
                if (!(wi.z > 0.0f)) return LobeValue{};
                const glm::vec3 h = reflection_half_vector(wo, wi);
                return DiffuseLobe(mix).eval(mix, wi, mix.reflectance(glm::dot(wo, h)));
              }};
    case Lobe::Reflection:
      return {[=](glm::vec2 u) { return ReflectionLobe::direction(wo, ggx.sample_visible(wo, u)); },
              [=](const glm::vec3& wi) {
                if (!(wi.z > 0.0f)) return LobeValue{};
                const HalfVectorSum h = reflection_half_sum(wo, wi);
                const float cos_wo_h = h.cos_with(wo);
                return ReflectionLobe(mix, ggx).eval(out, wi, h, mix.specular_tint(cos_wo_h, mix.reflectance(cos_wo_h)));
              }};
    case Lobe::ThinWall: {
      const ThinWallLobe lobe(mix, ggx, true);
      return {[=](glm::vec2 u) { return lobe.direction(wo, ggx.sample_visible(wo, u)); },
              [=](const glm::vec3& wi) {
                if (!(wi.z < 0.0f)) return LobeValue{};
                const glm::vec3 m = *lobe.facet_normal(wo, wi);
                return lobe.eval(mix, out, wi, m, mix.reflectance(glm::dot(wo, m)));
              }};
    }
    case Lobe::Refraction: {
      const RefractionLobe lobe(mix, ggx, false, eta);
      return {[=](glm::vec2 u) { return lobe.direction(wo, ggx.sample_visible(wo, u)); },
              [=](const glm::vec3& wi) {
                if (!(wi.z < 0.0f)) return LobeValue{};
                const std::optional<glm::vec3> m = lobe.facet_normal(wo, wi);
                if (!m || lobe.weight(mix, wo, *m, glm::vec3(0.0f)) == 0.0f) return LobeValue{};  // no refraction there
                return lobe.eval(mix, out, wi, *m, mix.reflectance(glm::dot(wo, *m)));
              }};
    }
  }
  return {};
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char ch : s) h = (h ^ ch) * 0x100000001B3ull;
  return h;
}

float average(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

class BaseLobes : public ::testing::TestWithParam<LobeCase> {};

TEST_P(BaseLobes, SamplingMatchesDensityAndAlbedoMatchesQuadrature) {
  const LobeCase& c = GetParam();
  const BaseFresnel mix(c.in, c.entering);
  const float alpha = c.in.roughness * c.in.roughness;
  const GgxDistribution ggx(alpha);
  const float theta = c.theta_deg * std::numbers::pi_v<float> / 180.0f;
  LobeOutgoing out;
  out.lo = glm::vec3(std::sin(theta), 0.0f, std::cos(theta));
  out.lambda_o = ggx.lambda(out.lo);
  out.g1_o = 1.0f / (1.0f + out.lambda_o);
  out.inv_4cos_o = 1.0f / (4.0f * out.lo.z);
  const LobeProbe lobe = probe(c, mix, ggx, out);

  // The lobe exists as the base builds it (a case that tested a lobe the base never uses
  // would prove nothing).
  const BaseBsdf base(c.in, ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f)), c.entering);
  ASSERT_TRUE(base.has_non_delta());

  const test::SphereBins bins;
  std::vector<double> histogram(bins.size(), 0.0);
  SplitMix64 rng(fnv1a(c.name));
  double failed = 0.0, sum_w = 0.0, sum_w2 = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const std::optional<glm::vec3> wi = lobe.sample(glm::vec2(rng.uniform(), rng.uniform()));
    if (!wi) {
      failed += 1.0;
      continue;
    }
    const int bin = bins.index(*wi);
    ASSERT_GE(bin, 0);
    const LobeValue v = lobe.eval(*wi);
    ASSERT_GT(v.density, 0.0f) << "a sampled direction has no density";
    histogram[bin] += 1.0;
    const double w = average(v.f) / v.density;
    sum_w += w;
    sum_w2 += w * w;
  }

  // Quadrature nodes at the lobes' peaks: the mirror, straight through, and the refraction.
  std::vector<glm::vec3> peaks = {glm::vec3(-out.lo.x, -out.lo.y, out.lo.z), -out.lo};
  const float eta = c.entering ? c.in.ior : 1.0f / c.in.ior;
  if (const auto t = refract_about(out.lo, glm::vec3(0.0f, 0.0f, 1.0f), eta); t && c.lobe == Lobe::Refraction)
    peaks.push_back(*t);
  // And the edge of refraction's support in the plane of wo and n, reached through the
  // facet at the critical angle (wo grazes it when eta > 1): near the pole that edge cuts off
  // a cap too small for the quadrature's first nodes to see.
  const float edge_cos = eta > 1.0f ? 0.0f : std::sqrt(1.0f - eta * eta);
  const float beta = std::acos(edge_cos) - 1e-3f;
  for (float side : {-1.0f, 1.0f}) {
    const glm::vec3 facet = std::cos(beta) * out.lo + side * std::sin(beta) * glm::vec3(-out.lo.z, 0.0f, out.lo.x);
    if (const auto t = refract_about(out.lo, facet, eta); t && facet.z > 0.0f && c.lobe == Lobe::Refraction)
      peaks.push_back(*t);
  }
  const test::BinIntegrals density =
      test::integrate_bins_checked([&](const glm::vec3& d) { return lobe.eval(d).density; }, bins, peaks, 1e-7);
  ASSERT_TRUE(density.problem().empty()) << density.problem();
  double total = 0.0;
  for (double p : density.value) total += p;
  EXPECT_LT(total, 1.0 + 1e-4) << "the density integrates to more than 1";
  const double fail_rate = std::max(0.0, 1.0 - total);
  EXPECT_NEAR(failed / kSamples, fail_rate, 5.0 * std::sqrt(std::max(fail_rate, 1.0 / kSamples) / kSamples) + 1e-4)
      << "samples leave the lobe more or less often than its density implies";
  std::vector<double> expected(bins.size());
  for (int i = 0; i < bins.size(); ++i) expected[i] = (kSamples - failed) * density.value[i] / total;
  const test::Chi2Result chi2 = test::chi2_test(
      histogram, expected, test::sidak_significance(kFamilySignificance, static_cast<int>(lobe_cases().size())));
  EXPECT_TRUE(chi2.message.empty()) << chi2.message;

  const double mc = sum_w / kSamples;
  const double sigma = std::sqrt(std::max(0.0, sum_w2 / kSamples - mc * mc) / kSamples);
  const test::BinIntegrals albedo = test::integrate_bins_checked(
      [&](const glm::vec3& d) { return average(lobe.eval(d).f); }, test::SphereBins{5, 8}, peaks, 1e-6);
  ASSERT_TRUE(albedo.problem().empty()) << albedo.problem();
  double quadrature = 0.0;
  for (double a : albedo.value) quadrature += a;
  EXPECT_NEAR(mc, quadrature, 4.0 * sigma + 1e-4) << "Monte Carlo and quadrature albedos differ";
  EXPECT_LE(quadrature, 1.0 + 1e-4) << "the lobe alone reflects more than it receives";
  std::printf("%-32s chi2 %7.1f dof %3d p %.3f  albedo mc %.4f +- %.4f quad %.4f  failed %.4f\n", c.name.c_str(),
              chi2.statistic, chi2.dof, chi2.p_value, mc, sigma, quadrature, failed / kSamples);
}

INSTANTIATE_TEST_SUITE_P(Cases, BaseLobes, ::testing::ValuesIn(lobe_cases()),
                         [](const ::testing::TestParamInfo<LobeCase>& p) { return p.param.name; });

// A white Lambertian base without a specular layer reflects exactly what it receives.
TEST(BaseLobes, WhiteDiffuseWithoutSpecularIsLambert) {
  const BaseFresnel mix(inputs(glm::vec3(1.0f), 0.0f, 0.5f, 0.0f, 0.0f, false), true);
  const glm::vec3 wi = glm::normalize(glm::vec3(0.3f, -0.2f, 0.7f));
  const LobeValue v = DiffuseLobe(mix).eval(mix, wi, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(v.f.x, wi.z / std::numbers::pi_v<float>);
  EXPECT_FLOAT_EQ(v.density, wi.z / std::numbers::pi_v<float>);
}

// The reflection lobe's value and density from the unnormalised half vector (one division,
// ReflectionLobe::eval) equal the textbook form with h normalised, computed in double: D(h)
// G2 / (4 wo.z) and G1(wo) D(h) / (4 wo.z). Also where the pair is nearly opposite and grazing,
// so that |wo + wi| is rescaled (HalfVectorSum), and at alphas from nearly smooth to 1.
TEST(BaseLobes, ReflectionFromTheHalfVectorSumIsTheNormalisedForm) {
  const BaseFresnel mix(inputs(glm::vec3(1.0f), 1.0f, 0.5f, 1.0f, 0.0f, false), true);
  const auto reference = [](double a, const glm::dvec3& wo, const glm::dvec3& wi, double& density) {
    const double a2 = a * a;
    const glm::dvec3 h = glm::normalize(wo + wi);
    const double k = a2 * h.z * h.z + h.x * h.x + h.y * h.y;
    const double d = a2 / (std::numbers::pi * k * k);
    const auto lambda = [&](const glm::dvec3& w) {
      return 0.5 * (std::sqrt(w.z * w.z + a2 * (w.x * w.x + w.y * w.y)) / w.z - 1.0);
    };
    density = d / (1.0 + lambda(wo)) / (4.0 * wo.z);
    return d / (1.0 + lambda(wo) + lambda(wi)) / (4.0 * wo.z);
  };
  std::vector<std::pair<glm::vec3, glm::vec3>> pairs;
  SplitMix64 rng(7);
  const auto uniform = [&] { return rng.uniform(); };
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 wo = glm::normalize(glm::vec3(2.0f * uniform() - 1.0f, 2.0f * uniform() - 1.0f, uniform() + 1e-3f));
    const glm::vec3 wi = glm::normalize(glm::vec3(2.0f * uniform() - 1.0f, 2.0f * uniform() - 1.0f, uniform() + 1e-3f));
    pairs.push_back({wo, wi});
  }
  // Nearly opposite and grazing: |wo + wi|^2 about 1e-19, so that D's k^2 would fall below
  // the normal floats without the rescaling.
  const glm::vec3 grazing = glm::normalize(glm::vec3(1.0f, 0.0f, 1e-10f));
  const glm::vec3 back = glm::normalize(glm::vec3(-1.0f, 3e-11f, 2e-10f));
  ASSERT_LT(glm::dot(grazing + back, grazing + back), 0x1p-60f);
  pairs.push_back({grazing, back});
  pairs.push_back({back, grazing});
  // wo grazing to within a few normal floats: Lambda(wo) finite but huge, so that D's
  // denominator times g would overflow float.
  const glm::vec3 skimming(1.0f, 0.0f, 2e-38f);  // unit in float
  pairs.push_back({skimming, glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f))});
  int compared = 0;
  for (const float alpha : {2e-3f, 0.05f, 0.3f, 1.0f}) {
    const GgxDistribution ggx(alpha);
    const ReflectionLobe lobe(mix, ggx);
    for (const auto& [wo, wi] : pairs) {
      LobeOutgoing out;
      out.lo = wo;
      out.lambda_o = ggx.lambda(wo);
      out.g1_o = 1.0f / (1.0f + out.lambda_o);
      out.inv_4cos_o = 1.0f / (4.0f * wo.z);
      const HalfVectorSum h = reflection_half_sum(wo, wi);
      EXPECT_NEAR(h.cos_with(wo), glm::dot(glm::dvec3(wo), glm::normalize(glm::dvec3(wo) + glm::dvec3(wi))), 2e-6);
      const LobeValue v = lobe.eval(out, wi, h, glm::vec3(1.0f));
      double density = 0.0;
      const double f = reference(alpha, glm::dvec3(wo), glm::dvec3(wi), density);
      // Relative to the value, and absolutely where the float inputs' rounding dominates a
      // value near 0 (far in the tail of a narrow lobe).
      EXPECT_NEAR(v.f.x, f, 1e-4 * f + 1e-30) << "alpha " << alpha << " wo.z " << wo.z << " wi.z " << wi.z;
      EXPECT_NEAR(v.density, density, 1e-4 * density + 1e-30) << "alpha " << alpha;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 4 * 203);
}

// Which lobes a material has follows its inputs, one type each.
TEST(BaseLobes, ExistenceFollowsTheMaterial) {
  const GgxDistribution ggx(0.25f);
  const BaseFresnel metal(inputs(glm::vec3(0.9f), 1.0f, 0.5f, 1.0f, 0.0f, false), true);
  EXPECT_FALSE(DiffuseLobe(metal).exists());
  EXPECT_TRUE(ReflectionLobe(metal, ggx).exists());
  const BaseFresnel glass(inputs(glm::vec3(1.0f), 0.0f, 0.5f, 1.0f, 1.0f, false), true);
  EXPECT_FALSE(DiffuseLobe(glass).exists());
  EXPECT_TRUE(RefractionLobe(glass, ggx, false, 1.5f).exists());
  EXPECT_FALSE(ThinWallLobe(glass, ggx, false).exists());
  EXPECT_TRUE(ThinWallLobe(glass, ggx, true).exists());
  EXPECT_FALSE(RefractionLobe(glass, ggx, true, 1.0f).exists());
  // Index-matched refraction is a delta lobe whatever the roughness.
  EXPECT_TRUE(RefractionLobe(glass, ggx, false, 1.0f + 1e-4f).delta());
  EXPECT_FALSE(RefractionLobe(glass, ggx, false, 1.5f).delta());
  // Black glass transmits nothing.
  const BaseFresnel black(inputs(glm::vec3(0.0f), 0.0f, 0.5f, 1.0f, 1.0f, false), true);
  EXPECT_FALSE(RefractionLobe(black, ggx, false, 1.5f).exists());
}

}  // namespace
}  // namespace lancer
