// The path tracer's noise on the Cornell box with a mirror and a glass sphere
// (scenes/cornell-box-spheres.gltf), at 32 x 32 pixels:
//  (a) no NaN or infinity (and no negative value) in the 64-spp images, nor in the image
//      after any pass of one of them (the integrator drops a non-finite sample before it
//      reaches the pixel sums, path.cpp; this checks nothing else lets one through);
//  (b) fireflies stay within a stated bound, per sample and per pixel (see FirefliesStayBounded);
//  (c) the error falls like 1 / sqrt(spp): the fitted log-log slope of the RMS error at 4, 16
//      and 64 spp lies in [-0.75, -0.45] (see ErrorFallsLikeOneOverSqrtSpp).
// The error is measured without a reference image, as the spread between renders with
// independent seeds: the variance of an spp-N pixel across seeds is exactly its mean squared
// error (the estimator is unbiased), and a reference would add its own noise to every level.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

constexpr int kSize = 32;
constexpr int kSeeds = 4;  // independent renders per sample count
constexpr int kMaxDepth = 8;

struct Cornell {
  Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  KdTree kd{scene.triangles};
  float max_emission = 0.0f;  // the brightest emitted radiance, any channel (17, red)

  Cornell() {
    for (const Material& m : scene.materials) {
      const glm::vec3 e = m.emission();
      max_emission = std::max({max_emission, e.x, e.y, e.z});
    }
  }

  ImageRGB render(int spp, std::uint64_t seed, const RenderControl& control = {}) const {
    const PinholeCamera cam = PinholeCamera::from_desc(scene.cameras.at(0), kSize, kSize);
    RenderSettings s;
    s.width = kSize;
    s.height = kSize;
    s.spp = spp;
    s.integrator = IntegratorKind::Path;
    s.max_depth = kMaxDepth;
    s.seed = seed;
    RenderStats stats;
    return render_image(scene, kd, cam, s, stats, {}, control);
  }
};

const Cornell& cornell() {
  static const Cornell c;
  return c;
}

// Renders at 4, 16 and 64 spp, kSeeds each, made on first use and shared by the tests (so a
// test run alone renders only what it needs).
class Renders {
 public:
  static constexpr int kLevels[] = {4, 16, 64};

  // The kSeeds renders at `spp` (one of kLevels), seeds 1..kSeeds.
  const std::vector<ImageRGB>& at(int spp) {
    std::vector<ImageRGB>& images = images_[level_index(spp)];
    for (int k = static_cast<int>(images.size()); k < kSeeds; ++k) {
      const std::uint64_t seed = 1 + static_cast<std::uint64_t>(k);
      if (spp == 64 && k == 0) {
        RenderControl control;
        control.checkpoint_s = 1e-12;  // after every pass
        control.on_checkpoint = [&](const ImageRGB& image, int) { passes_.push_back(image); };
        images.push_back(cornell().render(spp, seed, control));
        passes_.push_back(images.back());
      } else {
        images.push_back(cornell().render(spp, seed));
      }
    }
    return images;
  }
  // The 64-spp render with seed 1 pass by pass: passes()[k] is the image after k + 1 passes.
  const std::vector<ImageRGB>& passes() {
    at(64);
    return passes_;
  }

 private:
  static std::size_t level_index(int spp) {
    const auto* it = std::find(std::begin(kLevels), std::end(kLevels), spp);
    if (it == std::end(kLevels)) throw std::invalid_argument("no renders at " + std::to_string(spp) + " spp");
    return static_cast<std::size_t>(it - std::begin(kLevels));
  }
  std::vector<ImageRGB> images_[std::size(kLevels)];
  std::vector<ImageRGB> passes_;
};

Renders& renders() {
  static Renders r;
  return r;
}

double image_mean(const ImageRGB& image) {
  double sum = 0.0;
  for (float v : image.rgb) sum += v;
  return sum / static_cast<double>(image.rgb.size());
}

TEST(PathNoise, NoNaNOrInfinityInAnyImage) {
  std::size_t non_finite = 0, negative = 0, values = 0;
  for (const std::vector<ImageRGB>* images : {&renders().at(64), &renders().passes()})
    for (const ImageRGB& image : *images)
      for (float v : image.rgb) {
        non_finite += !std::isfinite(v);
        negative += v < 0.0f;
        ++values;
      }
  EXPECT_EQ(non_finite, 0u) << "of " << values << " values";
  EXPECT_EQ(negative, 0u) << "of " << values << " values";
  EXPECT_GT(image_mean(renders().at(64).front()), 0.05) << "the box is lit";
}

// Fireflies are single samples far brighter than their pixel's mean. The bound has two parts.
// 1. A ceiling on every sample: Le (1 + 1.5 max_depth) = 221, Le = 17 the brightest emitted
//    radiance. A sample adds emission along one path of at most max_depth bounces. The
//    camera ray's own hit adds at most Le. Each bounce adds a next-event term and a BSDF-hit
//    term; the power heuristic bounds the first by beta Le w / 2 (w / p_light <= 1 / (2 p_bsdf))
//    and the second by beta Le w, with the BSDF weight w = f cos / p_bsdf about 1 at most here
//    (albedos <= 0.95, lossless glass; the glTF layering gains a little at grazing angles) and
//    the throughput beta <= 1 (Russian roulette rescales it to at most 1, which is also why one
//    path can meet the light at full strength twice: 34 is seen on a light pixel).
//    A weight blow-up (a pdf that disagrees with its sampler, a division by a vanishing pdf)
//    lands far above. The samples come from the 64-spp render's pass-by-pass images (the
//    image after k passes is the spp = k image): s_k = k I_k - (k - 1) I_(k-1).
// 2. The firefly bound proper, per pixel at 64 spp: no pixel outside the light and its
//    images in the mirror and glass sphere (the pixels whose 192-spp reference exceeds 0.5,
//    about 4x the image mean) is brighter than 20x the image mean (2.7). Such a pixel would
//    need its samples to sum to over 170 against an expectation of at most 32: about eight
//    full-strength sightings of the light (<= Le each, caustics through the glass, rarely two
//    per path) beyond an expected count under two; the Poisson tail of that is below 1e-4 per
//    pixel even when the whole pixel value comes from such rare sightings. The brightest such
//    pixel measures about 6x the mean.
TEST(PathNoise, FirefliesStayBounded) {
  const double le = cornell().max_emission;
  ASSERT_NEAR(le, 17.0, 1e-4);
  const std::vector<ImageRGB>& passes = renders().passes();
  ASSERT_EQ(passes.size(), 64u);

  double max_sample = 0.0;
  std::size_t at = 0;
  int above_le = 0;  // samples that met the light more than once at full strength
  for (std::size_t k = 0; k < passes.size(); ++k)
    for (std::size_t i = 0; i < passes[k].rgb.size(); ++i) {
      const double now = static_cast<double>(k + 1) * passes[k].rgb[i];
      const double before = k == 0 ? 0.0 : static_cast<double>(k) * passes[k - 1].rgb[i];
      above_le += now - before > 1.1 * le;
      if (now - before > max_sample) {
        max_sample = now - before;
        at = i / 3;
      }
    }
  const double ceiling = le * (1.0 + 1.5 * kMaxDepth);
  EXPECT_LE(max_sample, ceiling) << "a firefly at pixel (" << at % kSize << ", " << at / kSize << ")";

  const std::vector<ImageRGB>& full = renders().at(64);
  ImageRGB reference(kSize, kSize);  // the other seeds' mean: 192 spp, independent of full[0]
  for (int k = 1; k < kSeeds; ++k)
    for (std::size_t i = 0; i < reference.rgb.size(); ++i) reference.rgb[i] += full[k].rgb[i] / (kSeeds - 1);
  const double mean = image_mean(reference);
  int light_pixels = 0, brightest = -1;
  float brightest_value = 0.0f;
  for (std::size_t p = 0; p < reference.rgb.size() / 3; ++p) {
    const float* ref = &reference.rgb[3 * p];
    if (std::max({ref[0], ref[1], ref[2]}) > 0.5f) {
      ++light_pixels;
      continue;
    }
    for (int c = 0; c < 3; ++c)
      if (full[0].rgb[3 * p + c] > brightest_value) {
        brightest_value = full[0].rgb[3 * p + c];
        brightest = static_cast<int>(p);
      }
  }
  EXPECT_LT(light_pixels, kSize * kSize / 20) << "the light covers more of the image than expected";
  EXPECT_LE(brightest_value, 20.0 * mean) << "pixel (" << brightest % kSize << ", " << brightest / kSize << ")";
  std::printf("brightest sample %.2f (ceiling %.0f), %d of %zu above 1.1 Le; "
              "brightest pixel off the light %.3f = %.1fx the mean %.4f (%d light pixels)\n",
              max_sample, ceiling, above_le, passes.size() * passes[0].rgb.size(), brightest_value,
              brightest_value / mean, mean, light_pixels);
}

// RMS error of an spp-N render: the square root of the per-value variance across the
// kSeeds independent renders (unbiased, n - 1), averaged over all pixels and channels.
double rms_error(const std::vector<ImageRGB>& seeds) {
  const std::size_t n = seeds.front().rgb.size();
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0.0, sum2 = 0.0;
    for (const ImageRGB& image : seeds) {
      sum += image.rgb[i];
      sum2 += static_cast<double>(image.rgb[i]) * image.rgb[i];
    }
    const double k = static_cast<double>(seeds.size());
    total += std::max(0.0, (sum2 - sum * sum / k) / (k - 1.0));
  }
  return std::sqrt(total / static_cast<double>(n));
}

// Plain Monte Carlo has RMS error sigma / sqrt(N): slope -0.5 in log-log. The sampler is
// Owen-scrambled Sobol', which converges faster on the smooth low-dimensional parts of the
// integrand; for integrands with discontinuities (visibility, the light's edge) scrambled
// nets reach at best an RMS error of N^(-1/2 - 1/(2d)), -0.75 in two dimensions (Owen 1997,
// "Scrambled net variance for integrals of smooth functions"; He & Owen 2015 for
// discontinuous ones). So the slope must lie in [-0.75, -0.45]: flatter than -0.45 means
// samples that repeat or correlate across passes or seeds, or an error that does not average
// out; steeper than -0.75 is more than any sampler can give a path tracer. 0.05 of slack
// on the -0.5 side covers the estimate's own noise (kSeeds x 3072 values per level).
TEST(PathNoise, ErrorFallsLikeOneOverSqrtSpp) {
  std::vector<double> x, y;
  for (int spp : Renders::kLevels) {
    const double e = rms_error(renders().at(spp));
    ASSERT_GT(e, 0.0) << "renders with different seeds are identical at " << spp << " spp";
    x.push_back(std::log(static_cast<double>(spp)));
    y.push_back(std::log(e));
    std::printf("%3d spp: RMS error %.5f\n", spp, e);
  }
  // Least-squares slope of y over x.
  const double n = static_cast<double>(x.size());
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::printf("fitted slope %.3f\n", slope);
  EXPECT_GE(slope, -0.75);
  EXPECT_LE(slope, -0.45);
}

}  // namespace
}  // namespace lancer
