// The layer lobes of bsdf.h (KHR_materials_clearcoat, KHR_materials_sheen) under the same
// statistical tests as the base lobes (bsdf_sampling_test.cpp): chi-square goodness of fit
// of sample() against pdf() per case, Sidak-corrected over this file's cases, the rate of
// failed samples, and the white furnace (Monte Carlo albedo from the weights against the
// quadrature of eval(), at most 1, and exactly 1 where the model conserves energy). Plus the
// sheen albedo table against direct quadrature and the known values of a smooth coat.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
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
// How far the bilinear table of the sheen's directional albedo may be from the lobe's true
// albedo: the furnace of a white sheen over a white Lambert base is 1 up to this
// (SheenAlbedo.TableMatchesQuadrature measures it).
constexpr double kSheenTableError = 3e-3;

struct LayerCase {
  std::string name;
  BsdfInputs in;
  float theta_deg = 0.0f;
  bool lossless = false;  // the albedo must be 1 (up to kSheenTableError)
  bool at_most_one = true;
};

// Names built by appending: GCC 12 warns (-Wrestrict, a false positive) on "r" + temporary.
std::string angle_name(float a) { return std::to_string(static_cast<int>(a)) + "deg"; }
std::string roughness_name(float r) {
  std::string name = "r";
  name += std::to_string(static_cast<int>(std::lround(r * 100)));
  return name;
}

BsdfInputs lambert() { return {glm::vec3(1.0f), 0.0f, 0.7f, 1.5f, 0.0f}; }

std::vector<LayerCase> layer_cases() {
  std::vector<LayerCase> cases;
  const float angles[] = {0.0f, 30.0f, 60.0f, 85.0f};
  for (float r : {0.1f, 0.3f, 0.6f, 1.0f})
    for (float a : angles) {
      std::string suffix = "_";
      suffix += roughness_name(r);
      suffix += "_";
      suffix += angle_name(a);
      BsdfInputs sheen = lambert();
      sheen.sheen_color = glm::vec3(1.0f);
      sheen.sheen_roughness = r;
      cases.push_back({"sheen_white_lambert" + suffix, sheen, a, true});
      BsdfInputs coat = lambert();
      coat.clearcoat = 1.0f;
      coat.clearcoat_roughness = r;
      cases.push_back({"coat_lambert" + suffix, coat, a});
    }
  // Everything at once: a red sheen and a rough half coat over a rough plastic, and a coat
  // whose normal leans 20 degrees from the shading normal.
  BsdfInputs all{glm::vec3(0.2f, 0.5f, 0.9f), 0.3f, 0.4f, 1.5f, 1.0f};
  all.sheen_color = glm::vec3(1.0f, 0.2f, 0.1f);
  all.sheen_roughness = 0.5f;
  all.clearcoat = 0.5f;
  all.clearcoat_roughness = 0.2f;
  BsdfInputs tilted = lambert();
  tilted.clearcoat = 1.0f;
  tilted.clearcoat_roughness = 0.3f;
  const float lean = 20.0f * std::numbers::pi_v<float> / 180.0f;
  tilted.clearcoat_normal = glm::vec3(std::sin(lean), 0.0f, std::cos(lean));
  for (float a : angles) {
    cases.push_back({"all_layers_" + angle_name(a), all, a, false, a < 60.0f});
    cases.push_back({"coat_tilted_" + angle_name(a), tilted, a});
  }
  return cases;
}

float average(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char ch : s) h = (h ^ ch) * 0x100000001B3ull;
  return h;
}

struct Stats {
  std::vector<double> histogram;
  double failed = 0.0;
  int invalid = 0, delta = 0;
  double sum_w = 0.0, sum_w2 = 0.0;
  glm::dvec3 sum_rgb{0.0};
};

Stats draw(const Bsdf& bsdf, const glm::vec3& wo, const test::SphereBins& bins, int n, std::uint64_t seed) {
  Stats st;
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
    const int bin = bins.index(s->wi);
    const bool finite = std::isfinite(s->weight.x) && std::isfinite(s->weight.y) && std::isfinite(s->weight.z);
    if (bin < 0 || std::abs(glm::length(s->wi) - 1.0f) > 1e-4f || !finite ||
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

class BsdfLayers : public ::testing::TestWithParam<LayerCase> {};

TEST_P(BsdfLayers, ChiSquareAndWhiteFurnace) {
  const LayerCase& c = GetParam();
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f));  // identity, see bsdf_sampling_test
  const float theta = c.theta_deg * std::numbers::pi_v<float> / 180.0f;
  const glm::vec3 wo(std::sin(theta), 0.0f, std::cos(theta));
  const Bsdf bsdf(c.in, frame, true);
  ASSERT_TRUE(bsdf.layered());
  ASSERT_FALSE(bsdf.has_delta());

  const test::SphereBins bins;
  std::array<Stats, 2> parts;
  {
    std::vector<std::thread> workers;
    for (size_t k = 0; k < parts.size(); ++k)
      workers.emplace_back([&, k] { parts[k] = draw(bsdf, wo, bins, kSamples / 2, fnv1a(c.name) + k); });
    for (std::thread& w : workers) w.join();
  }
  Stats st = parts[0];
  for (size_t i = 0; i < st.histogram.size(); ++i) st.histogram[i] += parts[1].histogram[i];
  st.failed += parts[1].failed;
  st.invalid += parts[1].invalid;
  st.delta += parts[1].delta;
  st.sum_w += parts[1].sum_w;
  st.sum_w2 += parts[1].sum_w2;
  st.sum_rgb += parts[1].sum_rgb;
  ASSERT_EQ(st.delta, 0);
  ASSERT_EQ(st.invalid, 0) << "sample() returned non-finite or non-unit directions, or bad weights";

  // Peaks: the mirror direction about the shading normal and about the coat's normal.
  std::vector<glm::vec3> peaks = {glm::vec3(-wo.x, -wo.y, wo.z)};
  if (c.in.clearcoat_normal != glm::vec3(0.0f)) peaks.push_back(glm::reflect(-wo, c.in.clearcoat_normal));
  const test::BinIntegrals pdf_bins =
      test::integrate_bins_checked([&](const glm::vec3& d) { return bsdf.pdf(wo, d); }, bins, peaks, 1e-7);
  ASSERT_TRUE(pdf_bins.problem().empty()) << "pdf(): " << pdf_bins.problem();
  double total = 0.0;
  for (double p : pdf_bins.value) total += p;
  EXPECT_LT(total, 1.0 + 1e-4) << "pdf integrates to more than 1";
  const double fail_rate = std::max(0.0, 1.0 - total);
  EXPECT_NEAR(st.failed / kSamples, fail_rate, 5.0 * std::sqrt(std::max(fail_rate, 1.0 / kSamples) / kSamples) + 1e-4)
      << "sample() fails more or less often than pdf() implies";
  std::vector<double> expected(bins.size());
  for (int i = 0; i < bins.size(); ++i) expected[i] = (kSamples - st.failed) * pdf_bins.value[i] / total;
  for (int i = 0; i < bins.size(); ++i) {
    const double count_error = (kSamples - st.failed) * pdf_bins.error[i] / total;
    ASSERT_LE(count_error, 0.05 * std::sqrt(std::max(expected[i], 5.0)))
        << "bin " << i << ": quadrature error " << pdf_bins.error[i] << " too large for the chi-square test";
  }
  const double significance =
      test::sidak_significance(kFamilySignificance, static_cast<int>(layer_cases().size()));
  const test::Chi2Result chi2 = test::chi2_test(st.histogram, expected, significance);
  EXPECT_TRUE(chi2.message.empty()) << chi2.message;

  // White furnace.
  const double mc = st.sum_w / kSamples;
  const double sigma = std::sqrt(std::max(0.0, st.sum_w2 / kSamples - mc * mc) / kSamples);
  const glm::dvec3 mc_rgb = st.sum_rgb / static_cast<double>(kSamples);
  const test::SphereBins coarse{5, 8};
  const test::BinIntegrals albedo_bins = test::integrate_bins_checked(
      [&](const glm::vec3& d) { return average(bsdf.eval(wo, d)); }, coarse, peaks, 1e-6);
  ASSERT_TRUE(albedo_bins.problem().empty()) << "eval(): " << albedo_bins.problem();
  double quadrature = 0.0, quadrature_error = 0.0;
  for (int i = 0; i < coarse.size(); ++i) {
    quadrature += albedo_bins.value[i];
    quadrature_error += albedo_bins.error[i];
  }
  ASSERT_LT(quadrature_error, 1e-4) << "albedo quadrature not accurate enough";
  EXPECT_NEAR(mc, quadrature, 4.0 * sigma + 1e-4) << "Monte Carlo and quadrature albedos differ";
  if (c.at_most_one) {
    EXPECT_LE(std::max({mc_rgb.x, mc_rgb.y, mc_rgb.z}), 1.0 + 3.0 * sigma) << "albedo above 1";
  }
  if (c.lossless) {
    EXPECT_NEAR(mc, 1.0, 3.0 * sigma + kSheenTableError);
    EXPECT_NEAR(quadrature, 1.0, kSheenTableError);
  }
  std::printf("%-30s chi2 %7.1f dof %3d p %.3f  albedo mc %.4f +- %.4f quad %.4f  failed %.4f\n", c.name.c_str(),
              chi2.statistic, chi2.dof, chi2.p_value, mc, sigma, quadrature, st.failed / kSamples);
}

INSTANTIATE_TEST_SUITE_P(Cases, BsdfLayers, ::testing::ValuesIn(layer_cases()),
                         [](const ::testing::TestParamInfo<LayerCase>& p) { return p.param.name; });

// ---- Sheen albedo -------------------------------------------------------------------------

TEST(SheenAlbedo, TableMatchesQuadrature) {
  // Off the table's nodes (between them in both cos and roughness), against a finer
  // quadrature than the one that filled the table; and the finer one against adaptive
  // Simpson over the sphere, which shares no code with either.
  double worst = 0.0;
  for (float r : {0.1f, 0.33f, 0.5f, 0.77f, 0.95f})
    for (float c : {0.05f, 0.123f, 0.3f, 0.55f, 0.81f, 0.99f}) {
      const double reference = sheen_albedo_quadrature(c, r, 512);
      const double table = sheen_albedo(c, r);
      worst = std::max(worst, std::abs(table - reference));
      EXPECT_NEAR(table, reference, kSheenTableError) << "cos " << c << " roughness " << r;
    }
  std::printf("sheen albedo table: worst error %.2e\n", worst);
  for (float r : {0.2f, 0.8f}) {
    const float c = 0.4f;
    const glm::vec3 wo(std::sqrt(1.0f - c * c), 0.0f, c);
    const std::vector<double> bins = test::integrate_bins(
        [&](const glm::vec3& d) { return charlie_sheen(wo, d, r * r); }, test::SphereBins{4, 8}, {}, 1e-7);
    double simpson = 0.0;
    for (double b : bins) simpson += b;
    EXPECT_NEAR(sheen_albedo_quadrature(c, r, 512), simpson, 1e-4) << "roughness " << r;
  }
}

TEST(SheenAlbedo, ScalesTheBaseAndStaysInRange) {
  for (float r : {0.0f, 0.3f, 1.0f})
    for (float c : {0.0f, 0.01f, 0.5f, 1.0f}) {
      const float e = sheen_albedo(c, r);
      EXPECT_TRUE(std::isfinite(e));
      EXPECT_GE(e, 0.0f);
    }
  // A black sheen is no sheen: the Bsdf is the base itself.
  BsdfInputs in = lambert();
  in.sheen_roughness = 0.5f;
  EXPECT_FALSE(Bsdf(in, ShadingFrame::from_normal(glm::vec3(0, 0, 1)), true).layered());
  // A white sheen dims the white Lambert base by exactly 1 - E(cos_o).
  in.sheen_color = glm::vec3(1.0f);
  const Bsdf sheen(in, ShadingFrame::from_normal(glm::vec3(0, 0, 1)), true);
  const Bsdf base(lambert(), ShadingFrame::from_normal(glm::vec3(0, 0, 1)), true);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f));
  const glm::vec3 wi = glm::normalize(glm::vec3(-0.1f, 0.3f, 0.9f));
  const float e = sheen_albedo(0.8f, 0.5f);
  const float lobe = charlie_sheen(wo, wi, 0.25f);
  EXPECT_NEAR(sheen.eval(wo, wi).x, lobe + (1.0f - e) * base.eval(wo, wi).x, 1e-6f);
}

// ---- Clearcoat: known values --------------------------------------------------------------

TEST(Clearcoat, SmoothCoatOverBlackReflectsFourPercentAtNormalIncidence) {
  // Black dielectric without specular: the base scatters nothing; all that comes back is
  // the coat's mirror reflection, clearcoat * (0.04 + 0.96 (1 - cos)^5).
  BsdfInputs in{glm::vec3(0.0f), 0.0f, 0.5f, 1.5f, 0.0f};
  in.clearcoat = 1.0f;
  in.clearcoat_roughness = 0.0f;
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0, 0, 1));
  const Bsdf bsdf(in, frame, true);
  EXPECT_TRUE(bsdf.has_delta());
  EXPECT_TRUE(bsdf.is_delta_only());
  for (float cos_o : {1.0f, 0.5f, 0.1f}) {
    const glm::vec3 wo(std::sqrt(1.0f - cos_o * cos_o), 0.0f, cos_o);
    const auto s = bsdf.sample(wo, 0.5f, glm::vec2(0.3f, 0.7f));
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->delta);
    EXPECT_FALSE(s->transmitted);
    EXPECT_NEAR(glm::dot(s->wi, glm::vec3(-wo.x, -wo.y, wo.z)), 1.0f, 1e-6f);
    const float m = 1.0f - cos_o;
    EXPECT_NEAR(s->weight.x * s->pdf, 0.04f + 0.96f * m * m * m * m * m, 1e-6f) << "cos " << cos_o;
  }
  // Half a coat: half of it.
  in.clearcoat = 0.5f;
  const auto s = Bsdf(in, frame, true).sample(glm::vec3(0, 0, 1), 0.5f, glm::vec2(0.3f, 0.7f));
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->weight.x * s->pdf, 0.02f, 1e-6f);
}

TEST(Clearcoat, DimsTheBaseByOneMinusItsFresnelWeight) {
  BsdfInputs in = lambert();
  in.clearcoat = 0.8f;
  in.clearcoat_roughness = 0.0f;  // a delta coat: eval() is the dimmed base alone
  const ShadingFrame frame = ShadingFrame::from_normal(glm::vec3(0, 0, 1));
  const Bsdf coated(in, frame, true);
  const Bsdf base(lambert(), frame, true);
  const glm::vec3 wo = glm::normalize(glm::vec3(0.8f, 0.0f, 0.6f));
  const glm::vec3 wi = glm::normalize(glm::vec3(-0.2f, 0.1f, 0.9f));
  const float m = 0.4f;
  const float fc = 0.04f + 0.96f * m * m * m * m * m;
  EXPECT_NEAR(coated.eval(wo, wi).x, (1.0f - 0.8f * fc) * base.eval(wo, wi).x, 1e-6f);
  // The coat's delta sample comes with the probability it was chosen with.
  int deltas = 0;
  for (int i = 0; i < 100; ++i) {
    const auto s = coated.sample(wo, 0.5f, glm::vec2((i + 0.5f) / 100.0f, 0.5f));
    if (s && s->delta) {
      ++deltas;
      EXPECT_NEAR(s->weight.x * s->pdf, 0.8f * fc, 1e-6f);
    }
  }
  EXPECT_GT(deltas, 0);
  EXPECT_LT(deltas, 100);
}

TEST(Layers, WithoutLayersTheBsdfIsTheBase) {
  const BsdfInputs in{glm::vec3(0.9f, 0.6f, 0.8f), 0.25f, 0.45f, 1.33f, 0.8f, glm::vec3(1.0f, 0.6f, 0.3f), 0.5f};
  const ShadingFrame frame = ShadingFrame::from_normal(glm::normalize(glm::vec3(0.2f, -0.3f, 0.9f)));
  const Bsdf bsdf(in, frame, true);
  const BaseBsdf base(in, frame, true);
  EXPECT_FALSE(bsdf.layered());
  SplitMix64 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 wo = glm::normalize(glm::vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform()));
    const glm::vec3 wi = glm::normalize(glm::vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f));
    const BsdfEval a = bsdf.evaluate(wo, wi), b = base.evaluate(wo, wi);
    EXPECT_EQ(a.f, b.f);
    EXPECT_EQ(a.pdf, b.pdf);
    const float us = rng.uniform();
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const auto sa = bsdf.sample(wo, us, u), sb = base.sample(wo, us, u);
    ASSERT_EQ(sa.has_value(), sb.has_value());
    if (sa) {
      EXPECT_EQ(sa->wi, sb->wi);
      EXPECT_EQ(sa->weight, sb->weight);
      EXPECT_EQ(sa->pdf, sb->pdf);
    }
  }
}

}  // namespace
}  // namespace lancer
