// The layered materials in whole renders (bsdf_layers_test.cpp tests the lobes themselves):
//  - a smooth clearcoat over a black base under a uniform sky of radiance 1, seen straight
//    down, is clearcoat * 0.04 (KHR_materials_clearcoat's Fresnel at normal incidence);
//  - a red sheen over a black base under the same sky is red, with the sheen's directional
//    albedo E(cos) as its value; a white sheen over a white Lambert base is 1 (the albedo
//    scaling of KHR_materials_sheen conserves energy there);
//  - Whitted: a smooth coat mirrors an emitter with its Fresnel share, and a sheen is lit as
//    the path tracer lights it;
//  - KHR_materials_unlit shows its base colour in the dark, for the path tracer and Whitted,
//    and is no light for next-event estimation;
//  - the same from glTF files that require the extensions (reader to image).
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/bsdf_lobes.h"
#include "render/environment.h"
#include "render/lights.h"
#include "render/renderer.h"
#include "image_estimate.h"
#include "render_test_scenes.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/procedural.h"

namespace lancer {
namespace {

using test::add_material;
using test::Estimate;
using test::estimate;

ImageRGB render(const Scene& scene, const PinholeCamera& cam, int spp, const Environment* env,
                IntegratorKind kind = IntegratorKind::Path) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = spp;
  s.integrator = kind;
  s.max_depth = 16;
  s.environment = env;
  s.seed = 3;
  RenderStats stats;
  return render_image(scene, kd, cam, s, stats);
}

Material black_base() {
  Material m = test::diffuse_material(glm::vec3(0.0f));
  m.specular = 0.0f;  // no specular layer: the base scatters nothing
  return m;
}

TEST(ClearcoatRender, SmoothCoatOverBlackReflectsFourPercent) {
  for (float coat : {1.0f, 0.5f}) {
    Scene scene;
    Material m = black_base();
    m.clearcoat = coat;
    test::add_square_z(scene, 0, 0, 0, 100.0f, true, add_material(scene, m));
    const Environment sky(glm::vec3(1.0f));
    // Within 0.06 rad of the normal: (1 - cos)^5 < 1e-12, so F = 0.04.
    const PinholeCamera cam = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.08f, 8, 8);
    const ImageRGB image = render(scene, cam, 4, &sky);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(estimate(image, c).mean, 0.04 * coat, 1e-5) << "clearcoat " << coat;
    // Without the coat: black.
    Scene bare;
    test::add_square_z(bare, 0, 0, 0, 100.0f, true, add_material(bare, black_base()));
    EXPECT_EQ(estimate(render(bare, cam, 4, &sky), 0).mean, 0.0);
  }
}

TEST(ClearcoatRender, RoughCoatOverBlackReflectsAtMostItsFresnel) {
  Scene scene;
  Material m = black_base();
  m.clearcoat = 1.0f;
  m.clearcoat_roughness = 0.5f;
  test::add_square_z(scene, 0, 0, 0, 100.0f, true, add_material(scene, m));
  const Environment sky(glm::vec3(1.0f));
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.08f, 8, 8);
  const Estimate e = estimate(render(scene, cam, 64, &sky), 0);
  // 0.04 times the GGX lobe's single-scattering albedo at roughness 0.5 (about 0.95).
  EXPECT_GT(e.mean, 0.035);
  EXPECT_LT(e.mean, 0.04 + 5.0 * e.stderr_);
}

// The plane seen at `cos_view` from its normal, filling a narrow view.
PinholeCamera oblique(float cos_view) {
  const float sin_view = std::sqrt(1.0f - cos_view * cos_view);
  return PinholeCamera::look_at({0, -3.0f * sin_view, 3.0f * cos_view}, {0, 0, 0}, {0, 0, 1}, 0.02f, 8, 8);
}

TEST(SheenRender, RedClothOverBlackShowsTheSheenAlbedo) {
  Scene scene;
  Material m = black_base();
  m.sheen_color = glm::vec3(1.0f, 0.0f, 0.0f);
  m.sheen_roughness = 0.6f;
  test::add_square_z(scene, 0, 0, 0, 100.0f, true, add_material(scene, m));
  const Environment sky(glm::vec3(1.0f));
  for (float cos_view : {0.9f, 0.3f}) {
    const ImageRGB image = render(scene, oblique(cos_view), 256, &sky);
    const Estimate red = estimate(image, 0);
    const double expected = sheen_albedo(cos_view, 0.6f);
    std::printf("red sheen at cos %.1f: %.4f +- %.4f, E = %.4f\n", cos_view, red.mean, red.stderr_, expected);
    EXPECT_GT(red.mean, 0.05) << "a red sheen cloth is not near black";
    EXPECT_NEAR(red.mean, expected, 5.0 * red.stderr_ + 0.01 * expected);
    EXPECT_EQ(estimate(image, 1).mean, 0.0);
    EXPECT_EQ(estimate(image, 2).mean, 0.0);
  }
}

TEST(SheenRender, WhiteSheenOverWhiteLambertIsOneUnderAUniformSky) {
  Scene scene;
  Material m = test::diffuse_material(glm::vec3(1.0f));
  m.specular = 0.0f;
  m.sheen_color = glm::vec3(1.0f);
  m.sheen_roughness = 0.4f;
  test::add_square_z(scene, 0, 0, 0, 1000.0f, true, add_material(scene, m));
  const Environment sky(glm::vec3(1.0f));
  for (float cos_view : {0.95f, 0.5f}) {
    const Estimate e = estimate(render(scene, oblique(cos_view), 128, &sky), 0);
    EXPECT_NEAR(e.mean, 1.0, 5.0 * e.stderr_ + 3e-3) << "cos " << cos_view;
  }
}

// Whitted has no sky: a smooth coat over a black base mirrors an emitter of radiance 1 above
// it with the coat's Fresnel share; a rough coat is left out, as every glossy lobe is there.
TEST(ClearcoatRender, WhittedMirrorsAnEmitterThroughASmoothCoat) {
  for (float roughness : {0.0f, 0.1f, 0.5f})
    for (float coat : {1.0f, 0.5f}) {
      Scene scene;
      Material m = black_base();
      m.clearcoat = coat;
      m.clearcoat_roughness = roughness;
      test::add_square_z(scene, 0, 0, 0, 100.0f, true, add_material(scene, m));
      test::add_square_z(scene, 0, 0, 2, 100.0f, false, add_material(scene, test::emissive_material(glm::vec3(1.0f))));
      const PinholeCamera cam = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.08f, 8, 8);
      const ImageRGB image = render(scene, cam, 4, nullptr, IntegratorKind::Whitted);
      const double expected = roughness < 0.2f ? 0.04 * coat : 0.0;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(estimate(image, c).mean, expected, 1e-5) << "clearcoat " << coat << " roughness " << roughness;
    }
}

// Whitted lights a sheen as the path tracer does: on a lone square under a directional light
// both give next-event estimation alone (nothing else to bounce off), so they agree. A red
// sheen over black is red; over white Lambert it dims the base by 1 - max(sheenColor) E.
TEST(SheenRender, WhittedLightsTheSheenAsThePathTracerDoes) {
  for (float base : {0.0f, 1.0f})
    for (float cos_view : {0.95f, 0.5f}) {
      Scene scene;
      Material m = test::diffuse_material(glm::vec3(base));
      m.specular = 0.0f;
      m.sheen_color = glm::vec3(1.0f, 0.3f, 0.1f);
      m.sheen_roughness = 0.5f;
      test::add_square_z(scene, 0, 0, 0, 1000.0f, true, add_material(scene, m));
      PunctualLight sun;
      sun.type = LightType::Directional;
      sun.direction = glm::normalize(glm::vec3(0.3f, 0.6f, -1.0f));
      sun.intensity = 2.0f;
      scene.lights.push_back(sun);
      const ImageRGB whitted = render(scene, oblique(cos_view), 4, nullptr, IntegratorKind::Whitted);
      const ImageRGB path = render(scene, oblique(cos_view), 4, nullptr, IntegratorKind::Path);
      for (int c = 0; c < 3; ++c) {
        const double w = estimate(whitted, c).mean, p = estimate(path, c).mean;
        EXPECT_NEAR(w, p, 2e-3 * p + 1e-6) << "base " << base << " cos " << cos_view << " channel " << c;
      }
      const double red = estimate(whitted, 0).mean, blue = estimate(whitted, 2).mean;
      std::printf("Whitted sheen, base %.0f, cos %.2f: red %.4f blue %.4f\n", base, cos_view, red, blue);
      if (base == 0.0f) {
        EXPECT_GT(red, 0.005) << "a red sheen over black is lit";
        EXPECT_GT(red, 5.0 * blue) << "and red";
      }
      if (base > 0.0f) {  // the sheen dims the white base: less blue than the bare Lambert's
        Scene bare = scene;
        bare.materials[0].sheen_color = glm::vec3(0.0f);
        EXPECT_LT(estimate(whitted, 2).mean, estimate(render(bare, oblique(cos_view), 4, nullptr, IntegratorKind::Whitted), 2).mean);
      }
    }
}

TEST(UnlitRender, ShowsItsBaseColourAndLightsNothingByNextEvent) {
  Scene scene;
  Material m = test::diffuse_material(glm::vec3(0.2f, 0.4f, 0.6f));
  m.unlit = true;
  test::add_square_z(scene, 0, 0, 0, 100.0f, true, add_material(scene, m));
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.5f, 8, 8);
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const ImageRGB image = render(scene, cam, 4, nullptr, kind);
    EXPECT_NEAR(estimate(image, 0).mean, 0.2, 1e-6);
    EXPECT_NEAR(estimate(image, 1).mean, 0.4, 1e-6);
    EXPECT_NEAR(estimate(image, 2).mean, 0.6, 1e-6);
  }
  EXPECT_TRUE(AreaLights(scene).empty()) << "an unlit surface is no light for next-event estimation";
  // Seen from its back too (unlit is not emission, which is one-sided).
  const PinholeCamera below = PinholeCamera::look_at({0, 0, -1}, {0, 0, 0}, {0, 1, 0}, 0.5f, 8, 8);
  EXPECT_NEAR(estimate(render(scene, below, 4, nullptr), 1).mean, 0.4, 1e-6);
}

// A glTF file of one large square in z = 0 facing +z, with `material`, requiring `ext`.
void write_square_gltf(const gltf_test::json& material, const char* ext, const std::filesystem::path& file) {
  gltf_test::GltfBuilder b;
  const int pos = b.add_vec3({{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}});
  const int idx = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  b.push("materials", material);
  b.single_node_scene(b.add_mesh({{"POSITION", pos}}, 4, idx, 0));
  b.doc["extensionsUsed"] = {ext};
  b.doc["extensionsRequired"] = {ext};
  b.write_data_uri_gltf(file);
}

class MaterialLayersGltfRender : public gltf_test::GltfTempDir {};

TEST_F(MaterialLayersGltfRender, FilesRequiringTheExtensionsRenderThem) {
  const gltf_test::json black = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}};
  const gltf_test::json no_specular = {{"KHR_materials_specular", {{"specularFactor", 0.0}}}};
  gltf_test::json coat = {{"pbrMetallicRoughness", black}, {"extensions", no_specular}};
  coat["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0}};
  write_square_gltf(coat, "KHR_materials_clearcoat", path("coat.gltf"));
  gltf_test::json sheen = {{"pbrMetallicRoughness", black}, {"extensions", no_specular}};
  sheen["extensions"]["KHR_materials_sheen"] = {{"sheenColorFactor", {1.0, 0.0, 0.0}}, {"sheenRoughnessFactor", 0.6}};
  write_square_gltf(sheen, "KHR_materials_sheen", path("sheen.gltf"));
  write_square_gltf({{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}},
                     {"extensions", {{"KHR_materials_unlit", gltf_test::json::object()}}}},
                    "KHR_materials_unlit", path("unlit.gltf"));

  const Environment sky(glm::vec3(1.0f));
  const PinholeCamera down = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.08f, 8, 8);
  EXPECT_NEAR(estimate(render(read_gltf(path("coat.gltf")), down, 4, &sky), 1).mean, 0.04, 1e-5);
  const Estimate red = estimate(render(read_gltf(path("sheen.gltf")), oblique(0.3f), 64, &sky), 0);
  EXPECT_NEAR(red.mean, sheen_albedo(0.3f, 0.6f), 5.0 * red.stderr_ + 0.01 * red.mean);
  const ImageRGB unlit = render(read_gltf(path("unlit.gltf")), down, 4, nullptr);
  EXPECT_NEAR(estimate(unlit, 2).mean, 0.6, 1e-6);
}

}  // namespace
}  // namespace lancer
