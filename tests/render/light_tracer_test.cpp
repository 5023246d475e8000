// Light tracing for the path tracer's caustics seen directly (render/light_tracer.h):
//  - the path tracer with it and without it agree within the noise over seeds where the
//    path tracer alone finds every caustic (a large light over a glass pane and a mirror),
//    also where the path length limit cuts paths: nothing is counted twice or missed;
//  - it applies only where it can: the path integrator, a box filter, a perspective camera,
//    nothing moving, delta materials and emissive triangles present;
//  - a light path splats only after a delta bounce, and only within the depth limit;
//  - images are bit-identical across thread counts, tile sizes and trace modes, and differ
//    from the path tracer's alone.
#include "render/light_tracer.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "caustic_test_support.h"
#include "render/lights.h"
#include "render/photon_walk.h"
#include "render/render_state.h"
#include "render/renderer.h"
#include "render_test_scenes.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "test_paths.h"

namespace lancer {
namespace {

// Unbiased both ways, so every 4x4 block mean agrees within 5 combined standard errors over
// 6 seeds (48 comparisons per depth; the seeds are fixed, so the outcome is too). Counting
// the caustics twice (the path tracer not leaving them out) puts the floor under the pane
// and beside the mirror far off; leaving out a path the light tracer does not take (one cut
// by the depth limit on one side only) darkens them.
TEST(LightTracer, AgreesWithThePathTracerAlone) {
  const test::GlassAndMirror g;
  const KdTree accel(g.scene.triangles);
  constexpr int kSize = 32, kSeeds = 6, kSpp = 256;
  const PinholeCamera camera = test::GlassAndMirror::camera(kSize);
  {
    const AreaLights lights(g.scene);
    ASSERT_TRUE(
        LightTracer::applies(g.scene, camera, test::caustic_settings(IntegratorKind::Path, kSize, kSpp), lights));
  }
  for (int max_depth : {2, 3, 8}) {
    auto render = [&](bool light_traced, std::uint64_t seed) {
      RenderSettings s = test::caustic_settings(IntegratorKind::Path, kSize, kSpp);
      s.seed = seed;
      s.max_depth = max_depth;
      s.light_traced_caustics = light_traced;
      RenderStats stats;
      const ImageRGB image = render_image(g.scene, accel, camera, s, stats);
      EXPECT_EQ(stats.light_rays > 0, light_traced);
      return image;
    };
    const test::SeedStats alone = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(false, seed); });
    const test::SeedStats with = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(true, seed); });
    const int resolved = test::expect_same_block_means(alone, with, "max_depth " + std::to_string(max_depth));
    // Of 48: the black background's blocks aside, differences of 5 % are resolved in most.
    EXPECT_GE(resolved, 27) << "max_depth " << max_depth;
  }
}

// A floor lit only through two glass panes, one above the other (thin walls: one delta
// scattering each), seen from below them. Camera - floor - pane - pane - light is three
// scattering events: at max_depth 2 neither side may count it (the image is black: a light
// tracer that joins one bounce too late lights the floor), at max_depth 3 both do and agree
// (one that stops one bounce too early leaves it black).
TEST(LightTracer, CutsPathsAtTheDepthLimitAsThePathTracerDoes) {
  Scene scene;
  const std::uint32_t floor = test::add_material(scene, test::diffuse_material(glm::vec3(0.5f)));
  const std::uint32_t glass = test::add_material(scene, test::glass_material(1.5f));
  const std::uint32_t light = test::add_material(scene, test::emissive_material(glm::vec3(3.0f)));
  test::add_square_z(scene, 0.0f, 0.0f, 0.0f, 3.0f, true, floor);
  test::add_square_z(scene, 0.0f, 0.0f, 0.5f, 3.0f, true, glass);
  test::add_square_z(scene, 0.0f, 0.0f, 0.6f, 3.0f, true, glass);
  test::add_square_z(scene, 0.0f, 0.0f, 1.0f, 1.0f, false, light);
  const KdTree accel(scene.triangles);
  constexpr int kSize = 16, kSeeds = 4;
  const PinholeCamera camera = PinholeCamera::look_at(glm::vec3(0.0f, 0.0f, 0.3f), glm::vec3(0.0f),
                                                      glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, kSize, kSize);
  auto render = [&](bool light_traced, int max_depth, std::uint64_t seed) {
    RenderSettings s = test::caustic_settings(IntegratorKind::Path, kSize, 128);
    s.seed = seed;
    s.max_depth = max_depth;
    s.light_traced_caustics = light_traced;
    RenderStats stats;
    return render_image(scene, accel, camera, s, stats);
  };
  for (bool light_traced : {false, true}) {
    const ImageRGB image = render(light_traced, 2, 1);
    for (float v : image.rgb) ASSERT_EQ(v, 0.0f) << "max_depth 2, light traced " << light_traced;
  }
  const test::SeedStats alone = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(false, 3, seed); });
  const test::SeedStats with = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(true, 3, seed); });
  const int resolved = test::expect_same_block_means(alone, with, "max_depth 3");
  EXPECT_EQ(resolved, 48) << "every block lit, and a 5 % difference visible in each";
}

// Single-sided surfaces (glTF's default, culled from behind) stop a ray from their front
// only, so a light path and a camera path through one may not take the same way. A black
// single-sided veil over the glass and mirror scene, seen from behind by the camera: camera
// rays pass it on their way to the first surface, and so does the light side's join to the
// lens (shared; counted twice if the camera side kept those paths whole). A veil under the
// light facing up: the camera's paths pass it from behind on their way to the light, light
// paths meet its front and stop (the camera side keeps those whole; darker if it shared
// them). Under the glass pane facing down, seen by the camera from behind: light paths that
// went through the pane pass it from behind, the floor's camera paths meet its front (the
// light side must stop there; brighter if it went on). Each way the images agree with the
// camera's paths alone.
TEST(LightTracer, OpaqueSingleSidedSurfacesAsBothSidesSeeThem) {
  struct Veil {
    const char* what;
    float x, z, half;
    bool facing_up;
  };
  for (const Veil& veil : {Veil{"veil seen from behind", 0.0f, 1.3f, 4.0f, false},
                           Veil{"veil under the light", 0.0f, 0.95f, 0.35f, true},
                           Veil{"veil under the pane, facing down", 0.25f, 0.2f, 0.2f, false}}) {
    test::GlassAndMirror g;
    Material black = test::diffuse_material(glm::vec3(0.0f));
    black.double_sided = false;
    test::add_square_z(g.scene, veil.x, 0.0f, veil.z, veil.half, veil.facing_up, test::add_material(g.scene, black));
    const KdTree accel(g.scene.triangles);
    constexpr int kSize = 32, kSeeds = 6;
    const PinholeCamera camera = test::GlassAndMirror::camera(kSize);
    {
      const AreaLights lights(g.scene);
      ASSERT_TRUE(LightTracer::applies(g.scene, camera, test::caustic_settings(IntegratorKind::Path, kSize, 1), lights))
          << veil.what;
    }
    auto render = [&](bool light_traced, std::uint64_t seed) {
      RenderSettings s = test::caustic_settings(IntegratorKind::Path, kSize, 256);
      s.seed = seed;
      s.light_traced_caustics = light_traced;
      RenderStats stats;
      return render_image(g.scene, accel, camera, s, stats);
    };
    const test::SeedStats alone = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(false, seed); });
    const test::SeedStats with = test::over_seeds(kSeeds, [&](std::uint64_t seed) { return render(true, seed); });
    const int resolved = test::expect_same_block_means(alone, with, veil.what);
    EXPECT_GE(resolved, 20) << veil.what;
  }
}

// Where light and camera paths would not take the same ways, the camera's take all: a
// single-sided surface that lets light through its front (coverage, transmission), which a
// camera path meets from behind and passes without a vertex; an absorbing volume, which a
// light path leaving an emitter inside it does not know it is in.
TEST(LightTracer, LeavesScenesWithoutReciprocityToTheCameraPaths) {
  const PinholeCamera camera = test::GlassAndMirror::camera(16);
  const RenderSettings s = test::caustic_settings(IntegratorKind::Path, 16, 1);
  auto applies_with = [&](const Material& m) {
    test::GlassAndMirror g;
    test::add_square_z(g.scene, 0.0f, 0.0f, 0.8f, 0.2f, true, test::add_material(g.scene, m));
    const AreaLights lights(g.scene);
    return LightTracer::applies(g.scene, camera, s, lights);
  };
  Material opaque = test::diffuse_material(glm::vec3(0.5f));
  opaque.double_sided = false;
  EXPECT_TRUE(applies_with(opaque)) << "opaque single-sided surfaces are handled";
  Material blend = opaque;
  blend.alpha_mode = AlphaMode::Blend;
  blend.base_color.a = 0.5f;
  EXPECT_FALSE(applies_with(blend)) << "single-sided, by coverage";
  Material translucent = opaque;
  translucent.transmission = 1.0f;
  translucent.roughness = 0.5f;
  EXPECT_FALSE(applies_with(translucent)) << "single-sided, by transmission";
  blend.double_sided = translucent.double_sided = true;
  EXPECT_TRUE(applies_with(blend)) << "double-sided coverage";
  EXPECT_TRUE(applies_with(translucent)) << "double-sided transmission";
  Material tinted = test::glass_material(1.5f);
  tinted.thickness = 0.1f;
  tinted.attenuation_distance = 0.5f;
  tinted.attenuation_color = glm::vec3(0.8f, 0.5f, 0.2f);
  EXPECT_FALSE(applies_with(tinted)) << "an absorbing volume";
  tinted.attenuation_distance = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(applies_with(tinted)) << "a clear volume";
}

// A state whose samples took the caustics seen directly at full weight (rendered without
// light paths) cannot go on with light paths: those caustics would count twice.
TEST(LightTracer, RefusesToContinueAStateRenderedWithoutIt) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const KdTree accel(scene.triangles);
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), 16, 16);
  RenderState state;
  RenderControl control;
  control.state = &state;
  RenderSettings s = test::caustic_settings(IntegratorKind::Path, 16, 2);
  s.light_traced_caustics = false;
  RenderStats stats;
  render_image(scene, accel, camera, s, stats, {}, control);
  ASSERT_EQ(state.passes, 2);
  s.spp = 4;
  s.light_traced_caustics = true;
  EXPECT_THROW(render_image(scene, accel, camera, s, stats, {}, control), std::invalid_argument);
  // And the other way: light sums that a render without light paths would leave as they are.
  RenderState lit;
  control.state = &lit;
  s.spp = 2;
  render_image(scene, accel, camera, s, stats, {}, control);
  ASSERT_EQ(lit.light_passes, 2);
  s.spp = 4;
  s.light_traced_caustics = false;
  EXPECT_THROW(render_image(scene, accel, camera, s, stats, {}, control), std::invalid_argument);
}

TEST(LightTracer, AppliesOnlyWhereItCan) {
  const Scene spheres = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const Scene plain = load_scene(test::scenes_dir() / "cornell-box.gltf");
  const AreaLights spheres_lights(spheres), plain_lights(plain);
  const PinholeCamera camera = PinholeCamera::from_desc(spheres.cameras.at(0), 16, 16);
  const RenderSettings s = test::caustic_settings(IntegratorKind::Path, 16, 1);
  EXPECT_TRUE(LightTracer::applies(spheres, camera, s, spheres_lights));
  EXPECT_FALSE(LightTracer::applies(plain, camera, s, plain_lights)) << "no delta material";
  // Textured roughness counts by its smallest texel: the still life's metals are rough
  // everywhere, but a texel of 0 anywhere makes a material possibly smooth.
  Scene still = load_scene(test::scenes_dir() / "textured" / "still-life.gltf");
  const AreaLights still_lights(still);
  EXPECT_FALSE(LightTracer::applies(still, camera, s, still_lights)) << "rough textures";
  Material& textured = still.materials.at(0);
  ASSERT_TRUE(textured.metallic_roughness_texture.present());
  Image& image = still.images.at(static_cast<std::size_t>(
      still.textures.at(static_cast<std::size_t>(textured.metallic_roughness_texture.texture)).image));
  image.pixels.at(image.channels >= 3 ? 1 : 0) = 0;  // one texel's roughness (G) 0
  EXPECT_TRUE(LightTracer::applies(still, camera, s, still_lights)) << "a smooth texel";
  RenderSettings off = s;
  off.light_traced_caustics = false;
  EXPECT_FALSE(LightTracer::applies(spheres, camera, off, spheres_lights));
  for (IntegratorKind other : {IntegratorKind::Photon, IntegratorKind::Sppm, IntegratorKind::Whitted,
                               IntegratorKind::Ao, IntegratorKind::Normals}) {
    RenderSettings o = s;
    o.integrator = other;
    EXPECT_FALSE(LightTracer::applies(spheres, camera, o, spheres_lights)) << integrator_name(other);
  }
  RenderSettings gaussian = s;
  gaussian.filter = PixelFilterType::Gaussian;
  EXPECT_FALSE(LightTracer::applies(spheres, camera, gaussian, spheres_lights)) << "not a box filter";
  RenderSettings shallow = s;
  shallow.max_depth = 1;
  EXPECT_FALSE(LightTracer::applies(spheres, camera, shallow, spheres_lights)) << "no room for a delta bounce";
  PinholeCamera moving = camera;
  moving.set_shutter_open(true);
  EXPECT_FALSE(LightTracer::applies(spheres, moving, s, spheres_lights)) << "motion blur";
  CameraDesc ortho;
  ortho.orthographic = true;
  ortho.xmag = ortho.ymag = 1.0f;
  EXPECT_FALSE(LightTracer::applies(spheres, PinholeCamera::from_desc(ortho, 16, 16), s, spheres_lights));
}

// Splats come only from light that met a delta surface first: a glass pane over the floor
// (at max_depth 2: one delta bounce, then the floor); without the pane, none. A path of more
// scattering events than max_depth never splats (at max_depth 1 LightTracer::applies says no
// anyway, and the path tracer keeps everything).
TEST(LightTracer, SplatsOnlyAfterADeltaBounceWithinTheDepth) {
  auto splats = [](int panes, int max_depth) {
    Scene scene;
    const std::uint32_t floor = test::add_material(scene, test::diffuse_material(glm::vec3(0.5f)));
    const std::uint32_t glass = test::add_material(scene, test::glass_material(1.5f));
    const std::uint32_t light = test::add_material(scene, test::emissive_material(glm::vec3(4.0f)));
    test::add_square_z(scene, 0.0f, 0.0f, 0.0f, 2.0f, true, floor);
    for (int k = 0; k < panes; ++k) test::add_square_z(scene, 0.0f, 0.0f, 0.5f + 0.1f * float(k), 2.0f, true, glass);
    test::add_square_z(scene, 0.0f, 0.0f, 1.0f, 0.3f, false, light);
    const KdTree accel(scene.triangles);
    const AreaLights lights(scene);
    RenderSettings s = test::caustic_settings(IntegratorKind::Path, 16, 1);
    s.max_depth = max_depth;
    const PinholeCamera camera = PinholeCamera::look_at(glm::vec3(0.0f, 0.0f, 0.3f), glm::vec3(0.0f),
                                                        glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, 16, 16);
    const LightTracer tracer(scene, accel, camera, lights, s);
    std::vector<LightTracer::Splat> out;
    std::uint64_t rays = 0;
    for (std::uint64_t i = 0; i < 4000; ++i) tracer.trace_path(i, out, rays);
    EXPECT_GE(rays, 4000u);
    for (const LightTracer::Splat& sp : out) {
      EXPECT_LT(sp.pixel, 16u * 16u);
      EXPECT_GT(sp.value.x, 0.0f);
      EXPECT_TRUE(std::isfinite(sp.value.x));
    }
    return out.size();
  };
  EXPECT_GT(splats(1, 2), 50u) << "through the pane onto the floor, seen by the camera";
  EXPECT_EQ(splats(0, 2), 0u) << "no delta surface: the floor's light is the path tracer's";
  EXPECT_EQ(splats(1, 1), 0u) << "two scattering events do not fit in max_depth 1";
  EXPECT_EQ(splats(2, 2), 0u) << "three scattering events do not fit in max_depth 2";
  EXPECT_GT(splats(2, 3), 50u) << "they fit in max_depth 3";
}

// 136 x 136: 4,624 light paths a pass, more than one chunk of them (kPhotonChunk), so the
// chunks' order is what the threads must not change.
TEST(LightTracer, BitIdenticalAcrossThreadsTilesAndModes) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const KdTree accel(scene.triangles);
  constexpr int kSize = 136;
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), kSize, kSize);
  const RenderSettings base = test::caustic_settings(IntegratorKind::Path, kSize, 2);
  ASSERT_GT(std::uint64_t(kSize) * kSize / kPixelsPerLightPath, std::uint64_t(kPhotonChunk));
  const ImageRGB one = test::expect_bit_identical_across_threads_tiles_and_modes(scene, accel, camera, base);
  RenderSettings alone = base;
  alone.light_traced_caustics = false;
  RenderStats stats;
  EXPECT_FALSE(test::bitwise_equal(one, render_image(scene, accel, camera, alone, stats)));
}

}  // namespace
}  // namespace lancer
