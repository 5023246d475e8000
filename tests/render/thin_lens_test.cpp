// The thin-lens camera: aperture 0 is the pinhole bit for bit (against rays recorded
// before the lens existed), the focus plane is sharp, other depths blur by the thin-lens
// circle of confusion, and the concentric disk map is uniform.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "render/camera.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

PinholeCamera golden_camera(int which) {
  return which == 0 ? PinholeCamera::look_at({1.5f, -2.0f, 3.25f}, {0.2f, 0.7f, -1.0f}, {0, 1, 0}, 0.7f, 64, 48)
                    : PinholeCamera::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.57079632679f, 200, 100);
}

// Rays of PinholeCamera::generate(i, j) as the code produced them before the thin lens was
// added (the same build flags: -ffp-contract=off).
struct GoldenRay {
  int camera;
  float i, j;
  std::uint32_t org[3], dir[3];
};
const GoldenRay kGolden[] = {
    {0, 0.5f, 0.5f, {0x3fc00000u, 0xc0000000u, 0x40500000u}, {0xbf0fad03u, 0x3f353672u, 0xbedb97b6u}},
    {0, 17.2999992f, 40.9000015f, {0x3fc00000u, 0xc0000000u, 0x40500000u}, {0xbef3b1afu, 0x3e912a4eu, 0xbf551f47u}},
    {0, 63.9900017f, 0.00999999978f, {0x3fc00000u, 0xc0000000u, 0x40500000u}, {0x3e6cd5c4u, 0x3f35c597u, 0xbf2a4333u}},
    {0, 32.0f, 24.0f, {0x3fc00000u, 0xc0000000u, 0x40500000u}, {0xbe7ffcf7u, 0x3f04eabcu, 0xbf513899u}},
    {1, 0.5f, 0.5f, {0, 0, 0}, {0xbf5105b2u, 0x3ecff8ceu, 0xbed21297u}},
    {1, 17.2999992f, 40.9000015f, {0, 0, 0}, {0xbf5a1ba6u, 0x3dbfff92u, 0xbf03ddf3u}},
    {1, 63.9900017f, 0.00999999978f, {0, 0, 0}, {0xbee85d63u, 0x3f214992u, 0xbf2151d4u}},
    {1, 32.0f, 24.0f, {0, 0, 0}, {0xbf451b56u, 0x3e96ba8du, 0xbf10ee74u}},
};

void expect_same_bits(const Ray& got, const std::uint32_t org[3], const std::uint32_t dir[3], const char* what) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(got.org[k]), org[k]) << what << " origin " << k;
    EXPECT_EQ(bits(got.dir[k]), dir[k]) << what << " direction " << k;
  }
}

TEST(ThinLens, ZeroApertureIsThePinholeBitForBit) {
  for (const GoldenRay& g : kGolden) {
    PinholeCamera cam = golden_camera(g.camera);
    EXPECT_EQ(cam.aperture_radius(), 0.0f) << "the default is a pinhole";
    expect_same_bits(cam.generate(g.i, g.j), g.org, g.dir, "generate(i, j)");
    for (float lu : {0.0f, 0.3f, 0.999f})
      expect_same_bits(cam.generate(g.i, g.j, {lu, 1.0f - lu}), g.org, g.dir, "generate(i, j, lens) at aperture 0");
    cam.set_thin_lens(0.0f, 2.0f);
    expect_same_bits(cam.generate(g.i, g.j, {0.7f, 0.2f}), g.org, g.dir, "explicit zero aperture");
    // The lens never changes the pinhole path.
    cam.set_thin_lens(0.5f, 2.0f);
    expect_same_bits(cam.generate(g.i, g.j), g.org, g.dir, "generate(i, j) with a lens set");
  }
}

PinholeCamera lens_camera(float aperture, float focus) {
  PinholeCamera cam = PinholeCamera::look_at({1, 2, 3}, {-2, 1, -4}, {0, 1, 0}, 0.8f, 160, 90);
  cam.set_thin_lens(aperture, focus);
  return cam;
}

// Where a ray crosses the plane at `depth` along the optical axis.
glm::vec3 cross_plane(const PinholeCamera& cam, const Ray& r, float depth) {
  const float t = (depth - glm::dot(r.org - cam.origin(), cam.forward())) / glm::dot(r.dir, cam.forward());
  return r.org + t * r.dir;
}

// The continuous pixel position a world point projects to through the pinhole.
glm::vec2 project(const PinholeCamera& cam, const glm::vec3& p) {
  const glm::vec3 q = p - cam.origin();
  const float z = glm::dot(q, cam.forward());
  const float sx = glm::dot(q, cam.x_axis()) / (z * glm::dot(cam.x_axis(), cam.x_axis()));
  const float sy = glm::dot(q, cam.y_axis()) / (z * glm::dot(cam.y_axis(), cam.y_axis()));
  return {(0.5f * sx + 0.5f) * static_cast<float>(cam.width()), (0.5f * sy + 0.5f) * static_cast<float>(cam.height())};
}

std::vector<glm::vec2> lens_grid() {
  std::vector<glm::vec2> u;
  for (int a = 0; a < 9; ++a)
    for (int b = 0; b < 9; ++b) u.push_back({(a + 0.5f) / 9.0f, (b + 0.5f) / 9.0f});
  u.push_back({0.0f, 0.0f});
  u.push_back({0.999f, 0.5f});
  return u;
}

TEST(ThinLens, FocusPlaneIsSharp) {
  constexpr float kFocus = 6.0f, kAperture = 0.25f;
  const PinholeCamera cam = lens_camera(kAperture, kFocus);
  for (float i : {0.5f, 40.25f, 80.0f, 159.5f})
    for (float j : {0.5f, 45.0f, 89.5f}) {
      const glm::vec3 target = cross_plane(cam, cam.generate(i, j), kFocus);
      for (const glm::vec2& u : lens_grid()) {
        const Ray r = cam.generate(i, j, u);
        EXPECT_NEAR(glm::length(r.dir), 1.0f, 1e-6f);
        EXPECT_EQ(r.tnear, 0.0f);
        // The ray leaves from the lens disk ...
        EXPECT_NEAR(glm::dot(r.org - cam.origin(), cam.forward()), 0.0f, 1e-6f);
        EXPECT_LE(glm::length(r.org - cam.origin()), kAperture * (1 + 1e-6f));
        // ... and meets the focus plane where the pinhole ray does: the same pixel.
        const glm::vec3 hit = cross_plane(cam, r, kFocus);
        EXPECT_LT(glm::length(hit - target), 2e-5f * kFocus) << "pixel " << i << ", " << j;
        const glm::vec2 px = project(cam, hit);
        EXPECT_NEAR(px.x, i, 2e-3f);
        EXPECT_NEAR(px.y, j, 2e-3f);
      }
    }
}

// A point at depth D, off the focus plane F, is missed by the lens ray from lens offset l
// by l (1 - D / F) (similar triangles): the circle of confusion.
TEST(ThinLens, OtherDepthsBlurByTheCircleOfConfusion) {
  constexpr float kFocus = 4.0f, kAperture = 0.1f;
  const PinholeCamera cam = lens_camera(kAperture, kFocus);
  float widest = 0.0f;
  for (float depth : {1.0f, 2.0f, 8.0f, 40.0f}) {
    const glm::vec3 sharp = cross_plane(cam, cam.generate(30.0f, 70.0f), depth);
    for (const glm::vec2& u : lens_grid()) {
      const Ray r = cam.generate(30.0f, 70.0f, u);
      const float lens_offset = glm::length(r.org - cam.origin());
      widest = std::max(widest, lens_offset);
      const float miss = glm::length(cross_plane(cam, r, depth) - sharp);
      EXPECT_NEAR(miss, lens_offset * std::abs(1.0f - depth / kFocus), 1e-5f * depth) << "depth " << depth;
    }
  }
  EXPECT_GT(widest, 0.9f * kAperture) << "the samples reach the rim of the lens";
}

TEST(ThinLens, FocusAtInfinityKeepsThePinholeDirection) {
  PinholeCamera cam = lens_camera(0.3f, std::numeric_limits<float>::infinity());
  for (const glm::vec2& u : lens_grid()) {
    const Ray pin = cam.generate(12.5f, 33.0f), lens = cam.generate(12.5f, 33.0f, u);
    EXPECT_EQ(lens.dir, pin.dir);
    EXPECT_LE(glm::length(lens.org - pin.org), 0.3f * (1 + 1e-6f));
  }
}

TEST(ThinLens, FromDescAndValidation) {
  CameraDesc desc;
  desc.camera_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 5));
  EXPECT_EQ(PinholeCamera::from_desc(desc, 10, 10).aperture_radius(), 0.0f);
  desc.aperture_radius = 0.05f;
  PinholeCamera cam = PinholeCamera::from_desc(desc, 10, 10);
  EXPECT_EQ(cam.aperture_radius(), 0.05f);
  EXPECT_TRUE(std::isinf(cam.focus_distance())) << "no focus distance: focused at infinity";
  desc.focus_distance = 3.0f;
  cam = PinholeCamera::from_desc(desc, 10, 10);
  EXPECT_EQ(cam.focus_distance(), 3.0f);
  // The point 3 units in front of the camera (at z = 2) is sharp.
  for (const glm::vec2& u : lens_grid()) {
    const Ray r = cam.generate(5.0f, 5.0f, u);
    const float t = (2.0f - r.org.z) / r.dir.z;
    EXPECT_NEAR(r.org.x + t * r.dir.x, 0.0f, 1e-5f);
    EXPECT_NEAR(r.org.y + t * r.dir.y, 0.0f, 1e-5f);
  }
  EXPECT_THROW(cam.set_thin_lens(-0.1f, 1.0f), std::invalid_argument);
  EXPECT_THROW(cam.set_thin_lens(NAN, 1.0f), std::invalid_argument);
  EXPECT_THROW(cam.set_thin_lens(INFINITY, 1.0f), std::invalid_argument);
  EXPECT_THROW(cam.set_thin_lens(0.1f, 0.0f), std::invalid_argument);
  EXPECT_THROW(cam.set_thin_lens(0.1f, -1.0f), std::invalid_argument);
  EXPECT_THROW(cam.set_thin_lens(0.1f, NAN), std::invalid_argument);
}

TEST(ConcentricDisk, MapsTheSquareOntoTheDiskUniformly) {
  EXPECT_EQ(concentric_disk({0.5f, 0.5f}), glm::vec2(0.0f));
  auto expect_near = [](glm::vec2 got, glm::vec2 want) {
    EXPECT_NEAR(got.x, want.x, 1e-6f);
    EXPECT_NEAR(got.y, want.y, 1e-6f);
  };
  expect_near(concentric_disk({0.75f, 0.5f}), {0.5f, 0.0f});  // square rings go to circles
  expect_near(concentric_disk({0.5f, 0.75f}), {0.0f, 0.5f});
  expect_near(concentric_disk({0.25f, 0.5f}), {-0.5f, 0.0f});
  expect_near(concentric_disk({0.5f, 0.0f}), {0.0f, -1.0f});
  expect_near(concentric_disk({1.0f, 1.0f}), {std::sqrt(0.5f), std::sqrt(0.5f)});
  // Uniform points on the square land evenly in equal-area rings and sectors (random
  // points: a regular grid is itself biased at the rings' edges).
  constexpr int kN = 1 << 20;
  std::vector<int> rings(8, 0), sectors(16, 0);
  SplitMix64 rng(42);
  for (int n = 0; n < kN; ++n) {
    const float a = rng.uniform();
    const glm::vec2 p = concentric_disk({a, rng.uniform()});
    const float r2 = glm::dot(p, p);
    ASSERT_LT(r2, 1.0f);
    ++rings[std::min(7, static_cast<int>(r2 * 8))];
    double phi = std::atan2(p.y, p.x);
    if (phi < 0) phi += 2 * std::numbers::pi;
    ++sectors[std::min(15, static_cast<int>(phi / (2 * std::numbers::pi) * 16))];
  }
  // Binomial counts: five standard deviations.
  for (int c : rings) EXPECT_NEAR(c, kN / 8.0, 5 * std::sqrt(kN / 8.0 * 7 / 8));
  for (int c : sectors) EXPECT_NEAR(c, kN / 16.0, 5 * std::sqrt(kN / 16.0 * 15 / 16));
}

}  // namespace
}  // namespace lancer
