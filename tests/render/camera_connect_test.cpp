// PinholeCamera::connect, the adjoint of generate() that light tracing joins points with:
//  - it finds the pixel and lens point whose ray reaches the point (pinhole, thin lens
//    focused near or at infinity), and refuses points behind the camera, outside the image,
//    and any point for an orthographic camera;
//  - its importance is normalised: integrated over a plane that fills the view (times the
//    cosine at the plane), every pixel gets 1, whatever the lens.
#include "render/camera.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace lancer {
namespace {

PinholeCamera test_camera(float aperture, float focus) {
  PinholeCamera cam = PinholeCamera::look_at(glm::vec3(0.3f, -0.2f, 2.0f), glm::vec3(0.1f, 0.2f, 0.0f),
                                             glm::vec3(0.0f, 1.0f, 0.0f), 0.8f, 12, 9);
  if (aperture > 0.0f) cam.set_thin_lens(aperture, focus);
  return cam;
}

TEST(CameraConnect, FindsThePixelAndLensPointOfTheRayThroughThePoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const float inf = std::numeric_limits<float>::infinity();
  for (const auto& [aperture, focus] : {std::pair{0.0f, inf}, std::pair{0.05f, 1.7f}, std::pair{0.05f, inf}}) {
    const PinholeCamera cam = test_camera(aperture, focus);
    for (int k = 0; k < 500; ++k) {
      // Away from pixel borders, where rounding may pick the neighbour.
      const int px = static_cast<int>(u01(rng) * 12.0f) % 12, py = static_cast<int>(u01(rng) * 9.0f) % 9;
      const float i = float(px) + 0.05f + 0.9f * u01(rng), j = float(py) + 0.05f + 0.9f * u01(rng);
      const glm::vec2 lens_u(u01(rng), u01(rng));
      const Ray ray = cam.generate(i, j, lens_u);
      const glm::vec3 p = ray.org + (0.5f + 3.0f * u01(rng)) * ray.dir;
      const CameraPoint c = cam.connect(p, lens_u);
      ASSERT_TRUE(c.valid) << "aperture " << aperture << " focus " << focus;
      EXPECT_EQ(c.x, px);
      EXPECT_EQ(c.y, py);
      EXPECT_LT(glm::length(c.lens - ray.org), 1e-5f);
      EXPECT_GT(c.importance, 0.0f);
    }
  }
}

TEST(CameraConnect, RefusesPointsItCannotSee) {
  const PinholeCamera cam = test_camera(0.0f, std::numeric_limits<float>::infinity());
  const glm::vec3 ahead = cam.origin() + cam.forward();
  EXPECT_TRUE(cam.connect(ahead, glm::vec2(0.5f)).valid);
  EXPECT_FALSE(cam.connect(cam.origin() - cam.forward(), glm::vec2(0.5f)).valid) << "behind";
  EXPECT_FALSE(cam.connect(cam.origin() + 0.5f * cam.x_axis(), glm::vec2(0.5f)).valid) << "in the lens plane";
  EXPECT_FALSE(cam.connect(ahead + 1.01f * cam.x_axis(), glm::vec2(0.5f)).valid) << "right of the image";
  EXPECT_FALSE(cam.connect(ahead - 1.01f * cam.y_axis(), glm::vec2(0.5f)).valid) << "above the image";
  CameraDesc ortho;
  ortho.orthographic = true;
  ortho.xmag = ortho.ymag = 1.0f;
  const PinholeCamera o = PinholeCamera::from_desc(ortho, 4, 4);
  EXPECT_FALSE(o.connect(o.origin() + o.forward(), glm::vec2(0.5f)).valid) << "orthographic";
}

// (1 / A) times the image-plane area a patch of the plane covers is what the pixel's mean
// over its area weighs the patch by: summed over a plane filling the view, 1 per pixel.
TEST(CameraConnect, ImportanceIntegratesToOnePerPixel) {
  const float inf = std::numeric_limits<float>::infinity();
  for (const auto& [aperture, focus] : {std::pair{0.0f, inf}, std::pair{0.1f, 1.5f}}) {
    const PinholeCamera cam = test_camera(aperture, focus);
    // A plane 3 units in front of the camera, facing it, tilted, much larger than the view.
    const glm::vec3 centre = cam.origin() + 3.0f * cam.forward();
    const glm::vec3 n = glm::normalize(-cam.forward() + 0.3f * glm::normalize(cam.x_axis()));
    const glm::vec3 a = glm::normalize(glm::cross(n, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 b = glm::cross(n, a);
    constexpr float kHalf = 6.0f;
    constexpr int kGrid = 2000, kLens = 2;  // points on the plane and lens points, both stratified
    std::vector<double> per_pixel(12 * 9, 0.0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const int lens_samples = aperture > 0.0f ? kLens * kLens : 1;
    const double cell = double(2.0f * kHalf / kGrid) * double(2.0f * kHalf / kGrid) / lens_samples;
    for (int y = 0; y < kGrid; ++y)
      for (int x = 0; x < kGrid; ++x) {
        const float s = -kHalf + 2.0f * kHalf * (float(x) + u01(rng)) / kGrid;
        const float t = -kHalf + 2.0f * kHalf * (float(y) + u01(rng)) / kGrid;
        const glm::vec3 p = centre + s * a + t * b;
        for (int l = 0; l < lens_samples; ++l) {
          const glm::vec2 lens_u((float(l % kLens) + u01(rng)) / kLens, (float(l / kLens) + u01(rng)) / kLens);
          const CameraPoint c = cam.connect(p, lens_u);
          if (!c.valid) continue;
          const float cos_p = std::abs(glm::dot(glm::normalize(c.lens - p), n));
          per_pixel[std::size_t(c.y) * 12 + std::size_t(c.x)] += double(c.importance) * cos_p * cell;
        }
      }
    // About 2,000 plane points per pixel: the count near its border varies by about 1 %.
    double total = 0.0;
    for (std::size_t k = 0; k < per_pixel.size(); ++k) {
      EXPECT_NEAR(per_pixel[k], 1.0, 0.02) << "pixel " << k << " aperture " << aperture;
      total += per_pixel[k];
    }
    EXPECT_NEAR(total / double(per_pixel.size()), 1.0, 0.003) << "aperture " << aperture;
  }
}

}  // namespace
}  // namespace lancer
