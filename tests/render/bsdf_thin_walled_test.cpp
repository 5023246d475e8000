// Thin-walled transmission (KHR_materials_transmission without KHR_materials_volume, or with
// thicknessFactor 0) against volume boundaries (thicknessFactor > 0):
//  - the BSDF: a smooth thin wall passes light straight through with weight (1 - F) baseColor
//    and reflects F, from either side (no total internal reflection); the rough thin BTDF is
//    the spec's formula (H_T = normalize(V - 2 (N.L) N + L)), reciprocal, and for a white
//    wall reflection + transmission is exactly the white metal's specular_brdf, pointwise and
//    in albedo (the microfacet lobe's own single-scattering loss, nothing more); sample() is
//    checked by a chi-square test and a white furnace (chi2_support.h);
// The integrators' side is in thin_walled_render_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "chi2_support.h"
#include "render/bsdf.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kIor = 1.5f;

BsdfInputs thin_glass(float roughness, const glm::vec3& color = glm::vec3(1.0f), float transmission = 1.0f) {
  return {color, 0.0f, roughness, kIor, 1.0f, glm::vec3(1.0f), transmission, true};
}

glm::vec3 at_angle(float theta_deg, bool above) {
  const float t = theta_deg * kPi / 180.0f;
  return {std::sin(t), 0.0f, above ? std::cos(t) : -std::cos(t)};
}

float average(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }
float max_abs_diff(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z});
}

// ---- Smooth thin walls ------------------------------------------------------------------

// Every delta sample of a smooth thin wall, found by sweeping u_split: the transmitted one
// keeps the direction and carries (1 - F) baseColor, the reflected one mirrors and carries
// F, F being the exact Fresnel reflectance of ior 1.5 entered from air, on either side.
TEST(ThinWallSmooth, PassesStraightThroughWithOneMinusF) {
  const ShadingFrame frame = ShadingFrame::from_normal(glm::normalize(glm::vec3(0.3f, -0.4f, 0.85f)));
  const glm::vec3 tint(0.9f, 0.6f, 0.2f);
  for (const glm::vec3& color : {glm::vec3(1.0f), tint}) {
    for (bool front : {true, false}) {
      const Bsdf bsdf(thin_glass(0.0f, color), frame, front);
      ASSERT_TRUE(bsdf.is_delta_only());
      EXPECT_EQ(bsdf.eta(), 1.0f);
      for (float theta : {0.0f, 30.0f, 60.0f, 85.0f}) {
        const glm::vec3 lo = at_angle(theta, front);
        const glm::vec3 wo = frame.to_world(lo);
        const float F = exact_dielectric_fresnel(std::cos(theta * kPi / 180.0f), kIor);
        const glm::vec3 mirror = frame.to_world(glm::vec3(-lo.x, -lo.y, lo.z));
        double p_reflect = 0.0, p_transmit = 0.0;
        constexpr int kSteps = 1000;
        for (int k = 0; k < kSteps; ++k) {
          const auto s = bsdf.sample(wo, (k + 0.5f) / kSteps, glm::vec2(0.3f, 0.7f));
          ASSERT_TRUE(s && s->delta) << theta;
          if (s->transmitted) {
            EXPECT_LT(glm::length(s->wi + wo), 1e-5f) << "bent at " << theta << " degrees";
            EXPECT_LT(max_abs_diff(s->weight * s->pdf, (1.0f - F) * color), 1e-5f) << theta;
            p_transmit += 1.0 / kSteps;
          } else {
            EXPECT_LT(glm::length(s->wi - mirror), 1e-5f) << theta;
            EXPECT_NEAR(average(s->weight * s->pdf), F, 1e-5f) << theta;
            p_reflect += 1.0 / kSteps;
          }
          EXPECT_EQ(average(bsdf.eval(wo, s->wi)), 0.0f);
          EXPECT_EQ(bsdf.pdf(wo, s->wi), 0.0f);
        }
        // u_split picks the lobes in proportion to their weights (1/1000 of resolution).
        const float t = average((1.0f - F) * color);
        EXPECT_NEAR(p_transmit, t / (F + t), 1.5e-3) << theta;
        EXPECT_NEAR(p_reflect + p_transmit, 1.0, 1e-9);
      }
    }
  }
}

// Seen from its back at 60 degrees a volume boundary of ior 1.5 reflects totally (the
// critical angle is 41.8 degrees); a thin wall has air behind it and transmits 1 - F.
TEST(ThinWallSmooth, BackSideHasNoTotalInternalReflection) {
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f));
  const glm::vec3 wo = at_angle(60.0f, false);
  BsdfInputs volume = thin_glass(0.0f);
  volume.thin_walled = false;
  const Bsdf solid(volume, frame, false);
  const Bsdf thin(thin_glass(0.0f), frame, false);
  const float F = exact_dielectric_fresnel(0.5f, kIor);
  for (float u : {0.01f, 0.5f, 0.99f}) {
    const auto s = solid.sample(wo, u, glm::vec2(0.5f));
    ASSERT_TRUE(s);
    EXPECT_FALSE(s->transmitted);
    EXPECT_NEAR(average(s->weight), 1.0f, 1e-6f);
  }
  const auto t = thin.sample(wo, 0.99f, glm::vec2(0.5f));
  ASSERT_TRUE(t && t->transmitted);
  EXPECT_NEAR(average(t->weight * t->pdf), 1.0f - F, 1e-6f);
}

// ---- Rough thin walls: the formula, reciprocity, the white metal identity --------------

// The spec's thin BTDF (KHR_materials_transmission, "Implementation Notes") written out,
// with the height-correlated G2 the whole BSDF uses (bsdf.h), times |N.L|, for specular 1
// (fr is then the exact Fresnel reflectance F, fresnel.h).
glm::vec3 spec_thin_btdf_cos(const BsdfInputs& in, const glm::vec3& v, const glm::vec3& l) {
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  const glm::vec3 h = glm::normalize(v - 2.0f * glm::dot(n, l) * n + l);  // H_T
  const float a2 = std::pow(in.roughness, 4.0f);
  // (N.H)^2 (a^2 - 1) + 1 for unit H, without the cancellation of 1 - (N.H)^2 near the peak.
  const float k = h.z * h.z * a2 + h.x * h.x + h.y * h.y;
  const float d = h.z > 0.0f ? a2 / (kPi * k * k) : 0.0f;
  const auto lambda = [&](const glm::vec3& w) {
    const float tan2 = (1.0f - w.z * w.z) / (w.z * w.z);
    return 0.5f * (std::sqrt(1.0f + a2 * tan2) - 1.0f);
  };
  const float g2 = 1.0f / (1.0f + lambda(v) + lambda(l));
  const float F = exact_dielectric_fresnel(std::abs(glm::dot(v, h)), in.ior);
  return (1.0f - F) * in.transmission * in.base_color * d * g2 / (4.0f * std::abs(v.z));
}

TEST(ThinWallRough, EvalIsTheSpecFormulaAndReciprocal) {
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f));
  SplitMix64 rng(7);
  int checked = 0;
  for (float roughness : {0.2f, 0.5f, 0.9f}) {
    const BsdfInputs in = thin_glass(roughness, glm::vec3(0.8f, 0.5f, 0.3f), 0.7f);
    for (bool front : {true, false}) {
      const Bsdf bsdf(in, frame, front);
      EXPECT_FALSE(bsdf.has_delta());
      for (int k = 0; k < 400; ++k) {
        const float z = 0.02f + 0.98f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
        const float r = std::sqrt(1.0f - z * z);
        const glm::vec3 v(r * std::cos(phi), r * std::sin(phi), z);
        const float z2 = 0.02f + 0.98f * rng.uniform(), phi2 = 2.0f * kPi * rng.uniform();
        const float r2 = std::sqrt(1.0f - z2 * z2);
        const glm::vec3 l(r2 * std::cos(phi2), r2 * std::sin(phi2), -z2);  // the other side
        // The same pair from the back face: both mirrored through the plane.
        const glm::vec3 vs = front ? v : glm::vec3(v.x, v.y, -v.z), ls = front ? l : glm::vec3(l.x, l.y, -l.z);
        const glm::vec3 f = bsdf.eval(vs, ls);
        const glm::vec3 expected = spec_thin_btdf_cos(in, v, l);
        EXPECT_LE(max_abs_diff(f, expected), 2e-5f * std::max(1.0f, average(expected)))
            << "roughness " << roughness << " front " << front;
        // Reciprocity of f = eval / |cos(wi)|.
        const glm::vec3 back = bsdf.eval(ls, vs);
        EXPECT_LE(max_abs_diff(f / z2, back / z), 2e-5f * std::max(1.0f, average(f / z2)));
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2400);
}

// For a white wall (transmission 1, specular 1) every facet splits fr + (1 - fr) = 1 between
// the reflected direction and its mirror image, with the same D and G2: reflection +
// transmission equals the specular_brdf of a white metal (conductor_fresnel = 1).
TEST(ThinWallRough, ReflectionPlusTransmissionIsTheWhiteMetalLobe) {
  const ShadingFrame frame = ShadingFrame::from_normal(glm::normalize(glm::vec3(-0.2f, 0.5f, 0.8f)));
  SplitMix64 rng(3);
  for (float roughness : {0.1f, 0.4f, 1.0f}) {
    const Bsdf thin(thin_glass(roughness), frame, true);
    const Bsdf metal({glm::vec3(1.0f), 1.0f, roughness}, frame, true);
    for (int k = 0; k < 500; ++k) {
      const float z = 0.05f + 0.95f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
      const float r = std::sqrt(1.0f - z * z);
      const glm::vec3 lo(r * std::cos(phi), r * std::sin(phi), z);
      const float z2 = 0.05f + 0.95f * rng.uniform(), phi2 = 2.0f * kPi * rng.uniform();
      const float r2 = std::sqrt(1.0f - z2 * z2);
      const glm::vec3 li(r2 * std::cos(phi2), r2 * std::sin(phi2), z2);
      const glm::vec3 wo = frame.to_world(lo), up = frame.to_world(li),
                      down = frame.to_world(glm::vec3(li.x, li.y, -li.z));
      const glm::vec3 sum = thin.eval(wo, up) + thin.eval(wo, down);
      const glm::vec3 lobe = metal.eval(wo, up);
      EXPECT_LE(max_abs_diff(sum, lobe), 1e-4f * std::max(1.0f, average(lobe))) << roughness;
      EXPECT_GT(average(thin.eval(wo, down)), 0.0f);
    }
  }
}

// ---- Chi-square and white furnace --------------------------------------------------------

struct ThinCase {
  std::string name;
  BsdfInputs in;
  bool front = true;
  float theta_deg = 0.0f;
  bool white = false;  // white, transmission 1, specular 1: albedo = the white metal's
};

// Names the case in failure messages (instead of GoogleTest's byte dump).
void PrintTo(const ThinCase& c, std::ostream* os) { *os << c.name; }

std::vector<ThinCase> thin_cases() {
  std::vector<ThinCase> cases;
  for (float r : {0.1f, 0.3f, 0.6f, 1.0f})
    for (float a : {0.0f, 30.0f, 60.0f, 85.0f})
      cases.push_back({"white_r" + std::to_string(std::lround(r * 100)) + "_" + std::to_string(std::lround(a)) + "deg",
                       thin_glass(r), true, a, true});
  cases.push_back({"white_back_r30_60deg", thin_glass(0.3f), false, 60.0f, true});
  // Partly transmissive, partly metallic, tinted specular, from both sides.
  const BsdfInputs mixed{glm::vec3(0.9f, 0.6f, 0.8f), 0.25f, 0.45f, 1.33f, 0.8f, glm::vec3(1.0f, 0.6f, 0.3f), 0.5f,
                         true};
  for (bool front : {true, false})
    for (float a : {30.0f, 70.0f})
      cases.push_back({std::string("mixed_") + (front ? "front_" : "back_") + std::to_string(std::lround(a)) + "deg",
                       mixed, front, a});
  return cases;
}

class ThinWallSampling : public ::testing::TestWithParam<ThinCase> {};

TEST_P(ThinWallSampling, ChiSquareAndWhiteFurnace) {
  const ThinCase& c = GetParam();
  constexpr int kSamples = 300000;
  // The identity frame: bins in world space are bins in the local frame (see bsdf_sampling_test.cpp).
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f));
  const glm::vec3 wo = at_angle(c.theta_deg, c.front);
  const Bsdf bsdf(c.in, frame, c.front);
  ASSERT_FALSE(bsdf.has_delta());

  const test::SphereBins bins;
  std::vector<double> observed(bins.size(), 0.0);
  double failed = 0.0, sum_w = 0.0, sum_w2 = 0.0;
  SplitMix64 rng(0x7417 + c.name.size() * 131 + static_cast<std::uint64_t>(c.theta_deg));
  for (int i = 0; i < kSamples; ++i) {
    const float u_split = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const auto s = bsdf.sample(wo, u_split, u);
    if (!s) {
      failed += 1.0;
      continue;
    }
    ASSERT_FALSE(s->delta);
    const int bin = bins.index(s->wi);
    ASSERT_GE(bin, 0);
    ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f);
    ASSERT_TRUE(std::isfinite(average(s->weight)) && std::min({s->weight.x, s->weight.y, s->weight.z}) >= 0.0f);
    // transmitted means the other side of the surface from wo.
    ASSERT_EQ(s->transmitted, (s->wi.z > 0.0f) != (wo.z > 0.0f));
    observed[bin] += 1.0;
    const double w = average(s->weight);
    sum_w += w;
    sum_w2 += w * w;
  }

  // Peaks of the two lobes: the mirror direction and the straight line through the wall.
  const std::vector<glm::vec3> peaks = {glm::vec3(-wo.x, -wo.y, wo.z), -wo};
  const test::BinIntegrals pdf_bins =
      test::integrate_bins_checked([&](const glm::vec3& d) { return bsdf.pdf(wo, d); }, bins, peaks, 1e-7);
  ASSERT_TRUE(pdf_bins.problem().empty()) << "pdf(): " << pdf_bins.problem();
  double total = 0.0;
  for (double p : pdf_bins.value) total += p;
  EXPECT_LT(total, 1.0 + 1e-4);
  const double fail_rate = std::max(0.0, 1.0 - total);
  EXPECT_NEAR(failed / kSamples, fail_rate, 5.0 * std::sqrt(std::max(fail_rate, 1.0 / kSamples) / kSamples) + 1e-4);
  std::vector<double> expected(bins.size());
  for (int i = 0; i < bins.size(); ++i) {
    expected[i] = (kSamples - failed) * pdf_bins.value[i] / total;
    const double count_error = (kSamples - failed) * pdf_bins.error[i] / total;
    ASSERT_LE(count_error, 0.05 * std::sqrt(std::max(expected[i], 5.0))) << "bin " << i << ": quadrature too coarse";
  }
  const double significance = test::sidak_significance(0.01, static_cast<int>(thin_cases().size()));
  const test::Chi2Result chi2 = test::chi2_test(observed, expected, significance);
  EXPECT_TRUE(chi2.message.empty()) << chi2.message;

  // White furnace: the weights against the quadrature of eval(), which must stay <= 1 and,
  // for a white wall, equal the white metal's albedo.
  const double mc = sum_w / kSamples;
  const double sigma = std::sqrt(std::max(0.0, sum_w2 / kSamples - mc * mc) / kSamples);
  const test::SphereBins coarse{5, 8};
  const auto albedo_of = [&](const Bsdf& b, double& error) {
    const test::BinIntegrals a = test::integrate_bins_checked(
        [&](const glm::vec3& d) { return average(b.eval(wo, d)); }, coarse, peaks, 1e-6);
    EXPECT_TRUE(a.problem().empty()) << a.problem();
    double sum = 0.0;
    error = 0.0;
    for (int i = 0; i < coarse.size(); ++i) {
      sum += a.value[i];
      error += a.error[i];
    }
    return sum;
  };
  double quad_error = 0.0;
  const double quad = albedo_of(bsdf, quad_error);
  ASSERT_LT(quad_error, 1e-4);
  EXPECT_NEAR(mc, quad, 4.0 * sigma + 1e-4) << "Monte Carlo and quadrature albedos differ";
  EXPECT_LE(quad, 1.0 + 1e-4) << "reflected + transmitted above 1";
  double metal_albedo = 0.0;
  if (c.white) {
    const Bsdf metal({glm::vec3(1.0f), 1.0f, c.in.roughness}, frame, c.front);
    double metal_error = 0.0;
    metal_albedo = albedo_of(metal, metal_error);
    EXPECT_NEAR(quad, metal_albedo, quad_error + metal_error + 1e-5) << "lost more than the microfacet lobe loses";
    if (c.in.roughness <= 0.1f && c.theta_deg <= 60.0f) {
      EXPECT_GT(quad, 0.99);
    }
  }
  std::printf("%-22s chi2 %7.1f dof %3d p %.3f  albedo mc %.4f +- %.4f quad %.4f metal %.4f failed %.4f\n",
              c.name.c_str(), chi2.statistic, chi2.dof, chi2.p_value, mc, sigma, quad, metal_albedo,
              failed / kSamples);
}

INSTANTIATE_TEST_SUITE_P(Cases, ThinWallSampling, ::testing::ValuesIn(thin_cases()),
                         [](const ::testing::TestParamInfo<ThinCase>& p) { return p.param.name; });

}  // namespace
}  // namespace lancer
