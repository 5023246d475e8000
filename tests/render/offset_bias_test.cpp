// Ray offsets must not bias what a point sees (accel/ray_offset.h). A diffuse point on a
// 2000 x 2000 ground plane lies under a small disk light at height h = 1; its irradiance E
// is known exactly from the light's triangles by Lambert's polygon formula,
//    E = L / 2 sum_i Theta_i (Gamma_i . n)
// (Lambert 1760; Arvo, "Applications of Irradiance Tensors to the Simulation of
// Non-Lambertian Phenomena", SIGGRAPH 1995: edge i subtends Theta_i at the point, Gamma_i is
// the unit normal of the plane through the point and the edge). The point sits on the
// plane's diagonal, where its two triangles meet.
//
// Rays that leave the plane from an origin pushed delta along the normal see the light from
// delta closer: a cosine-weighted estimate of E then grows by about 2 delta h / (h^2 + R^2),
// and the path tracer's BSDF-sampled share (after MIS) with it. The former floor of 2^-16 of
// the triangle's reach (1.5 cm here) gives +2.4 % and +0.3 %; these tests resolve both, and
// check that the renderer's offsets leave no trace: they are below 1e-5 h for every ray
// towards the light, and the estimates match E within their statistical error. The same
// scene tilted (off the axes, where the kernel's rounding does ask for a few ulps of the
// plane's extent, about 1e-3 here) still gives a cosine-weighted estimate within its error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "accel/ray_offset.h"
#include "image_estimate.h"
#include "render/renderer.h"
#include "render/surface.h"
#include "render_test_scenes.h"
#include "scene/scene_builder.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kHalfWidth = 1000.0f;  // the plane is 2000 x 2000
constexpr float kHeight = 1.0f;        // of the light above the plane
constexpr float kRadius = 0.5f;        // of the light's circumcircle
constexpr float kRadiance = 2.0f;
constexpr float kAlbedo = 0.6f;
// What the renderer used to push origins off this plane: 2^-16 of the triangle's reach.
constexpr float kFormerFloor = kHalfWidth / 65536.0f;

// ---- Lambert's formula ------------------------------------------------------------------

// Irradiance per unit radiance at x (unit normal n) from polygon `poly`, wholly above x's
// tangent plane.
double polygon_irradiance(const glm::dvec3& x, const glm::dvec3& n, const std::vector<glm::dvec3>& poly) {
  double sum = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec3 a = glm::normalize(poly[i] - x), b = glm::normalize(poly[(i + 1) % poly.size()] - x);
    const glm::dvec3 c = glm::cross(a, b);
    const double s = glm::length(c);
    if (s > 0.0) sum += std::atan2(s, glm::dot(a, b)) * glm::dot(c / s, n);
  }
  return 0.5 * std::fabs(sum);
}

// Irradiance at x on the plane (unit normal n) from every emissive triangle.
double light_irradiance(const Scene& s, const glm::dvec3& x, const glm::dvec3& n) {
  double e = 0.0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    const double radiance = s.materials[s.material_id[t]].emission().x;
    if (radiance > 0.0)
      e += radiance * polygon_irradiance(x, n,
                                         {glm::dvec3(s.triangles.vertex(t, 0)), glm::dvec3(s.triangles.vertex(t, 1)),
                                          glm::dvec3(s.triangles.vertex(t, 2))});
  }
  return e;
}

// ---- The scene ---------------------------------------------------------------------------

// The scene's frame: the identity (the plane z = 0), or a rotation that tilts it off every
// axis. The plane's normal is frame * (0, 0, 1).
const glm::dmat3 kAxes(1.0);
const glm::dmat3 kTilted(glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1.0, 2.0, 3.0))));

glm::vec3 in_frame(const glm::dmat3& frame, const glm::dvec3& v) { return glm::vec3(frame * v); }

// The 2000 x 2000 plane z = 0 (two triangles meeting on the diagonal x = y), Lambertian
// without a specular layer, under a 16-gon of circumradius kRadius at height kHeight,
// facing down, emitting and reflecting nothing else; all of it turned by `frame`.
Scene wide_plane_scene(const glm::dmat3& frame = kAxes) {
  Scene scene;
  Material plane = test::diffuse_material(glm::vec3(kAlbedo));
  plane.specular = 0.0f;
  Material light = test::emissive_material(glm::vec3(kRadiance));
  light.specular = 0.0f;
  test::add_square_z(scene, 0.0f, 0.0f, 0.0f, kHalfWidth, true, test::add_material(scene, plane));
  const std::uint32_t emitter = test::add_material(scene, light);
  SceneBuilder builder(scene, "disk light");
  const auto rim = [](int k) {
    const double phi = 2.0 * kPi * (k % 16) / 16.0;
    return glm::vec3(float(kRadius * std::cos(phi)), float(kRadius * std::sin(phi)), kHeight);
  };
  for (int k = 0; k < 16; ++k) {
    const glm::vec3 p[3] = {glm::vec3(0.0f, 0.0f, kHeight), rim(k + 1), rim(k)};  // facing -z
    EXPECT_TRUE(builder.add_triangle(p, emitter, std::uint32_t(k)));
  }
  builder.finish();
  // Turned after the fact (the corner normals too), so the axis-aligned scene stays exact.
  if (frame != kAxes) {
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 v = in_frame(frame, glm::dvec3(scene.triangles.vertex(i, k)));
        scene.triangles.x[k][i] = v.x, scene.triangles.y[k][i] = v.y, scene.triangles.z[k][i] = v.z;
      }
    for (glm::vec3& n : scene.normals) n = in_frame(frame, glm::dvec3(n));
  }
  return scene;
}

constexpr glm::vec3 kPoint(0.0f, 0.0f, 0.0f);  // on the diagonal, under the light's centre

// A camera with a 1e-4 rad field of view on the point: every pixel sees the plane within
// 1e-3 of it, where E differs from E(kPoint) by under 1e-7 relative.
PinholeCamera point_camera(int size, const glm::dmat3& frame = kAxes) {
  return PinholeCamera::look_at(kPoint + in_frame(frame, {2.0, 0.5, 1.0}), kPoint, in_frame(frame, {0.0, 0.0, 1.0}),
                                1e-4f, size, size);
}

// The surface points the camera's rays hit, as the renderer computes them.
std::vector<SurfacePoint> camera_hits(const Scene& scene, const KdTree& kd, int size,
                                      const glm::dmat3& frame = kAxes) {
  const PinholeCamera cam = point_camera(size, frame);
  std::vector<SurfacePoint> out;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Ray r = cam.generate(float(x) + 0.5f, float(y) + 0.5f);
      const Hit h = kd.intersect(r);
      EXPECT_TRUE(h.valid());
      if (h.valid()) out.push_back(make_surface_point(scene, r, h));
    }
  return out;
}

// ---- The offsets themselves ---------------------------------------------------------------

TEST(OffsetBias, OffsetsTowardsTheLightAreBelow1e5OfItsHeight) {
  const Scene scene = wide_plane_scene();
  const KdTree kd(scene.triangles);
  SplitMix64 rng(1);
  double largest = 0.0;
  for (const SurfacePoint& sp : camera_hits(scene, kd, 32)) {
    const SurfaceOffset leave(sp.p, sp.ng, triangle_corners(scene.triangles, sp.prim));
    for (int k = 0; k < 16; ++k) {
      // A point on the light's disk, aimed at as a shadow ray is (path.cpp).
      const double r = kRadius * std::cos(kPi / 16.0) * std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
      const glm::vec3 target(float(r * std::cos(phi)), float(r * std::sin(phi)), kHeight);
      const glm::vec3 o = leave.origin_towards(offset_ray_origin(target, {0, 0, -1}));
      largest = std::max(largest, glm::length(glm::dvec3(o) - glm::dvec3(sp.p)));
      EXPECT_GT(o.z, 0.0f);
    }
  }
  std::printf("[ info     ] largest offset towards the light: %.3g (former floor %.3g)\n", largest, kFormerFloor);
  EXPECT_LT(largest, 1e-5 * kHeight);
}

// ---- A cosine-weighted estimate of E ------------------------------------------------------

using test::Estimate;

// E from `count` cosine-weighted directions at the camera's hit points: pi L times the
// fraction of rays that reach the light's front, each leaving from origin(point, dir).
template <typename Origin>
Estimate cosine_estimate(const Scene& scene, const glm::dmat3& frame, int count, Origin origin) {
  const KdTree kd(scene.triangles);
  const std::vector<SurfacePoint> points = camera_hits(scene, kd, 16, frame);
  SplitMix64 rng(2);
  int seen = 0;
  for (int i = 0; i < count; ++i) {
    const SurfacePoint& sp = points[std::size_t(i) % points.size()];
    const double r = std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
    Ray ray;
    ray.dir = in_frame(frame, {r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0 - r * r)});
    ray.org = origin(sp, ray.dir);
    const Hit h = kd.intersect(ray);
    seen += h.valid() && scene.materials[scene.material_id[h.prim]].emission().x > 0.0f;
  }
  const double f = double(seen) / count;
  return {kPi * kRadiance * f, kPi * kRadiance * std::sqrt(f * (1.0 - f) / count)};
}

void expect_unbiased_cosine_estimate(const glm::dmat3& frame, const char* what) {
  const Scene scene = wide_plane_scene(frame);
  const double expected = light_irradiance(scene, glm::dvec3(kPoint), frame * glm::dvec3(0.0, 0.0, 1.0));
  constexpr int kRays = 1 << 19;
  const Estimate now = cosine_estimate(scene, frame, kRays, [&](const SurfacePoint& sp, const glm::vec3& dir) {
    return SurfaceOffset(sp.p, sp.ng, triangle_corners(scene.triangles, sp.prim)).origin(dir);
  });
  const Estimate former = cosine_estimate(
      scene, frame, kRays, [](const SurfacePoint& sp, const glm::vec3&) { return sp.p + kFormerFloor * sp.ng; });
  std::printf("[ info     ] %s: E = %.5f; cosine-weighted estimate %.5f +- %.5f (%+.2f %%), with the former floor "
              "%.5f (%+.2f %%)\n",
              what, expected, now.mean, now.stderr_, 100.0 * (now.mean / expected - 1.0), former.mean,
              100.0 * (former.mean / expected - 1.0));
  EXPECT_NEAR(now.mean, expected, 5.0 * now.stderr_) << what;
  EXPECT_GT(former.mean - expected, 5.0 * former.stderr_) << what << ": the estimate does not resolve the former floor";
}

TEST(OffsetBias, CosineWeightedEstimateSeesTheLightFromThePoint) {
  expect_unbiased_cosine_estimate(kAxes, "plane z = 0");
}

TEST(OffsetBias, CosineWeightedEstimateOnATiltedPlane) { expect_unbiased_cosine_estimate(kTilted, "tilted plane"); }

// ---- The path tracer ------------------------------------------------------------------------

// Lifts the origin of every ray that leaves the ground plane to at least the former floor
// above it (a shadow ray keeps its end point): the renderer as it was, for comparison.
class FormerFloor final : public Accelerator {
 public:
  explicit FormerFloor(const Accelerator& inner) : inner_(inner) {}
  Hit intersect(const Ray& ray) const override { return inner_.intersect(lifted(ray)); }
  bool occluded(const Ray& ray) const override { return inner_.occluded(lifted(ray)); }
  // The path tracer traces coherent secondary rays as packets too: every ray is lifted
  // (camera rays start far from the plane and are left as they are).
  void intersect_packet(const Ray* rays, Hit* hits, int count) const override {
    const std::vector<Ray> up = lifted(rays, count);
    inner_.intersect_packet(up.data(), hits, count);
  }
  void occluded_packet(const Ray* rays, bool* occluded, int count) const override {
    const std::vector<Ray> up = lifted(rays, count);
    inner_.occluded_packet(up.data(), occluded, count);
  }
  std::size_t memory_bytes() const override { return inner_.memory_bytes(); }
  std::string_view name() const override { return "former-floor"; }

 private:
  static Ray lifted(const Ray& ray) {
    if (!(std::fabs(ray.org.z) < kFormerFloor)) return ray;
    Ray r = ray;
    r.org.z = std::copysign(kFormerFloor, ray.dir.z);
    if (std::isfinite(ray.tfar)) r.dir = ray.org + ray.dir - r.org;
    return r;
  }
  static std::vector<Ray> lifted(const Ray* rays, int count) {
    std::vector<Ray> up(rays, rays + count);
    for (Ray& r : up) r = lifted(r);
    return up;
  }
  const Accelerator& inner_;
};

Estimate render_estimate(const Scene& scene, const Accelerator& accel, int spp) {
  const PinholeCamera cam = point_camera(32);
  RenderSettings settings;
  settings.width = cam.width();
  settings.height = cam.height();
  settings.spp = spp;
  settings.integrator = IntegratorKind::Path;
  settings.max_depth = 8;
  settings.seed = 5;
  RenderStats stats;
  const ImageRGB image = render_image(scene, accel, cam, settings, stats);
  for (float v : image.rgb) EXPECT_TRUE(std::isfinite(v));
  return test::estimate(image, 0);  // the pixels are independent
}

TEST(OffsetBias, PathTracerMatchesLambertsFormulaOnAWidePlane) {
  const Scene scene = wide_plane_scene();
  const KdTree kd(scene.triangles);
  const double expected = kAlbedo / kPi * light_irradiance(scene, glm::dvec3(kPoint), {0.0, 0.0, 1.0});
  const Estimate now = render_estimate(scene, kd, 64);
  const Estimate former = render_estimate(scene, FormerFloor(kd), 64);
  std::printf("[ info     ] radiance %.6f; rendered %.6f +- %.6f (%+.3f %%), with the former floor %.6f (%+.3f %%)\n",
              expected, now.mean, now.stderr_, 100.0 * (now.mean / expected - 1.0), former.mean,
              100.0 * (former.mean / expected - 1.0));
  // 1e-6: float rounding of the sums, far below the statistical error.
  EXPECT_NEAR(now.mean, expected, 5.0 * now.stderr_ + 1e-6);
  EXPECT_GT(former.mean - expected, 5.0 * former.stderr_) << "the render does not resolve the former floor";
}

}  // namespace
}  // namespace lancer
