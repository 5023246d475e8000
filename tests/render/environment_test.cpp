// Environment light: the equirectangular convention, lookups, the sampling density
// (normalisation, agreement between sample() and pdf(), chi-square fit, an importance-
// sampled integral against the exact sum over pixels), constant environments, and the
// refusal of unreadable or non-physical maps.
#include "render/environment.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/chi2_support.h"
#include "render/color.h"
#include "render/image_io.h"
#include "simd/splitmix64.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
constexpr int kW = 32, kH = 16;

// A dim sky that varies in colour by row and column, a bright 3 x 2 spot, and a black
// patch (never to be sampled).
ImageRGB spot_map() {
  ImageRGB im(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      im.set(x, y, {0.05f + 0.02f * static_cast<float>(y), 0.1f + 0.003f * static_cast<float>(x), 0.2f});
  for (int y = 5; y < 7; ++y)
    for (int x = 20; x < 23; ++x) im.set(x, y, {400.0f, 300.0f, 120.0f});
  for (int y = 12; y < 14; ++y)
    for (int x = 2; x < 6; ++x) im.set(x, y, {0.0f, 0.0f, 0.0f});
  return im;
}

class EnvironmentFiles : public ::testing::Test {
 protected:
  test::TempDir temp_{"lancer_env"};
  const fs::path& dir_ = temp_.path();
};

glm::dvec2 pixel_centre_uv(int x, int y) { return {(x + 0.5) / kW, (y + 0.5) / kH}; }

TEST(Environment, DirectionConvention) {
  auto expect_dir = [](double u, double v, glm::vec3 want) {
    const glm::vec3 d = equirect_direction(u, v);
    EXPECT_NEAR(d.x, want.x, 1e-6f) << u << ", " << v;
    EXPECT_NEAR(d.y, want.y, 1e-6f) << u << ", " << v;
    EXPECT_NEAR(d.z, want.z, 1e-6f) << u << ", " << v;
  };
  expect_dir(0.5, 0.5, {0, 0, -1});   // image centre: -z, where a glTF camera looks
  expect_dir(0.75, 0.5, {1, 0, 0});   // to the right of centre: +x
  expect_dir(0.25, 0.5, {-1, 0, 0});
  expect_dir(0.0, 0.5, {0, 0, 1});    // the seam: +z
  expect_dir(0.3, 0.0, {0, 1, 0});    // top row: +y
  expect_dir(0.3, 1.0, {0, -1, 0});   // bottom row: -y
  // Round trip away from the seam and the poles, and independence of the length.
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const glm::dvec2 uv = pixel_centre_uv(x, y);
      const glm::vec3 d = equirect_direction(uv.x, uv.y);
      EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
      const glm::dvec2 back = equirect_uv(d * 7.5f);
      EXPECT_NEAR(back.x, uv.x, 1e-6);
      EXPECT_NEAR(back.y, uv.y, 1e-6);
    }
}

TEST(Environment, NearestPixelLookupWithScale) {
  ImageRGB im(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) im.set(x, y, {float(x), float(y), 1.0f});
  const Environment env(im, 2.0f, "ramp");
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (double du : {0.1, 0.5, 0.9})
        for (double dv : {0.1, 0.5, 0.9}) {
          const glm::vec3 d = equirect_direction((x + du) / kW, (y + dv) / kH);
          EXPECT_EQ(env.radiance(d), 2.0f * glm::vec3(float(x), float(y), 1.0f)) << x << ", " << y;
        }
  EXPECT_EQ(env.radiance({0, 0, -3}), 2.0f * glm::vec3(kW / 2, kH / 2, 1)) << "-z is the image centre";
  EXPECT_EQ(env.radiance({0, 1, 0}).y, 0.0f) << "+y is the top row";
  EXPECT_EQ(env.radiance({0, -1, 0}).y, 2.0f * (kH - 1)) << "-y is the bottom row";
}

// Integral of pdf over the sphere, by the midpoint rule in (phi, theta) on a grid aligned
// with the pixels (exact: pdf sin(theta) is constant inside each pixel) and on an
// unaligned grid in (phi, cos theta).
void expect_normalised(const Environment& env) {
  double aligned = 0.0;
  constexpr int kSub = 3;
  const double dphi = 2 * kPi / (kW * kSub), dtheta = kPi / (kH * kSub);
  for (int j = 0; j < kH * kSub; ++j)
    for (int i = 0; i < kW * kSub; ++i) {
      const double u = (i + 0.5) / (kW * kSub), v = (j + 0.5) / (kH * kSub);
      aligned += env.pdf(equirect_direction(u, v)) * std::sin(kPi * v) * dphi * dtheta;
    }
  EXPECT_NEAR(aligned, 1.0, 1e-5);

  // Jittered: a midpoint grid that does not follow the pixel edges makes an error of up
  // to half a cell per edge, systematic along a straight edge (about 1 % for the spot);
  // one random point per cell makes those errors independent (and far smaller in sum).
  double unaligned = 0.0;
  constexpr int kN = 1000;
  const double dz = 2.0 / kN, dp = 2 * kPi / (2 * kN);
  SplitMix64 jitter(77);
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < 2 * kN; ++i) {
      const double z = -1.0 + (j + jitter.uniform()) * dz, phi = (i + jitter.uniform()) * dp;
      const double r = std::sqrt(std::max(0.0, 1 - z * z));
      const glm::vec3 d(static_cast<float>(r * std::cos(phi)), static_cast<float>(z), static_cast<float>(r * std::sin(phi)));
      unaligned += env.pdf(d) * dz * dp;
    }
  EXPECT_NEAR(unaligned, 1.0, 2e-3);
}

TEST(Environment, PdfIntegratesToOne) {
  expect_normalised(Environment(spot_map(), 1.0f, "spot"));
  expect_normalised(Environment(ImageRGB(kW, kH), 1.0f, "black"));  // all black: uniform in (u, v)
}

// Everything a sample says agrees with pdf(), radiance(), and with the density computed
// here from the pixels: luminance * sin(theta_row) / sum * W H / (2 pi^2 sin(theta)).
TEST(Environment, SamplesAgreeWithPdfAndRadiance) {
  const ImageRGB im = spot_map();
  const Environment env(im, 3.0f, "spot");
  std::vector<double> w(kW * kH), row_total(kH, 0.0);
  double total = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      w[y * kW + x] = luminance(im.at(x, y)) * std::sin(kPi * (y + 0.5) / kH);
      row_total[y] += w[y * kW + x];
      total += w[y * kW + x];
    }
  SplitMix64 rng(11);
  for (int i = 0; i < 100000; ++i) {
    const glm::vec2 u(rng.uniform(), rng.uniform());
    const EnvSample s = env.sample(u);
    ASSERT_NEAR(glm::length(s.dir), 1.0f, 1e-5f);
    ASSERT_GT(s.pdf, 0.0f) << "u = (" << u.x << ", " << u.y << ")";
    ASSERT_EQ(s.pdf, env.pdf(s.dir));
    ASSERT_EQ(s.radiance, env.radiance(s.dir));
    const glm::dvec2 uv = equirect_uv(s.dir);
    const int x = std::min(kW - 1, int(uv.x * kW)), y = std::min(kH - 1, int(uv.y * kH));
    ASSERT_GT(w[y * kW + x], 0.0) << "a black pixel was sampled: " << x << ", " << y;
    ASSERT_EQ(s.radiance, 3.0f * im.at(x, y));
    const double sin_theta = std::sqrt(double(s.dir.x) * s.dir.x + double(s.dir.z) * s.dir.z) / glm::length(s.dir);
    const double want = w[y * kW + x] / total * (kW * kH) / (2 * kPi * kPi * sin_theta);
    // The distribution stores float CDFs (entries within 2^-25 of exact), so a bin's
    // probability is off by up to 2^-24 absolute, in the row's conditional and in the
    // marginal: a relative error 2^-24 / p that matters for dim pixels beside the spot.
    const double p_conditional = w[y * kW + x] / row_total[y], p_marginal = row_total[y] / total;
    const double tolerance = 1e-5 + 0x1p-24 / p_conditional + 0x1p-24 / p_marginal;
    ASSERT_NEAR(s.pdf / want, 1.0, tolerance) << "pixel " << x << ", " << y;
  }
}

// Pearson's test of sampled directions against the probabilities pdf() gives to each of
// 2 x 2 sub-cells per pixel (exact by the aligned midpoint rule).
TEST(Environment, SampledDirectionsFitThePdf) {
  const Environment env(spot_map(), 1.0f, "spot");
  constexpr int kCols = 2 * kW, kRows = 2 * kH, kSamples = 400000;
  std::vector<double> expected(kCols * kRows), observed(kCols * kRows, 0.0);
  for (int j = 0; j < kRows; ++j)
    for (int i = 0; i < kCols; ++i) {
      const double u = (i + 0.5) / kCols, v = (j + 0.5) / kRows;
      expected[j * kCols + i] =
          kSamples * env.pdf(equirect_direction(u, v)) * std::sin(kPi * v) * (2 * kPi / kCols) * (kPi / kRows);
    }
  SplitMix64 rng(2024);
  for (int n = 0; n < kSamples; ++n) {
    const EnvSample s = env.sample({rng.uniform(), rng.uniform()});
    const glm::dvec2 uv = equirect_uv(s.dir);
    const int i = std::min(kCols - 1, int(uv.x * kCols)), j = std::min(kRows - 1, int(uv.y * kRows));
    observed[j * kCols + i] += 1.0;
  }
  const test::Chi2Result r = test::chi2_test(observed, expected, 1e-3);
  EXPECT_TRUE(r.message.empty()) << r.message;
  EXPECT_GT(r.dof, 100);
}

// With importance sampling, mean(radiance / pdf) estimates the integral of the radiance
// over the sphere, which for a nearest-pixel map is exactly the sum over pixels of the
// pixel's radiance times its solid angle, dphi (cos theta0 - cos theta1).
TEST(Environment, ImportanceSampledIntegralMatchesThePixelSum) {
  const ImageRGB im = spot_map();
  const Environment env(im, 1.0f, "spot");
  glm::dvec3 exact(0.0);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double solid_angle = (2 * kPi / kW) * (std::cos(kPi * y / kH) - std::cos(kPi * (y + 1) / kH));
      exact += glm::dvec3(im.at(x, y)) * solid_angle;
    }
  constexpr int kN = 200000;
  glm::dvec3 sum(0.0), sum_sq(0.0);
  SplitMix64 rng(99);
  for (int n = 0; n < kN; ++n) {
    const EnvSample s = env.sample({rng.uniform(), rng.uniform()});
    const glm::dvec3 f = s.pdf > 0 ? glm::dvec3(s.radiance) / double(s.pdf) : glm::dvec3(0.0);
    sum += f;
    sum_sq += f * f;
  }
  const glm::dvec3 mean = sum / double(kN);
  for (int c = 0; c < 3; ++c) {
    const double stderr_c = std::sqrt((sum_sq[c] / kN - mean[c] * mean[c]) / kN);
    EXPECT_LT(stderr_c, 0.01 * exact[c]) << "channel " << c << ": the estimate should be tight";
    EXPECT_NEAR(mean[c], exact[c], 4 * stderr_c + 1e-9 * exact[c]) << "channel " << c;
  }
}

TEST(Environment, ConstantEnvironmentIsUniform) {
  const Environment env(glm::vec3(0.5f, 1.0f, 2.0f));
  EXPECT_TRUE(env.is_constant());
  const float quarter_over_pi = static_cast<float>(1.0 / (4.0 * kPi));
  EXPECT_EQ(env.pdf({0, 1, 0}), quarter_over_pi);
  EXPECT_EQ(env.pdf({0.3f, -0.2f, 5.0f}), quarter_over_pi);
  EXPECT_EQ(env.radiance({1, 0, 0}), glm::vec3(0.5f, 1.0f, 2.0f));
  SplitMix64 rng(5);
  glm::dvec3 mean(0.0);
  double mean_y2 = 0;
  constexpr int kN = 100000;
  std::vector<double> octant(8, 0.0);
  for (int n = 0; n < kN; ++n) {
    const EnvSample s = env.sample({rng.uniform(), rng.uniform()});
    ASSERT_NEAR(glm::length(s.dir), 1.0f, 1e-5f);
    ASSERT_EQ(s.pdf, quarter_over_pi);
    ASSERT_EQ(s.radiance, glm::vec3(0.5f, 1.0f, 2.0f));
    mean += glm::dvec3(s.dir);
    mean_y2 += double(s.dir.y) * s.dir.y;
    octant[(s.dir.x > 0) + 2 * (s.dir.y > 0) + 4 * (s.dir.z > 0)] += 1;
  }
  EXPECT_NEAR(mean.x / kN, 0.0, 0.01);
  EXPECT_NEAR(mean.y / kN, 0.0, 0.01);
  EXPECT_NEAR(mean.z / kN, 0.0, 0.01);
  EXPECT_NEAR(mean_y2 / kN, 1.0 / 3.0, 0.01);
  const test::Chi2Result r = test::chi2_test(octant, std::vector<double>(8, kN / 8.0), 1e-3);
  EXPECT_TRUE(r.message.empty()) << r.message;
  EXPECT_THROW(Environment(glm::vec3(-1.0f, 0.0f, 0.0f)), std::invalid_argument);
  EXPECT_THROW(Environment(glm::vec3(NAN, 0.0f, 0.0f)), std::invalid_argument);
}

TEST(Environment, PolesHaveNoDensity) {
  const Environment env(spot_map(), 1.0f, "spot");
  EXPECT_EQ(env.pdf({0, 1, 0}), 0.0f);
  EXPECT_EQ(env.pdf({0, -2, 0}), 0.0f);
  const EnvSample top = env.sample({0.5f, 0.0f});  // may land exactly on the pole
  EXPECT_TRUE(std::isfinite(top.pdf));
  EXPECT_TRUE(std::isfinite(top.dir.x) && std::isfinite(top.dir.y) && std::isfinite(top.dir.z));
}

TEST_F(EnvironmentFiles, ReadsAnExrMap) {
  const fs::path file = dir_ / "sky.exr";
  write_image(spot_map(), file);
  const Environment env(file, 0.5f);
  EXPECT_FALSE(env.is_constant());
  EXPECT_EQ(env.image().width, kW);
  EXPECT_EQ(env.image().height, kH);
  const glm::dvec2 uv = pixel_centre_uv(21, 5);
  EXPECT_EQ(env.radiance(equirect_direction(uv.x, uv.y)), 0.5f * glm::vec3(400.0f, 300.0f, 120.0f));
  expect_normalised(env);
}

void expect_image_error(const std::function<void()>& f, const std::string& file, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error for " << file;
  } catch (const ImageError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file), std::string::npos) << what;
    EXPECT_NE(what.find(part), std::string::npos) << "expected '" << part << "' in: " << what;
  }
}

TEST_F(EnvironmentFiles, BadFilesAreClearErrors) {
  const fs::path missing = dir_ / "missing.exr";
  expect_image_error([&] { Environment env(missing, 1.0f); }, missing.string(), "");

  const fs::path text = dir_ / "not_really.exr";
  std::ofstream(text) << "this is not an OpenEXR file\n";
  expect_image_error([&] { Environment env(text, 1.0f); }, text.string(), "");

  struct Bad {
    const char* name;
    float value;
    const char* says;
  };
  for (const Bad& bad : {Bad{"nan.exr", NAN, "NaN"}, Bad{"inf.exr", INFINITY, "infinite"},
                         Bad{"negative.exr", -0.25f, "negative"}}) {
    ImageRGB im = spot_map();
    im.rgb[(7 * kW + 9) * 3 + 1] = bad.value;  // pixel (9, 7), green
    const fs::path file = dir_ / bad.name;
    write_image(im, file);
    expect_image_error([&] { Environment env(file, 1.0f); }, file.string(), bad.says);
    expect_image_error([&] { Environment env(file, 1.0f); }, file.string(), "(9, 7)");
  }

  const fs::path good = dir_ / "good.exr";
  write_image(spot_map(), good);
  expect_image_error([&] { Environment env(good, -1.0f); }, good.string(), "scale");
  expect_image_error([&] { Environment env(good, NAN); }, good.string(), "scale");
  expect_image_error([&] { Environment env(good, 1e38f); }, good.string(), "overflow");
}

}  // namespace
}  // namespace lancer
