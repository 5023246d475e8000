// PinholeCamera against hand-computed directions.
#include "render/camera.h"

#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace lancer {
namespace {

constexpr float kHalfPi = 1.57079632679f;

void expect_dir(const glm::vec3& got, const glm::vec3& want_unnormalised) {
  const glm::vec3 want = glm::normalize(want_unnormalised);
  EXPECT_NEAR(got.x, want.x, 1e-6f);
  EXPECT_NEAR(got.y, want.y, 1e-6f);
  EXPECT_NEAR(got.z, want.z, 1e-6f);
  EXPECT_NEAR(glm::length(got), 1.0f, 1e-6f);
}

// 90 degree vertical field of view, 200 x 100: tan(45) = 1, so the image plane at
// distance 1 spans y in [-1, 1] and x in [-2, 2].
PinholeCamera wide_camera() {
  return PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kHalfPi, 200, 100);
}

TEST(Camera, CentrePixelLooksForward) {
  const Ray r = wide_camera().generate(100.0f, 50.0f);
  EXPECT_EQ(r.org, glm::vec3(0.0f));
  expect_dir(r.dir, {0, 0, -1});
}

TEST(Camera, CornersAreForwardPlusMinusAxes) {
  const PinholeCamera cam = wide_camera();
  expect_dir(cam.generate(0, 0).dir, {-2, 1, -1});      // top left
  expect_dir(cam.generate(200, 0).dir, {2, 1, -1});     // top right
  expect_dir(cam.generate(0, 100).dir, {-2, -1, -1});   // bottom left
  expect_dir(cam.generate(200, 100).dir, {2, -1, -1});  // bottom right
  expect_dir(cam.generate(150, 25).dir, {1, 0.5f, -1});
}

TEST(Camera, IGoesRightAndJGoesDown) {
  const PinholeCamera cam = wide_camera();
  EXPECT_GT(cam.generate(101, 50).dir.x, 0.0f);
  EXPECT_LT(cam.generate(99, 50).dir.x, 0.0f);
  EXPECT_LT(cam.generate(100, 51).dir.y, 0.0f);
  EXPECT_GT(cam.generate(100, 49).dir.y, 0.0f);
}

TEST(Camera, AspectRatioScalesTheHorizontalAxis) {
  const float vfov = 0.6f;
  const PinholeCamera cam = PinholeCamera::look_at({1, 2, 3}, {1, 2, 0}, {0, 1, 0}, vfov, 300, 100);
  EXPECT_NEAR(glm::length(cam.y_axis()), std::tan(0.5f * vfov), 1e-6f);
  EXPECT_NEAR(glm::length(cam.x_axis()), 3.0f * std::tan(0.5f * vfov), 1e-6f);
  // The vertical field of view is exactly vfov: the top-centre ray is vfov/2 off-axis.
  const Ray top = cam.generate(150, 0);
  EXPECT_NEAR(std::acos(glm::dot(top.dir, cam.forward())), 0.5f * vfov, 1e-5f);
  EXPECT_EQ(top.org, glm::vec3(1, 2, 3));
}

TEST(Camera, LookAtRejectsDegenerateInput) {
  EXPECT_THROW(PinholeCamera::look_at({1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 1.0f, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 5, 0}, {0, 1, 0}, 1.0f, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 0, 0}, 1.0f, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.0f, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 3.2f, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, NAN, 10, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 0, 10), std::invalid_argument);
  EXPECT_THROW(PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 10, -1), std::invalid_argument);
}

TEST(Camera, FromGltfDescLooksDownMinusZ) {
  CameraDesc desc;
  desc.camera_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 5));
  desc.yfov = kHalfPi;
  const PinholeCamera cam = PinholeCamera::from_desc(desc, 100, 100);
  const Ray centre = cam.generate(50, 50);
  EXPECT_EQ(centre.org, glm::vec3(0, 0, 5));
  expect_dir(centre.dir, {0, 0, -1});
  expect_dir(cam.generate(0, 0).dir, {-1, 1, -1});  // +y is up, +x right
}

TEST(Camera, FromGltfDescFollowsRotation) {
  // Rotated 90 degrees about +y: the camera's -z becomes world -x.
  CameraDesc desc;
  desc.camera_to_world = glm::rotate(glm::mat4(1.0f), kHalfPi, glm::vec3(0, 1, 0));
  desc.yfov = 0.5f;
  const PinholeCamera cam = PinholeCamera::from_desc(desc, 64, 32);
  expect_dir(cam.generate(32, 16).dir, {-1, 0, 0});
  EXPECT_LT(cam.generate(64, 16).dir.z, 0.0f);  // right of the image is world -z
}

// (i, j) of a world point in the image of `cam`, from d = f + sx x + sy y.
glm::vec2 project(const PinholeCamera& cam, const glm::vec3& p) {
  const glm::vec3 d = p - cam.origin();
  const float along = glm::dot(d, cam.forward());
  EXPECT_GT(along, 0.0f);
  const float sx = glm::dot(d, cam.x_axis()) / glm::dot(cam.x_axis(), cam.x_axis()) / along;
  const float sy = glm::dot(d, cam.y_axis()) / glm::dot(cam.y_axis(), cam.y_axis()) / along;
  return {(0.5f * sx + 0.5f) * cam.width(), (0.5f * sy + 0.5f) * cam.height()};
}

TEST(Camera, ProjectionInvertsGenerate) {
  const PinholeCamera cam = PinholeCamera::look_at({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 0.9f, 80, 60);
  const Ray r = cam.generate(17.25f, 41.5f);
  const glm::vec2 ij = project(cam, r.org + 7.0f * r.dir);
  EXPECT_NEAR(ij.x, 17.25f, 1e-3f);
  EXPECT_NEAR(ij.y, 41.5f, 1e-3f);
}

TEST(Camera, FramingSeesTheWholeBox) {
  const Bounds3 boxes[] = {
      {{-1, -1, -1}, {1, 1, 1}},
      {{0, 0, -0.56f}, {0.556f, 0.549f, 0}},
      {{10, -3, 2}, {50, 4, 3}},  // long and flat
      {{-5, -100, -5}, {5, 100, 5}},  // tall
  };
  for (const Bounds3& box : boxes) {
    for (auto [w, h] : {std::pair{64, 64}, std::pair{200, 50}, std::pair{50, 200}}) {
      const PinholeCamera cam = PinholeCamera::framing(box, w, h);
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                               (c & 4) ? box.hi.z : box.lo.z);
        const glm::vec2 ij = project(cam, corner);
        EXPECT_GE(ij.x, 0.0f) << "corner " << c << " image " << w << "x" << h;
        EXPECT_LE(ij.x, static_cast<float>(w)) << "corner " << c << " image " << w << "x" << h;
        EXPECT_GE(ij.y, 0.0f) << "corner " << c << " image " << w << "x" << h;
        EXPECT_LE(ij.y, static_cast<float>(h)) << "corner " << c << " image " << w << "x" << h;
      }
    }
  }
}

TEST(Camera, FramingSeesEveryAxisPlaneAtAnAngle) {
  // A model lying flat in any axis plane must not be seen edge-on: the view direction
  // makes at least 30 degrees with each of the planes.
  const PinholeCamera cam = PinholeCamera::framing({{-1, -1, -1}, {1, 1, 1}}, 64, 64);
  for (int axis = 0; axis < 3; ++axis) EXPECT_GE(std::abs(cam.forward()[axis]), 0.49f) << "axis " << axis;
  EXPECT_LT(cam.forward().y, 0.0f) << "from above";
  EXPECT_LT(cam.forward().z, 0.0f) << "from the front (+z)";
}

TEST(Camera, OrthographicRaysAreParallelAndSpanTheMagnification) {
  CameraDesc desc;
  desc.orthographic = true;
  desc.xmag = 3.0f;
  desc.ymag = 1.5f;
  desc.camera_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3));
  const PinholeCamera cam = PinholeCamera::from_desc(desc, 200, 100);
  EXPECT_TRUE(cam.orthographic());
  for (auto [i, j] : {std::pair{0.0f, 0.0f}, std::pair{200.0f, 100.0f}, std::pair{100.0f, 50.0f}, std::pair{37.5f, 80.0f}}) {
    const Ray r = cam.generate(i, j);
    EXPECT_EQ(r.dir, glm::vec3(0, 0, -1));
    EXPECT_NEAR(r.org.x, 1.0f + 3.0f * (i / 100.0f - 1.0f), 1e-5f) << "x spans [-xmag, xmag]";
    EXPECT_NEAR(r.org.y, 2.0f - 1.5f * (j / 50.0f - 1.0f), 1e-5f) << "y spans [-ymag, ymag], j downwards";
    EXPECT_EQ(r.org.z, 3.0f);
  }
  // No lens: a thin lens is refused, a zero aperture is not.
  PinholeCamera lensless = cam;
  EXPECT_THROW(lensless.set_thin_lens(0.1f, 5.0f), std::invalid_argument);
  EXPECT_NO_THROW(lensless.set_thin_lens(0.0f, 5.0f));
  desc.ymag = 0.0f;
  EXPECT_THROW(PinholeCamera::from_desc(desc, 10, 10), std::invalid_argument);
}

}  // namespace
}  // namespace lancer
