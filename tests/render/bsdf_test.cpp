// The glTF metallic-roughness BSDF (render/bsdf.h): the spec's formulas evaluated
// independently, special cases exactly, sample/eval/pdf agreement, reciprocity, the
// two-sided conventions, and robustness at the edges. Statistical tests (chi-square and
// white furnace) are in bsdf_sampling_test.cpp.
#include "render/bsdf.h"
#include "render/normal_mapping.h"
#include "render/sobol_sampler.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "chi2_support.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

glm::vec3 uniform_sphere(SplitMix64& rng) {
  const float z = 1.0f - 2.0f * rng.uniform();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * rng.uniform();
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// A tilted frame, so that every test also goes through the frame transforms.
ShadingFrame tilted_frame() { return ShadingFrame::from_normal(glm::normalize(glm::vec3(0.3f, -0.4f, 0.85f))); }

float rel_diff(float a, float b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-30f}); }
float rel_diff(const glm::vec3& a, const glm::vec3& b) {
  const float scale = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z), std::abs(b.x), std::abs(b.y),
                                std::abs(b.z), 1e-30f});
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)}) / scale;
}
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// ---- The spec's formulas, written out literally -----------------------------------------

// glTF 2.0 Appendix B.3.2: D with chi+(N.H).
float spec_d(float n_h, float alpha) {
  if (n_h <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  const float k = n_h * n_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * k * k);
}
// The height-correlated V = G2 / (4 |N.L| |N.V|) of the glTF sample renderer (V_GGX).
float spec_v(float n_l, float n_v, float alpha) {
  const float a2 = alpha * alpha;
  return 0.5f / (n_l * std::sqrt(n_v * n_v * (1.0f - a2) + a2) + n_v * std::sqrt(n_l * n_l * (1.0f - a2) + a2));
}
float pow5(float x) { return x * x * x * x * x; }

// The whole BRDF of B.3.5 + KHR_materials_ior/specular for metallic in {0, 1}, local frame.
glm::vec3 spec_brdf(const BsdfInputs& in, const glm::vec3& v, const glm::vec3& l) {
  const glm::vec3 h = glm::normalize(v + l);
  const float alpha = in.roughness * in.roughness;
  const float v_h = std::abs(glm::dot(v, h));
  const float dv = spec_d(h.z, alpha) * spec_v(l.z, v.z, alpha);
  if (in.metallic == 1.0f) return dv * (in.base_color + (1.0f - in.base_color) * pow5(1.0f - v_h));
  const float f0_ior = std::pow((in.ior - 1.0f) / (in.ior + 1.0f), 2.0f);
  const glm::vec3 f0 = glm::min(f0_ior * in.specular_color, glm::vec3(1.0f));
  const glm::vec3 fr = f0 + (1.0f - f0) * pow5(1.0f - v_h);
  const float fr_max = std::max({fr.x, fr.y, fr.z});
  return in.specular * fr * dv + (1.0f - in.specular * fr_max) * in.base_color / kPi;
}

TEST(BsdfSpec, OpaqueEvalMatchesAppendixB) {
  const ShadingFrame frame = tilted_frame();
  std::vector<BsdfInputs> materials;
  for (float roughness : {0.2f, 0.5f, 1.0f}) {
    materials.push_back({glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, roughness});                      // metal
    materials.push_back({glm::vec3(0.2f, 0.5f, 0.8f), 0.0f, roughness});                      // plastic
    materials.push_back({glm::vec3(0.7f), 0.0f, roughness, 1.33f, 0.6f, glm::vec3(1.0f, 0.4f, 2.0f)});  // ior, specular
    // F0 * specularColor clamped to 1 in red:
    materials.push_back({glm::vec3(0.7f), 0.0f, roughness, 2.5f, 1.0f, glm::vec3(30.0f, 1.0f, 0.0f)});
  }
  SplitMix64 rng(1);
  for (const BsdfInputs& in : materials) {
    const Bsdf bsdf(in, frame, true);
    for (int i = 0; i < 200; ++i) {
      glm::vec3 v = uniform_sphere(rng), l = uniform_sphere(rng);
      v.z = std::abs(v.z) + 1e-3f;
      l.z = std::abs(l.z) + 1e-3f;
      v = glm::normalize(v);
      l = glm::normalize(l);
      const glm::vec3 expected = spec_brdf(in, v, l) * l.z;
      const glm::vec3 got = bsdf.eval(frame.to_world(v), frame.to_world(l));
      ASSERT_LT(rel_diff(got, expected), 2e-4f) << "roughness " << in.roughness << " metallic " << in.metallic;
    }
  }
}

TEST(BsdfSpec, SpecularZeroAndMetallicZeroIsLambert) {
  const ShadingFrame frame = tilted_frame();
  const glm::vec3 color(0.8f, 0.45f, 0.1f);
  for (float roughness : {0.0f, 0.4f, 1.0f}) {
    for (float transmission_ior : {1.5f, 1.0f}) {
      BsdfInputs in{color, 0.0f, roughness, transmission_ior, 0.0f};
      const Bsdf bsdf(in, frame, true);
      EXPECT_FALSE(bsdf.has_delta());
      SplitMix64 rng(2);
      for (int i = 0; i < 500; ++i) {
        const glm::vec3 wo = uniform_sphere(rng), wi = uniform_sphere(rng);
        const float co = glm::dot(wo, frame.n), ci = glm::dot(wi, frame.n);
        const bool same_side = co * ci > 0.0f;
        const glm::vec3 expected = same_side ? color / kPi * std::abs(ci) : glm::vec3(0.0f);
        ASSERT_LT(rel_diff(bsdf.eval(wo, wi), expected), 1e-6f);
        ASSERT_LT(rel_diff(bsdf.pdf(wo, wi), same_side ? std::abs(ci) / kPi : 0.0f), 1e-6f);
        const auto s = bsdf.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        ASSERT_TRUE(s);
        EXPECT_LT(rel_diff(s->weight, color), 1e-6f);  // cosine sampling: the weight is the albedo
        EXPECT_FALSE(s->delta);
        EXPECT_FALSE(s->transmitted);
      }
    }
  }
}

TEST(BsdfSpec, MetalHasNoDiffuseAndNoTransmission) {
  const ShadingFrame frame = tilted_frame();
  // Smooth metal: a delta mirror only, so eval (non-delta lobes) is 0 everywhere.
  const Bsdf mirror({glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.0f, 1.5f, 1.0f, glm::vec3(1.0f), 1.0f}, frame, true);
  EXPECT_TRUE(mirror.is_delta_only());
  const Bsdf rough({glm::vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.5f, 1.5f, 1.0f, glm::vec3(1.0f), 1.0f}, frame, true);
  EXPECT_FALSE(rough.has_delta());
  SplitMix64 rng(3);
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 wo = uniform_sphere(rng), wi = uniform_sphere(rng);
    EXPECT_EQ(mirror.eval(wo, wi), glm::vec3(0.0f));
    EXPECT_EQ(mirror.pdf(wo, wi), 0.0f);
    if (glm::dot(wo, frame.n) * glm::dot(wi, frame.n) < 0.0f) {
      EXPECT_EQ(rough.eval(wo, wi), glm::vec3(0.0f));
    }
    const auto s = mirror.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->pdf, 1.0f);
    const float cos_o = glm::dot(wo, frame.n);
    EXPECT_LT(glm::length(s->wi - (2.0f * cos_o * frame.n - wo)), 1e-5f);
    EXPECT_LT(rel_diff(s->weight, schlick_fresnel(glm::vec3(0.9f, 0.6f, 0.3f), cos_o)), 1e-6f);
  }
}

// VNDF sampling of a single microfacet lobe has weight F G2 / G1(wo) (Heitz 2018).
TEST(BsdfSpec, MicrofacetSampleWeightIsG2OverG1) {
  const ShadingFrame frame = tilted_frame();
  for (float roughness : {0.1f, 0.5f, 1.0f}) {
    const Bsdf white_metal({glm::vec3(1.0f), 1.0f, roughness}, frame, true);
    const GgxDistribution ggx(roughness * roughness);
    SplitMix64 rng(4);
    for (int i = 0; i < 500; ++i) {
      const glm::vec3 wo = uniform_sphere(rng);
      const auto s = white_metal.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
      if (!s) continue;
      glm::vec3 lo = frame.to_local(wo), li = frame.to_local(s->wi);
      if (lo.z < 0.0f) lo.z = -lo.z, li.z = -li.z;
      const float expected = (1.0f + ggx.lambda(lo)) / (1.0f + ggx.lambda(lo) + ggx.lambda(li));
      ASSERT_LT(rel_diff(s->weight, glm::vec3(expected)), 1e-4f) << "roughness " << roughness;
    }
  }
}

TEST(BsdfSpec, IorSetsF0OfSmoothDielectric) {
  // A black, smooth, opaque dielectric is a pure Fresnel mirror: at normal incidence it
  // reflects F0 = ((ior - 1) / (ior + 1))^2 (KHR_materials_ior), times specularColor.
  const ShadingFrame frame = ShadingFrame::from_normal({0.0f, 0.0f, 1.0f});
  for (float ior : {1.0f, 1.33f, 1.5f, 2.4f}) {
    const Bsdf bsdf({glm::vec3(0.0f), 0.0f, 0.0f, ior, 1.0f, glm::vec3(1.0f, 0.5f, 0.25f)}, frame, true);
    const auto s = bsdf.sample({0.0f, 0.0f, 1.0f}, 0.5f, {0.5f, 0.5f});
    const float f0 = std::pow((ior - 1.0f) / (ior + 1.0f), 2.0f);
    if (f0 == 0.0f) {  // nothing to reflect at normal incidence: the sample is absorbed
      EXPECT_FALSE(s);
      continue;
    }
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_LT(rel_diff(s->weight * s->pdf, f0 * glm::vec3(1.0f, 0.5f, 0.25f)), 1e-5f) << "ior " << ior;
  }
}

// The spec's fresnel_mix weights the diffuse base by 1 - F(V.H) with H the half vector of
// each diffuse pair, while the specular layer takes F(V.H) of its own (mirror-like) pairs.
// At grazing incidence the specular layer reflects F(cos theta) ~ 0.6 but the diffuse base
// loses only ~F(cos 45 deg): a white glossy dielectric reflects more than it receives. This
// is the model as specified (Appendix B says its formulation breaks energy conservation);
// if the layering is ever made energy conserving, this test and bsdf.h's note must change.
TEST(BsdfSpec, FresnelMixGainsEnergyAtGrazingAngles) {
  const ShadingFrame frame = ShadingFrame::from_normal({0.0f, 0.0f, 1.0f});
  const Bsdf plastic({glm::vec3(1.0f), 0.0f, 0.1f}, frame, true);
  const auto albedo = [&](float theta_deg) {
    const float theta = theta_deg * kPi / 180.0f;
    const glm::vec3 wo(std::sin(theta), 0.0f, std::cos(theta));
    double sum = 0.0;
    for (double v : test::integrate_bins([&](const glm::vec3& d) { return plastic.eval(wo, d).x; },
                                         test::SphereBins{4, 8}, {glm::vec3(-wo.x, -wo.y, wo.z)}, 1e-6))
      sum += v;
    return sum;
  };
  EXPECT_LE(albedo(0.0f), 1.0);
  EXPECT_LE(albedo(30.0f), 1.0);
  EXPECT_GT(albedo(85.0f), 1.5);
}

// ---- Smooth dielectric: exact Fresnel, R + T = 1, total internal reflection -------------

TEST(BsdfSmoothDielectric, ReflectionPlusTransmissionIsOne) {
  const ShadingFrame frame = tilted_frame();
  for (float ior : {1.33f, 1.5f, 2.4f}) {
    for (bool entering : {true, false}) {
      const Bsdf glass({glm::vec3(1.0f), 0.0f, 0.0f, ior, 1.0f, glm::vec3(1.0f), 1.0f}, frame, entering);
      EXPECT_TRUE(glass.is_delta_only());
      const float eta = entering ? ior : 1.0f / ior;
      for (float theta_deg : {0.0f, 20.0f, 40.0f, 41.0f, 50.0f, 70.0f, 89.0f}) {
        const float theta = theta_deg * kPi / 180.0f;
        // Outward normal convention: wo below the normal when exiting.
        const glm::vec3 lo(std::sin(theta), 0.0f, entering ? std::cos(theta) : -std::cos(theta));
        const glm::vec3 wo = frame.to_world(lo);
        const float fresnel = exact_dielectric_fresnel(std::cos(theta), eta);
        const auto r = glass.sample(wo, 0.0f, {0.3f, 0.3f});
        const auto t = glass.sample(wo, 0.99999994f, {0.3f, 0.3f});
        const float reflected = r && !r->transmitted ? r->weight.x * r->pdf : 0.0f;
        const float transmitted = t && t->transmitted ? t->weight.x * t->pdf : 0.0f;
        EXPECT_NEAR(reflected + transmitted, 1.0f, 1e-6f) << ior << (entering ? " in " : " out ") << theta_deg;
        EXPECT_NEAR(reflected, fresnel, 2e-5f);  // the frame's rounding of cos(theta) is amplified at grazing angles
        if (fresnel == 1.0f) {  // total internal reflection: every sample reflects with weight 1
          EXPECT_FALSE(t && t->transmitted);
          EXPECT_GT(std::sin(theta) * ior, entering ? 0.0f : 1.0f);
        }
        // The lobe probabilities are the exact R and T, so every sample's weight is R + T = 1.
        for (const auto& s : {r, t}) {
          ASSERT_TRUE(s);
          EXPECT_TRUE(s->delta);
          EXPECT_NEAR(s->weight.x, 1.0f, 1e-5f);
        }
        if (t && t->transmitted) {  // Snell's law, and the side it leaves on
          const glm::vec3 li = frame.to_local(t->wi);
          EXPECT_NEAR(std::hypot(li.x, li.y) * eta, std::sin(theta), 1e-5f);
          EXPECT_LT(li.z * lo.z, 0.0f);
        }
      }
    }
  }
}

TEST(BsdfSmoothDielectric, IndexMatchedPassesStraightThrough) {
  const ShadingFrame frame = tilted_frame();
  const glm::vec3 tint(0.9f, 0.7f, 0.5f);
  for (float roughness : {0.0f, 0.5f, 1.0f}) {
    for (bool entering : {true, false}) {
      const Bsdf bsdf({tint, 0.0f, roughness, 1.0f, 1.0f, glm::vec3(1.0f), 1.0f}, frame, entering);
      EXPECT_TRUE(bsdf.is_delta_only());
      SplitMix64 rng(5);
      for (int i = 0; i < 200; ++i) {
        const glm::vec3 wo = uniform_sphere(rng), wi = uniform_sphere(rng);
        EXPECT_EQ(bsdf.eval(wo, wi), glm::vec3(0.0f));  // no reflection, and the refraction is a delta
        const auto s = bsdf.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->delta && s->transmitted);
        EXPECT_LT(glm::length(s->wi + wo), 1e-5f);
        EXPECT_LT(rel_diff(s->weight * s->pdf, tint), 1e-6f);
      }
    }
  }
}

// ---- Consistency of sample(), eval() and pdf() ------------------------------------------

std::vector<BsdfInputs> assorted_materials() {
  std::vector<BsdfInputs> m;
  for (float roughness : {0.0f, 0.05f, 0.1f, 0.3f, 0.6f, 1.0f}) {
    m.push_back({glm::vec3(0.95f, 0.64f, 0.54f), 1.0f, roughness});
    m.push_back({glm::vec3(0.8f, 0.2f, 0.1f), 0.0f, roughness});
    m.push_back({glm::vec3(1.0f), 0.0f, roughness, 1.5f, 1.0f, glm::vec3(1.0f), 1.0f});
    m.push_back({glm::vec3(0.7f, 0.9f, 0.8f), 0.3f, roughness, 1.33f, 0.7f, glm::vec3(1.0f, 0.6f, 0.3f), 0.5f});
    m.push_back({glm::vec3(0.0f), 0.0f, roughness, 3.0f, 1.0f, glm::vec3(1.0f), 0.0f});
  }
  return m;
}

TEST(BsdfConsistency, SampleWeightAndPdfAgreeWithEvalAndPdf) {
  const ShadingFrame frame = tilted_frame();
  SplitMix64 rng(6);
  for (const BsdfInputs& in : assorted_materials()) {
    const float tolerance = 1e-3f;
    for (bool entering : {true, false}) {
      const Bsdf bsdf(in, frame, entering);
      int non_delta = 0;
      for (int i = 0; i < 2000; ++i) {
        const glm::vec3 wo = uniform_sphere(rng);
        const auto s = bsdf.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        if (!s) continue;
        ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-5f);
        ASSERT_TRUE(finite(s->weight));
        ASSERT_GE(std::min({s->weight.x, s->weight.y, s->weight.z}), 0.0f);
        ASSERT_GT(s->pdf, 0.0f);
        EXPECT_EQ(s->transmitted, glm::dot(wo, frame.n) * glm::dot(s->wi, frame.n) < 0.0f);
        if (s->delta) {
          ASSERT_LE(s->pdf, 1.0f);
          ASSERT_TRUE(bsdf.has_delta());
          continue;
        }
        ++non_delta;
        const glm::vec3 f = bsdf.eval(wo, s->wi);
        const float p = bsdf.pdf(wo, s->wi);
        ASSERT_LT(rel_diff(p, s->pdf), tolerance) << "roughness " << in.roughness << " sample " << i;
        ASSERT_LT(rel_diff(s->weight, f / p), tolerance) << "roughness " << in.roughness << " sample " << i;
      }
      if (!bsdf.is_delta_only()) {
        EXPECT_GT(non_delta, 200);
      }
    }
  }
}

// The lobe is picked by the 2D sample's first coordinate, rescaled within the lobe: the
// diffuse directions drawn from a (0,2)-net of 1024 points (one pixel's Owen-scrambled
// Sobol' set) then come from its points with u.x past the interface's share, which lie one
// per 1/1024 of that axis. So each of 16 equal bands of 1 - cos^2(wi) (the cosine map's first
// axis) gets the same count to within rounding. A lobe picked by an independent value would
// leave the diffuse lobe a random half of the set: counts off by about 4 per band.
TEST(BsdfStratification, EachLobeKeepsItsPartOfTheTwoDimensionalSet) {
  // Half metal, half diffuse, smooth: the interface's samples are delta and easy to tell apart.
  const BsdfInputs in{glm::vec3(1.0f), 0.5f, 0.0f, 1.5f, 1.0f};
  const Bsdf bsdf(in, ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f)), true);
  const glm::vec3 wo(0.0f, 0.0f, 1.0f);
  for (std::uint32_t pixel = 0; pixel < 4; ++pixel) {
    std::array<int, 16> band{};
    int diffuse = 0, interface = 0;
    for (std::uint32_t i = 0; i < 1024; ++i) {
      const SobolSampler sampler(pixel, 7, i, 11);
      const auto s = bsdf.sample(wo, sampler.get1(2), sampler.get2(0));
      ASSERT_TRUE(s.has_value());
      if (s->delta) {
        ++interface;
        continue;
      }
      ++diffuse;
      const float u = 1.0f - s->wi.z * s->wi.z;  // the cosine map's first coordinate
      ++band[static_cast<std::size_t>(std::clamp(static_cast<int>(16.0f * u), 0, 15))];
    }
    ASSERT_GT(interface, 300) << "the test needs both lobes";
    ASSERT_GT(diffuse, 300) << "the test needs both lobes";
    for (std::size_t b = 0; b < band.size(); ++b)
      EXPECT_NEAR(band[b], diffuse / 16.0, 2.0) << "pixel " << pixel << ", band " << b;
  }
}

// The path tracer draws u_split only where reads_split() says sample() reads it: elsewhere
// every u_split must give the same sample, bit for bit.
TEST(BsdfStratification, SplitValueIsReadOnlyWhereTheBsdfSaysSo) {
  const ShadingFrame frame = tilted_frame();
  SplitMix64 rng(12);
  int unread = 0, read = 0;
  for (const BsdfInputs& in : assorted_materials()) {
    for (bool entering : {true, false}) {
      const Bsdf bsdf(in, frame, entering);
      if (bsdf.reads_split()) {
        ++read;
        continue;
      }
      ++unread;
      for (int i = 0; i < 500; ++i) {
        const glm::vec3 wo = uniform_sphere(rng);
        const glm::vec2 u(rng.uniform(), rng.uniform());
        const auto a = bsdf.sample(wo, 0.0f, u), b = bsdf.sample(wo, rng.uniform(), u);
        ASSERT_EQ(a.has_value(), b.has_value());
        if (!a) continue;
        ASSERT_EQ(std::memcmp(&a->wi, &b->wi, sizeof a->wi), 0);
        ASSERT_EQ(std::memcmp(&a->weight, &b->weight, sizeof a->weight), 0);
        ASSERT_EQ(a->pdf, b->pdf);
        ASSERT_EQ(a->delta, b->delta);
      }
    }
  }
  EXPECT_GT(unread, 0);
  EXPECT_GT(read, 0);
}

// ---- Reciprocity --------------------------------------------------------------------

TEST(BsdfReciprocity, ReflectionIsSymmetric) {
  const ShadingFrame frame = tilted_frame();
  SplitMix64 rng(7);
  for (const BsdfInputs& in : assorted_materials()) {
    for (bool entering : {true, false}) {
      const Bsdf bsdf(in, frame, entering);
      for (int i = 0; i < 300; ++i) {
        glm::vec3 a = uniform_sphere(rng), b = uniform_sphere(rng);
        if (glm::dot(a, frame.n) * glm::dot(b, frame.n) < 0.0f) b = b - 2.0f * glm::dot(b, frame.n) * frame.n;
        const float ca = std::abs(glm::dot(a, frame.n)), cb = std::abs(glm::dot(b, frame.n));
        if (ca < 1e-3f || cb < 1e-3f) continue;
        ASSERT_LT(rel_diff(bsdf.eval(a, b) / cb, bsdf.eval(b, a) / ca), 1e-4f) << "roughness " << in.roughness;
      }
    }
  }
}

// Refraction is reciprocal up to the squared indices: f(wo -> wi) / n(wi)^2 = f(wi -> wo) / n(wo)^2
// (Veach 1997, section 5.2), with the Bsdf for the reverse direction built for the other side.
TEST(BsdfReciprocity, RefractionIsSymmetricUpToIndexSquared) {
  const ShadingFrame frame = tilted_frame();
  const float ior = 1.5f;
  SplitMix64 rng(8);
  for (float roughness : {0.2f, 0.5f, 1.0f}) {
    const BsdfInputs in{glm::vec3(1.0f), 0.0f, roughness, ior, 1.0f, glm::vec3(1.0f), 1.0f};
    const Bsdf from_outside(in, frame, true), from_inside(in, frame, false);
    int nonzero = 0;
    for (int i = 0; i < 3000; ++i) {
      glm::vec3 out = uniform_sphere(rng), inside = uniform_sphere(rng);  // outward normal convention
      if (glm::dot(out, frame.n) < 0.0f) out = -out;
      if (glm::dot(inside, frame.n) > 0.0f) inside = -inside;
      const glm::vec3 forward = from_outside.eval(out, inside) / std::abs(glm::dot(inside, frame.n)) / (ior * ior);
      const glm::vec3 backward = from_inside.eval(inside, out) / std::abs(glm::dot(out, frame.n));
      if (forward.x > 0.0f) ++nonzero;
      // Where `out` grazes the microfacet, `inside` is near the critical angle, and there the
      // transmittance 1 - F(cos) has an infinite slope: a rounding error of 1e-7 in the
      // cosine changes it by far more than 1e-7. Those pairs test float, not the BTDF.
      const glm::vec3 h = glm::normalize(out + ior * inside);
      if (std::abs(glm::dot(out, h)) < 0.1f) continue;
      ASSERT_LT(rel_diff(forward, backward), 2e-4f) << "roughness " << roughness;
    }
    EXPECT_GT(nonzero, 100);
  }
}

// Passing the outward normal with wo below it, or the normal flipped towards wo, is the same.
TEST(BsdfConventions, OutwardAndFaceForwardNormalsAgree) {
  const glm::vec3 n = glm::normalize(glm::vec3(-0.2f, 0.5f, 0.7f));
  const ShadingFrame outward = ShadingFrame::from_normal(n), flipped = ShadingFrame::from_normal(-n);
  SplitMix64 rng(9);
  for (const BsdfInputs& in : assorted_materials()) {
    const Bsdf a(in, outward, false), b(in, flipped, false);
    for (int i = 0; i < 100; ++i) {
      glm::vec3 wo = uniform_sphere(rng);
      if (glm::dot(wo, n) > 0.0f) wo = -wo;  // arriving from inside
      const glm::vec3 wi = uniform_sphere(rng);
      ASSERT_LT(rel_diff(a.eval(wo, wi), b.eval(wo, wi)), 1e-4f);
      ASSERT_LT(rel_diff(a.pdf(wo, wi), b.pdf(wo, wi)), 1e-4f);
      const float ul = rng.uniform();
      const glm::vec2 u(rng.uniform(), rng.uniform());
      const auto sa = a.sample(wo, ul, u), sb = b.sample(wo, ul, u);
      ASSERT_EQ(sa.has_value(), sb.has_value());
      if (!sa) continue;
      EXPECT_EQ(sa->transmitted, sb->transmitted);
      EXPECT_EQ(sa->delta, sb->delta);
      // The tangents differ, so a non-delta sample lands elsewhere; delta ones must agree.
      if (sa->delta) {
        EXPECT_LT(glm::length(sa->wi - sb->wi), 1e-5f);
      }
    }
  }
}

// ---- Robustness ------------------------------------------------------------------------

TEST(BsdfRobustness, NoNanOrInfAnywhere) {
  const ShadingFrame frame = ShadingFrame::from_normal({0.0f, 0.0f, 1.0f});
  std::vector<glm::vec3> dirs = {{0, 0, 1},  {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (float z : {1e-7f, 1e-4f, -1e-7f, -1e-4f, 0.9999999f}) dirs.push_back(glm::normalize(glm::vec3(1.0f, 0.3f, z)));
  // Subnormal heights above and below the tangent plane.
  for (float z : {1e-40f, -1e-40f}) dirs.push_back(glm::vec3(0.9578263f, 0.2873479f, z));
  SplitMix64 rng(10);
  for (int i = 0; i < 20; ++i) dirs.push_back(uniform_sphere(rng));
  const std::vector<float> us = {0.0f, 1e-7f, 0.5f, 0.99999994f};
  for (float roughness : {0.0f, 0.01f, 0.0316f, 0.032f, 0.5f, 1.0f}) {
    for (float ior : {1.0f, 1.0001f, 1.5f, 0.0f, 1e30f}) {
      for (const glm::vec3 color : {glm::vec3(0.0f), glm::vec3(1.0f)}) {
        for (float metallic : {0.0f, 1.0f}) {
          for (float transmission : {0.0f, 1.0f}) {
            for (float specular : {0.0f, 1.0f}) {
              const BsdfInputs in{color, metallic, roughness, ior, specular, glm::vec3(1.0f), transmission};
              for (bool entering : {true, false}) {
                const Bsdf bsdf(in, frame, entering);
                for (const glm::vec3& wo : dirs) {
                  for (const glm::vec3& wi : {dirs[0], dirs[5], dirs[7], -wo, wo, glm::vec3(-wo.x, -wo.y, wo.z)}) {
                    const glm::vec3 f = bsdf.eval(wo, wi);
                    const float p = bsdf.pdf(wo, wi);
                    ASSERT_TRUE(finite(f) && std::isfinite(p) && p >= 0.0f && std::min({f.x, f.y, f.z}) >= 0.0f)
                        << "roughness " << roughness << " ior " << ior << " wo.z " << wo.z << " wi.z " << wi.z;
                  }
                  for (float ul : us) {
                    for (size_t k = 0; k < us.size(); ++k) {
                      const auto s = bsdf.sample(wo, ul, {us[k], us[(k + 1) % us.size()]});
                      if (!s) continue;
                      ASSERT_TRUE(finite(s->weight) && finite(s->wi) && std::isfinite(s->pdf) && s->pdf > 0.0f)
                          << "roughness " << roughness << " ior " << ior << " wo.z " << wo.z;
                      ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-5f);
                    }
                  }
                }
              }
            }
          }
        }
      }
    }
  }
}

TEST(BsdfRobustness, OutOfRangeInputsAreClamped) {
  const ShadingFrame frame = ShadingFrame::from_normal({0.0f, 0.0f, 1.0f});
  const BsdfInputs wild{glm::vec3(2.0f, -1.0f, NAN), 1.5f, -3.0f, 1.5f, 7.0f, glm::vec3(-1.0f), 2.0f};
  const BsdfInputs tame{glm::vec3(1.0f, 0.0f, 0.0f), 1.0f, 0.0f, 1.5f, 1.0f, glm::vec3(0.0f), 1.0f};
  const Bsdf a(wild, frame, true), b(tame, frame, true);
  EXPECT_EQ(a.is_delta_only(), b.is_delta_only());
  const auto sa = a.sample(glm::normalize(glm::vec3(0.3f, 0.0f, 1.0f)), 0.5f, {0.5f, 0.5f});
  const auto sb = b.sample(glm::normalize(glm::vec3(0.3f, 0.0f, 1.0f)), 0.5f, {0.5f, 0.5f});
  ASSERT_TRUE(sa && sb);
  EXPECT_EQ(sa->weight, sb->weight);
  // A dielectric: clamped colours, metallic, roughness and specular; NaN and negative
  // specular colour channels give F0 = 0, an infinite one F0 = 1.
  const float inf = std::numeric_limits<float>::infinity();
  const BsdfInputs wild2{glm::vec3(0.5f, 2.0f, -1.0f), -1.0f, 2.0f, 1.5f, 0.5f, glm::vec3(NAN, -1.0f, inf), -1.0f};
  const BsdfInputs tame2{glm::vec3(0.5f, 1.0f, 0.0f), 0.0f, 1.0f, 1.5f, 0.5f, glm::vec3(0.0f, 0.0f, 25.0f), 0.0f};
  const Bsdf c(wild2, frame, true), d(tame2, frame, true);
  SplitMix64 rng(12);
  for (int i = 0; i < 100; ++i) {
    const glm::vec3 wo = uniform_sphere(rng), wi = uniform_sphere(rng);
    ASSERT_EQ(c.eval(wo, wi), d.eval(wo, wi));
    ASSERT_EQ(c.pdf(wo, wi), d.pdf(wo, wi));
  }
}

// ---- Frames ----------------------------------------------------------------------------

TEST(ShadingFrame, IsOrthonormalAndRoundTrips) {
  SplitMix64 rng(11);
  std::vector<glm::vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, glm::normalize(glm::vec3(1e-4f, 0, -1))};
  for (int i = 0; i < 200; ++i) normals.push_back(uniform_sphere(rng));
  for (const glm::vec3& n : normals) {
    const glm::vec3 any_tangent = uniform_sphere(rng);
    // from_orthonormal with the tangent evaluate_shading would give (orthogonal_tangent).
    const ShadingFrame frames[] = {ShadingFrame::from_normal(n), ShadingFrame::from_normal_tangent(n, any_tangent),
                                   ShadingFrame::from_normal_tangent(n, n), ShadingFrame::from_normal_tangent(n, {}),
                                   ShadingFrame::from_orthonormal(n, orthogonal_tangent(any_tangent, n))};
    for (const ShadingFrame& f : frames) {
      EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::length(f.b), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(f.b, f.n), 0.0f, 1e-5f);
      EXPECT_EQ(f.n, n);
      const glm::vec3 v = uniform_sphere(rng);
      EXPECT_LT(glm::length(f.to_world(f.to_local(v)) - v), 1e-5f);
      EXPECT_NEAR(f.to_local(n).z, 1.0f, 1e-5f);
    }
  }
  const glm::vec3 t = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
  const ShadingFrame f = ShadingFrame::from_normal_tangent({0.0f, 0.0f, 1.0f}, t + glm::vec3(0.0f, 0.0f, 0.5f));
  EXPECT_LT(glm::length(f.t - t), 1e-6f);
}

}  // namespace
}  // namespace lancer
