// glTF doubleSided (render/shading_inputs.h, culls_back_faces and emits_toward) in every
// integrator, on small scenes whose answers are known:
//  - a single-sided square seen from behind is invisible (path, Whitted, debug views): the
//    wall behind it shows; seen from the front, or double-sided, it is there;
//  - a point that sees its back sees through it, light included: no shadow on a floor that
//    faces its back, a full one on a floor that faces its front. Every ray is traced from
//    the camera's end of its path segment (shadow rays from the shading point), so this is
//    what a camera placed on the floor would see, and paths and light samples agree;
//  - a single-sided emitter lights only its front side; a double-sided one lights both,
//    equally (light samples and BSDF samples, combined by MIS, must agree);
//  - a volume boundary (thicknessFactor > 0) keeps its back side, where rays leave it.
#include <cstdint>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/lights.h"
#include "render/renderer.h"
#include "image_estimate.h"
#include "render_test_scenes.h"

namespace lancer {
namespace {

using test::add_material;

Material emitter(const glm::vec3& radiance, bool double_sided) {
  Material m = test::emissive_material(radiance);
  m.specular = 0.0f;
  m.double_sided = double_sided;
  return m;
}

ImageRGB render(const Scene& scene, const PinholeCamera& cam, IntegratorKind kind, int spp, int max_depth = 8) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = spp;
  s.integrator = kind;
  s.max_depth = max_depth;
  s.seed = 5;
  RenderStats stats;
  return render_image(scene, kd, cam, s, stats);
}

glm::dvec3 image_mean(const ImageRGB& image) {
  return {test::estimate(image, 0).mean, test::estimate(image, 1).mean, test::estimate(image, 2).mean};
}

// A red wall at z = -1 facing the camera and, at z = 0, a green-emitting square whose
// front faces +z (towards the camera) or -z; seen from +z, the square filling the image.
Scene square_before_a_wall(bool square_faces_camera, bool double_sided) {
  Scene scene;
  test::add_square_z(scene, 0, 0, -1, 10.0f, true, add_material(scene, emitter({1, 0, 0}, false)));
  test::add_square_z(scene, 0, 0, 0, 1.0f, square_faces_camera, add_material(scene, emitter({0, 1, 0}, double_sided)));
  return scene;
}

const PinholeCamera kSquareCamera = PinholeCamera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.4f, 16, 16);

TEST(SingleSided, BackOfASquareIsInvisible) {
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    SCOPED_TRACE(integrator_name(kind));
    EXPECT_EQ(image_mean(render(square_before_a_wall(false, false), kSquareCamera, kind, 2)), glm::dvec3(1, 0, 0))
        << "from behind, the wall through the single-sided square";
    EXPECT_EQ(image_mean(render(square_before_a_wall(true, false), kSquareCamera, kind, 2)), glm::dvec3(0, 1, 0))
        << "from the front, the square";
    EXPECT_EQ(image_mean(render(square_before_a_wall(false, true), kSquareCamera, kind, 2)), glm::dvec3(0, 1, 0))
        << "double-sided: the square from behind, emitting from that side too";
  }
  // The debug views see through it as well: depth 5 (the wall), not 4 (the square).
  const ImageRGB depth = render(square_before_a_wall(false, false), kSquareCamera, IntegratorKind::Depth, 1);
  EXPECT_GT(test::estimate(depth, 0).mean, 4.9);
  const ImageRGB front = render(square_before_a_wall(true, false), kSquareCamera, IntegratorKind::Depth, 1);
  EXPECT_LT(test::estimate(front, 0).mean, 4.5);
}

// The mean radiance of a white floor at z = 0 under a point light at height 3, with a
// diffuse square at height 1 between them whose front faces the light (up) or the floor.
glm::dvec3 floor_under_a_square(bool square_faces_up, bool double_sided, IntegratorKind kind) {
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 10.0f, true, add_material(scene, test::diffuse_material(glm::vec3(0.8f))));
  Material m = test::diffuse_material(glm::vec3(0.5f));
  m.double_sided = double_sided;
  test::add_square_z(scene, 0, 0, 1.0f, 2.0f, square_faces_up, add_material(scene, m));
  PunctualLight lamp;
  lamp.position = {0, 0, 3};
  lamp.intensity = 9.0f;
  scene.lights.push_back(lamp);
  // From between the floor and the square, looking down at the floor under the square.
  const PinholeCamera cam = PinholeCamera::look_at({0, -0.9f, 0.5f}, {0, 0, 0}, {0, 0, 1}, 0.3f, 16, 16);
  return image_mean(render(scene, cam, kind, 4, 1));
}

TEST(SingleSided, CastsNoShadowOnWhatSeesItsBack) {
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    SCOPED_TRACE(integrator_name(kind));
    const glm::dvec3 through = floor_under_a_square(true, false, kind);
    EXPECT_GT(through.x, 0.1) << "the floor sees the square's back: no shadow";
    EXPECT_EQ(floor_under_a_square(false, false, kind), glm::dvec3(0.0)) << "the floor sees its front: a shadow";
    EXPECT_EQ(floor_under_a_square(true, true, kind), glm::dvec3(0.0)) << "double-sided: a shadow either way";
  }
}

// A white floor at z = 0 under a square emitter of radiance 1 at height 1, whose front
// faces the floor or away from it.
ImageRGB floor_under_an_emitter(bool emitter_faces_floor, bool double_sided, int spp) {
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 10.0f, true, add_material(scene, test::diffuse_material(glm::vec3(0.8f))));
  test::add_square_z(scene, 0, 0, 1.0f, 0.5f, !emitter_faces_floor, add_material(scene, emitter(glm::vec3(1.0f), double_sided)));
  const PinholeCamera cam = PinholeCamera::look_at({0, -0.5f, 0.05f}, {0, 0.5f, 0}, {0, 0, 1}, 0.5f, 16, 16);
  return render(scene, cam, IntegratorKind::Path, spp, 1);
}

TEST(SingleSided, EmitterLightsOnlyItsFrontUnlessDoubleSided) {
  const ImageRGB front = floor_under_an_emitter(true, false, 256);
  const test::Estimate lit = test::estimate(front, 0);
  EXPECT_GT(lit.mean, 0.01);
  EXPECT_EQ(test::estimate(floor_under_an_emitter(false, false, 16), 0).mean, 0.0) << "single-sided, back to the floor";
  // Double-sided, either side towards the floor: the same light, within the noise. Light
  // sampling alone would pass this even if a BSDF sample hitting the back were not counted
  // (MIS weights would then lose energy), so the comparison is with the front.
  for (bool faces_floor : {true, false}) {
    const test::Estimate both = test::estimate(floor_under_an_emitter(faces_floor, true, 256), 0);
    EXPECT_NEAR(both.mean, lit.mean, 5.0 * std::hypot(both.stderr_, lit.stderr_) + 1e-4)
        << "double-sided, " << (faces_floor ? "front" : "back") << " to the floor";
  }
}

TEST(SingleSided, DoubleSidedEmitterHasTwiceThePower) {
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 1.0f, true, add_material(scene, emitter(glm::vec3(1.0f), false)));
  test::add_square_z(scene, 5, 0, 0, 1.0f, true, add_material(scene, emitter(glm::vec3(1.0f), true)));
  const AreaLights lights(scene);
  ASSERT_EQ(lights.size(), 4u);
  float one = 0.0f, two = 0.0f;
  for (std::size_t i = 0; i < lights.size(); ++i) (lights.light(i).two_sided ? two : one) += lights.pick_probability(i);
  EXPECT_NEAR(two / one, 2.0f, 1e-5f);
}

TEST(SingleSided, VolumeBoundaryKeepsItsBackSide) {
  // A single-sided glass slab of thickness > 0 (a volume) in front of the camera: a ray
  // from inside meets its back side, which must be there for the ray to leave the volume.
  // Seen along the normal, glass of IOR 1.5 passes (1 - 0.04)^2 of a red wall behind it;
  // had the back been culled, the ray would stay inside and pass (1 - 0.04) of it.
  Scene scene;
  test::add_square_z(scene, 0, 0, -3, 20.0f, true, add_material(scene, emitter({1, 0, 0}, false)));
  Material glass = test::glass_material(1.5f);
  glass.thickness = 0.5f;
  glass.specular = 1.0f;
  const std::uint32_t g = add_material(scene, glass);
  test::add_square_z(scene, 0, 0, 0, 5.0f, true, g);
  test::add_square_z(scene, 0, 0, -0.5f, 5.0f, false, g);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.05f, 8, 8);
  const ImageRGB image = render(scene, cam, IntegratorKind::Whitted, 1, 4);
  EXPECT_NEAR(test::estimate(image, 0).mean, 0.96 * 0.96, 0.01);
}

}  // namespace
}  // namespace lancer
