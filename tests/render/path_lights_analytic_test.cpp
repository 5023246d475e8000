// Irradiance from area lights, through the whole path tracer: a Lambertian plane of albedo
// rho lit only by an emitter of radiance L has radiance rho / pi * E at a point that sees
// irradiance E, so the rendered value is checked against E in closed form:
//  - a disk of radius R at height h, parallel to the plane, seen from a point at distance a
//    from its axis: E = pi L / 2 (1 - (h^2 + a^2 - R^2) / sqrt((h^2 + a^2 + R^2)^2 - 4 a^2 R^2)),
//    which is pi L R^2 / (h^2 + R^2) = pi L sin^2(theta) on the axis (the form factor of a
//    differential area to a parallel disk; Howell's catalogue of configuration factors);
//  - a sphere of radius r whose centre lies at distance d straight above the point:
//    E = pi L (r / d)^2 = pi L sin^2(theta).
// The scene holds triangles, not a disk or a sphere, and an inscribed tessellation emits a
// few per cent less. So the expected value is computed from the actual triangles with
// Lambert's exact formula for the irradiance from a uniformly emitting polygon,
//    E = L / 2 sum_i Theta_i (Gamma_i . n)
// (Lambert 1760; Arvo, "Applications of Irradiance Tensors to the Simulation of
// Non-Lambertian Phenomena", SIGGRAPH 1995), where edge i subtends the angle Theta_i at the
// point and Gamma_i is the unit normal of the plane through the point and the edge. A first
// test checks that formula against the closed forms (they agree as the tessellation refines,
// and the tessellation's value lies between the closed forms of the inscribed and
// circumscribed shapes); the render tests then expect rho / pi * E within five standard
// errors that the render itself estimates, and check that the closed form of the ideal shape
// lies outside that band: the tolerance resolves the tessellation, it does not hide it.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/renderer.h"
#include "image_estimate.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- Closed forms and Lambert's polygon formula -----------------------------------------

// Irradiance per unit radiance from a disk of radius R parallel to the receiving plane at
// height h, at horizontal distance a from the disk's axis.
double disk_irradiance(double R, double h, double a) {
  const double s = h * h + a * a + R * R;
  return 0.5 * kPi * (1.0 - (h * h + a * a - R * R) / std::sqrt(s * s - 4.0 * a * a * R * R));
}

// Irradiance per unit radiance from a sphere of radius r at centre distance d, on a surface
// facing the centre (the whole sphere above the horizon: d > r).
double sphere_irradiance(double r, double d) { return kPi * (r / d) * (r / d); }

// Irradiance per unit radiance at x (unit normal n) from the polygon `poly`, wholly above
// x's tangent plane: Lambert's formula. The sign of the sum follows the winding; for a
// polygon above the plane its magnitude is the irradiance.
double polygon_irradiance(const glm::dvec3& x, const glm::dvec3& n, const std::vector<glm::dvec3>& poly) {
  double sum = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec3 u = glm::normalize(poly[i] - x);
    const glm::dvec3 v = glm::normalize(poly[(i + 1) % poly.size()] - x);
    const glm::dvec3 c = glm::cross(u, v);
    const double sin_theta = glm::length(c);
    if (sin_theta == 0.0) continue;  // the edge is seen end-on: it subtends nothing
    const double theta = std::atan2(sin_theta, glm::dot(u, v));
    sum += theta * glm::dot(c / sin_theta, n);
  }
  return 0.5 * std::abs(sum);
}

glm::dvec3 corner(const Scene& s, std::size_t t, int k) { return glm::dvec3(s.triangles.vertex(t, k)); }

// Irradiance at x (unit normal n) from every emissive triangle of the scene whose front side
// faces x, each with its material's radiance (channel 0). In a convex emitter those are
// exactly the triangles x sees (the others face away and are hidden behind them), and they
// cover its silhouette without overlap. Every such triangle must lie above x's tangent plane.
double scene_irradiance(const Scene& s, const glm::dvec3& x, const glm::dvec3& n) {
  double e = 0.0;
  for (std::size_t t = 0; t < s.triangle_count(); ++t) {
    const double radiance = s.materials[s.material_id[t]].emission().x;
    if (radiance == 0.0) continue;
    const glm::dvec3 a = corner(s, t, 0), b = corner(s, t, 1), c = corner(s, t, 2);
    if (glm::dot(glm::cross(b - a, c - a), x - a) <= 0.0) continue;  // faces away from x
    for (const glm::dvec3& p : {a, b, c}) EXPECT_GT(glm::dot(p - x, n), 0.0) << "emitter below the horizon";
    e += radiance * polygon_irradiance(x, n, {a, b, c});
  }
  return e;
}

// ---- Scenes ----------------------------------------------------------------------------

// A Lambertian material: no specular layer (KHR_materials_specular factor 0).
Material lambert(float albedo) {
  Material m = test::diffuse_material(glm::vec3(albedo));
  m.specular = 0.0f;
  return m;
}

// An emitter that reflects nothing (black, and no specular layer either), so the plane
// receives emitted light only.
Material black_emitter(float radiance) {
  Material m = test::emissive_material(glm::vec3(radiance));
  m.specular = 0.0f;
  return m;
}

// A regular n-gon of circumradius R in the plane z = h, centred on the z axis, as a fan of
// n triangles around its centre, facing down (-z).
void append_disk(Scene& scene, int n, float R, float h, std::uint32_t material) {
  SceneBuilder builder(scene, "disk light");
  const glm::vec3 centre(0.0f, 0.0f, h);
  const auto rim = [&](int k) {
    const double phi = 2.0 * kPi * (k % n) / n;
    return glm::vec3(static_cast<float>(R * std::cos(phi)), static_cast<float>(R * std::sin(phi)), h);
  };
  for (int k = 0; k < n; ++k) {
    const glm::vec3 p[3] = {centre, rim(k + 1), rim(k)};  // clockwise seen from above
    ASSERT_TRUE(builder.add_triangle(p, material, static_cast<std::uint32_t>(k)));
  }
  builder.finish();
}

struct LitPlane {
  Scene scene;
  glm::dvec3 point{0.0};        // on the plane z = 0, normal +z
  double ideal_irradiance = 0;  // the closed form of the untessellated shape (radiance 1)
};

constexpr float kAlbedo = 0.6f;
constexpr float kRadiance = 2.0f;

// The plane is a 4 x 4 square: secondary rays leave a triangle from a point pushed 2^-16 of
// its vertices' reach off it (accel/ray_offset.h), which for a plane 1000 units wide is
// 1.5 cm: BSDF-sampled rays would then measure the light from 1.5 % closer to it, a bias of
// about +0.3 % (disk) and +1.3 % (sphere) after MIS that these tests resolve. Here the
// offset is 3e-5, and its effect below 1e-5 relative.
LitPlane plane_scene() {
  LitPlane s;
  test::add_square_z(s.scene, 0.0f, 0.0f, 0.0f, 2.0f, true, test::add_material(s.scene, lambert(kAlbedo)));
  return s;
}

// ---- Rendering -------------------------------------------------------------------------

using test::Estimate;
using test::estimate;

// Renders the plane around s.point through a camera with a 1e-4 rad field of view: every
// pixel sees a patch under 1e-3 across, over which E changes by less than 1e-6 relative
// (it is smooth there), far below the statistical error.
ImageRGB render_point(const LitPlane& s, int spp) {
  const KdTree kd(s.scene.triangles);
  const glm::vec3 target(s.point);
  const glm::vec3 eye = target + glm::vec3(2.0f, 0.5f, 1.0f);  // sees the plane past the light
  const PinholeCamera cam = PinholeCamera::look_at(eye, target, {0, 0, 1}, 1e-4f, 32, 32);
  RenderSettings settings;
  settings.width = cam.width();
  settings.height = cam.height();
  settings.spp = spp;
  settings.integrator = IntegratorKind::Path;
  settings.max_depth = 8;
  settings.seed = 5;
  RenderStats stats;
  return render_image(s.scene, kd, cam, settings, stats);
}

void expect_plane_radiance(const LitPlane& s, const char* what) {
  const double e = scene_irradiance(s.scene, s.point, {0.0, 0.0, 1.0});
  const double expected = kAlbedo / kPi * e;
  const double ideal = kAlbedo / kPi * kRadiance * s.ideal_irradiance;
  const ImageRGB image = render_point(s, 64);
  for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v)) << what;
  for (int c = 0; c < 3; ++c) {
    const Estimate est = estimate(image, c);
    // 1e-6: float rounding of the sums, far below the statistical error.
    EXPECT_NEAR(est.mean, expected, 5.0 * est.stderr_ + 1e-6)
        << what << ", channel " << c << ": " << est.mean << " +- " << est.stderr_;
    EXPECT_GT(std::abs(ideal - expected), 5.0 * est.stderr_)
        << what << ": the band does not resolve the tessellation (ideal " << ideal << ")";
    if (c == 0)
      std::printf("%s: rendered %.6f +- %.6f, tessellation %.6f, ideal shape %.6f\n", what, est.mean, est.stderr_,
                  expected, ideal);
  }
}

// ---- Tests -----------------------------------------------------------------------------

std::vector<glm::dvec3> regular_polygon(int n, double R, double h) {
  std::vector<glm::dvec3> p;
  for (int k = 0; k < n; ++k) p.emplace_back(R * std::cos(2.0 * kPi * k / n), R * std::sin(2.0 * kPi * k / n), h);
  return p;
}

TEST(LightIrradianceOracle, PolygonFormulaAgreesWithTheClosedForms) {
  const glm::dvec3 n(0.0, 0.0, 1.0);
  const double R = 0.5, h = 1.0;
  for (double a : {0.0, 0.3, 0.6, 1.5}) {
    const glm::dvec3 x(a, 0.0, 0.0);
    // A fine polygon is the disk to O((2 pi / n)^2).
    EXPECT_NEAR(polygon_irradiance(x, n, regular_polygon(20000, R, h)) / disk_irradiance(R, h, a), 1.0, 1e-7) << a;
    // A coarse one lies between its inscribed and circumscribed disks.
    const int sides = 16;
    const double e = polygon_irradiance(x, n, regular_polygon(sides, R, h));
    EXPECT_LT(e, disk_irradiance(R, h, a)) << a;
    EXPECT_GT(e, disk_irradiance(R * std::cos(kPi / sides), h, a)) << a;
  }
  EXPECT_NEAR(disk_irradiance(R, h, 0.0), kPi * R * R / (h * h + R * R), 1e-15);

  // A fine icosphere of radius r is the sphere; a coarse one lies between its insphere
  // (the nearest face plane) and its circumsphere.
  const double r = 0.4, d = 1.2;
  for (int subdivisions : {1, 5}) {
    Scene s;
    append_icosphere(s, {0.0f, 0.0f, static_cast<float>(d)}, static_cast<float>(r), subdivisions,
                     test::add_material(s, black_emitter(1.0f)));
    double inradius = r;
    for (std::size_t t = 0; t < s.triangle_count(); ++t) {
      const glm::dvec3 a = corner(s, t, 0), b = corner(s, t, 1), c = corner(s, t, 2);
      const glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
      inradius = std::min(inradius, std::abs(glm::dot(normal, a - glm::dvec3(0.0, 0.0, d))));
    }
    const double e = scene_irradiance(s, glm::dvec3(0.0), n);
    // 1e-6: the vertices are float, within ~1e-7 r of the sphere.
    EXPECT_LT(e, sphere_irradiance(r, d) * (1.0 + 1e-6)) << subdivisions;
    EXPECT_GT(e, sphere_irradiance(inradius, d) * (1.0 - 1e-6)) << subdivisions;
    if (subdivisions == 5) {
      EXPECT_NEAR(e / sphere_irradiance(r, d), 1.0, 2e-3);
    }
  }
}

TEST(LightIrradiance, DiskOnItsAxis) {
  LitPlane s = plane_scene();
  append_disk(s.scene, 16, 0.5f, 1.0f, test::add_material(s.scene, black_emitter(kRadiance)));
  s.ideal_irradiance = disk_irradiance(0.5, 1.0, 0.0);
  expect_plane_radiance(s, "disk, on the axis");
}

TEST(LightIrradiance, DiskOffItsAxis) {
  LitPlane s = plane_scene();
  append_disk(s.scene, 16, 0.5f, 1.0f, test::add_material(s.scene, black_emitter(kRadiance)));
  s.point = glm::dvec3(0.6, 0.2, 0.0);
  s.ideal_irradiance = disk_irradiance(0.5, 1.0, std::hypot(0.6, 0.2));
  expect_plane_radiance(s, "disk, off the axis");
}

TEST(LightIrradiance, SphereStraightAbove) {
  LitPlane s = plane_scene();
  append_icosphere(s.scene, {0.0f, 0.0f, 1.2f}, 0.4f, 2, test::add_material(s.scene, black_emitter(kRadiance)));
  s.ideal_irradiance = sphere_irradiance(0.4, 1.2);
  expect_plane_radiance(s, "sphere");
}

}  // namespace
}  // namespace lancer
