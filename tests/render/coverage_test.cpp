// glTF alpha coverage (render/coverage.h) in every integrator, on small scenes whose
// answers are known:
//  - a MASK quad with a cut-out half in front of a red wall shows the wall through the
//    cut-out and itself elsewhere (path, Whitted, and the debug views), and the shadow it
//    casts has the same hole;
//  - a BLEND quad of alpha 0.3 in front of an emitter passes 0.7 of its light, adds 0.3 of
//    its own emission, and casts a shadow that lets 0.7 of a point light through;
//  - an emissive BLEND quad lights a floor with alpha times its radiance (light samples and
//    BSDF samples that hit it, combined by MIS, must agree);
//  - passing a surface is not a bounce, and the MIS weight of an emitter seen through
//    surfaces passed on the way measures the whole distance from the last bounce;
//  - 300 stacked cut-outs hide nothing (Whitted walks through them in a loop).
#include "render/coverage.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/renderer.h"
#include "render/texture.h"
#include "image_estimate.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

using test::add_material;

// A black, non-reflecting material emitting `radiance` from its front side.
Material emitter(const glm::vec3& radiance) {
  Material m = test::emissive_material(radiance);
  m.specular = 0.0f;
  return m;
}

// A w x 1 RGBA texture, nearest-filtered, clamped to its edges.
int add_rgba_strip(Scene& scene, const std::vector<std::uint8_t>& rgba) {
  Image image;
  image.width = static_cast<int>(rgba.size() / 4);
  image.height = 1;
  image.channels = 4;
  image.pixels = rgba;
  scene.images.push_back(image);
  Texture texture;
  texture.image = static_cast<int>(scene.images.size() - 1);
  texture.mag_filter = texture.min_filter = kFilterNearest;
  texture.wrap_s = texture.wrap_t = 33071;  // CLAMP_TO_EDGE
  scene.textures.push_back(texture);
  return static_cast<int>(scene.textures.size() - 1);
}

// The square [-h, h]^2 in the plane z, front +z, UV (x, y) mapped from [-h, h] to [0, 1].
void add_uv_square(Scene& scene, float h, float z, std::uint32_t material) {
  const glm::vec3 a(-h, -h, z), b(h, -h, z), c(h, h, z), d(-h, h, z);
  auto uv = [h](const glm::vec3& p) { return glm::vec2((p.x + h) / (2 * h), (p.y + h) / (2 * h)); };
  SceneBuilder builder(scene, "square");
  for (const auto& tri : {std::array<glm::vec3, 3>{a, b, c}, std::array<glm::vec3, 3>{a, c, d}}) {
    const glm::vec2 uvs[3] = {uv(tri[0]), uv(tri[1]), uv(tri[2])};
    CornerAttributes attribs;
    attribs.texcoords = uvs;
    builder.add_triangle(tri.data(), material, 0, attribs);
  }
}

ImageRGB render(const Scene& scene, const PinholeCamera& cam, IntegratorKind kind, int spp, int max_depth = 8) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = spp;
  s.integrator = kind;
  s.max_depth = max_depth;
  s.seed = 9;
  RenderStats stats;
  return render_image(scene, kd, cam, s, stats);
}

glm::vec3 pixel(const ImageRGB& image, int x, int y) {
  const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                             static_cast<std::size_t>(x));
  return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
}

// Mean of the image's columns [x0, x1), all rows.
glm::dvec3 columns_mean(const ImageRGB& image, int x0, int x1) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = x0; x < x1; ++x) sum += glm::dvec3(pixel(image, x, y));
  return sum / double((x1 - x0) * image.height);
}

// A red wall (emission (1, 0, 0)) at z = -1 and, at z = 0, a square emitting green whose
// left half is cut out by a MASK texture; seen from +z, the square filling the image.
Scene masked_square_before_a_wall(AlphaMode mode) {
  Scene scene;
  test::add_square_z(scene, 0, 0, -1, 10.0f, true, add_material(scene, emitter({1, 0, 0})));
  Material m = emitter({0, 1, 0});
  m.base_color_texture.texture = add_rgba_strip(scene, {255, 255, 255, 0, 255, 255, 255, 255});
  m.alpha_mode = mode;
  add_uv_square(scene, 1.0f, 0.0f, add_material(scene, m));
  return scene;
}

const PinholeCamera kSquareCamera = PinholeCamera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.4f, 16, 16);

TEST(Coverage, MaskCutOutShowsTheWallBehind) {
  const Scene scene = masked_square_before_a_wall(AlphaMode::Mask);
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const ImageRGB image = render(scene, kSquareCamera, kind, 4);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        const glm::vec3 expected = x < 8 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        ASSERT_EQ(pixel(image, x, y), expected) << integrator_name(kind) << " pixel " << x << ", " << y;
      }
  }
  // OPAQUE ignores alpha: the square everywhere.
  const ImageRGB opaque = render(masked_square_before_a_wall(AlphaMode::Opaque), kSquareCamera, IntegratorKind::Path, 1);
  EXPECT_EQ(columns_mean(opaque, 0, 16), glm::dvec3(0, 1, 0));
}

TEST(Coverage, ThreeHundredStackedCutOutsHideNothing) {
  // An emitter behind 300 fully cut-out squares: both integrators see it (Whitted goes
  // through them in a loop, not a recursion 300 deep).
  Scene scene;
  test::add_square_z(scene, 0, 0, -1, 10.0f, true, add_material(scene, emitter({1, 1, 1})));
  Material hole = test::diffuse_material(glm::vec3(0.5f));
  hole.base_color.a = 0.0f;
  hole.alpha_mode = AlphaMode::Mask;
  const std::uint32_t m = add_material(scene, hole);
  for (int k = 0; k < 300; ++k) test::add_square_z(scene, 0, 0, 0.001f * float(k), 10.0f, true, m);
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const ImageRGB image = render(scene, kSquareCamera, kind, 1);
    EXPECT_EQ(columns_mean(image, 0, 16), glm::dvec3(1.0)) << integrator_name(kind);
  }
}

TEST(Coverage, DebugViewsSeeThroughCutOuts) {
  const Scene scene = masked_square_before_a_wall(AlphaMode::Mask);
  const ImageRGB depth = render(scene, kSquareCamera, IntegratorKind::Depth, 1);
  for (int y = 0; y < 16; ++y) {
    EXPECT_GT(pixel(depth, 2, y).x, 4.9f) << "the wall, 5 away, through the cut-out";
    EXPECT_LT(pixel(depth, 13, y).x, 4.5f) << "the square, 4 to 4.2 away";
  }
  const ImageRGB ids = render(scene, kSquareCamera, IntegratorKind::PrimId, 1);
  EXPECT_EQ(pixel(ids, 2, 8), pixel(render(masked_square_before_a_wall(AlphaMode::Mask), kSquareCamera,
                                           IntegratorKind::PrimId, 1), 2, 8));
  EXPECT_NE(pixel(ids, 2, 8), pixel(ids, 13, 8)) << "the wall's triangle left, the square's right";
}

TEST(Coverage, MaskCutOutLetsTheShadowThrough) {
  // A white floor lit by a point light straight above; between them a masked square whose
  // left half (x < 0) is cut out. The floor is lit under the cut-out, dark under the rest.
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 10.0f, true, add_material(scene, test::diffuse_material(glm::vec3(0.8f))));
  Material m = test::diffuse_material(glm::vec3(0.5f));
  m.base_color_texture.texture = add_rgba_strip(scene, {255, 255, 255, 0, 255, 255, 255, 255});
  m.alpha_mode = AlphaMode::Mask;
  add_uv_square(scene, 2.0f, 1.0f, add_material(scene, m));
  PunctualLight lamp;
  lamp.position = {0, 0, 3};
  lamp.intensity = 9.0f;
  scene.lights.push_back(lamp);
  // Seen from between the floor and the square: x < 0 on the image's left.
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const PinholeCamera cam = PinholeCamera::look_at({0, -0.9f, 0.5f}, {0, 0, 0}, {0, 0, 1}, 0.6f, 32, 32);
    const ImageRGB image = render(scene, cam, kind, 16, 1);
    const glm::dvec3 left = columns_mean(image, 4, 12), right = columns_mean(image, 20, 28);
    EXPECT_GT(left.x, 0.05) << integrator_name(kind) << ": under the cut-out the floor is lit";
    EXPECT_LT(right.x, 0.2 * left.x) << integrator_name(kind) << ": under the opaque half it is in shadow";
  }
}

TEST(Coverage, BlendSquarePassesOneMinusAlpha) {
  // Green-emitting square of alpha 0.3 in front of a wall emitting red 1: 0.7 red, 0.3 green.
  Scene scene;
  test::add_square_z(scene, 0, 0, -1, 10.0f, true, add_material(scene, emitter({1, 0, 0})));
  Material m = emitter({0, 1, 0});
  m.base_color.a = 0.3f;
  m.alpha_mode = AlphaMode::Blend;
  add_uv_square(scene, 1.0f, 0.0f, add_material(scene, m));
  const ImageRGB whitted = render(scene, kSquareCamera, IntegratorKind::Whitted, 1);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_NEAR(pixel(whitted, x, y).x, 0.7f, 1e-6f);
      EXPECT_NEAR(pixel(whitted, x, y).y, 0.3f, 1e-6f);
    }
  const ImageRGB path = render(scene, kSquareCamera, IntegratorKind::Path, 64);
  for (int c = 0; c < 2; ++c) {
    const test::Estimate e = test::estimate(path, c);
    EXPECT_NEAR(e.mean, c == 0 ? 0.7 : 0.3, 5.0 * e.stderr_ + 1e-4) << "channel " << c;
  }
}

TEST(Coverage, BlendShadowLetsThroughOneMinusAlpha) {
  // A white floor under a point light, with and without a BLEND square of alpha 0.3 between
  // them: the floor under it gets 0.7 of the light.
  auto floor_radiance = [](bool occluder, IntegratorKind kind) {
    Scene scene;
    test::add_square_z(scene, 0, 0, 0, 10.0f, true, add_material(scene, test::diffuse_material(glm::vec3(0.8f))));
    if (occluder) {
      Material m = test::diffuse_material(glm::vec3(0.5f));
      m.base_color.a = 0.3f;
      m.alpha_mode = AlphaMode::Blend;
      add_uv_square(scene, 2.0f, 1.0f, add_material(scene, m));
    }
    PunctualLight lamp;
    lamp.position = {0, 0, 3};
    lamp.intensity = 9.0f;
    scene.lights.push_back(lamp);
    const PinholeCamera cam = PinholeCamera::look_at({0, -0.9f, 0.5f}, {0, 0, 0}, {0, 0, 1}, 0.3f, 16, 16);
    return columns_mean(render(scene, cam, kind, 4, 1), 0, 16);
  };
  for (IntegratorKind kind : {IntegratorKind::Path, IntegratorKind::Whitted}) {
    const glm::dvec3 open = floor_radiance(false, kind), shaded = floor_radiance(true, kind);
    EXPECT_GT(open.x, 0.05);
    EXPECT_NEAR(shaded.x / open.x, 0.7, 1e-4) << integrator_name(kind);
  }
}

// A white diffuse floor lit by a square emitter of radiance 1 at height 1, with alpha
// `alpha` (BLEND) or opaque; optionally with fully cut-out squares between them.
ImageRGB lit_floor(float alpha, int cut_outs, int max_depth) {
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 10.0f, true, add_material(scene, test::diffuse_material(glm::vec3(0.8f))));
  Material light = emitter(glm::vec3(1.0f));
  if (alpha < 1.0f) {
    light.base_color.a = alpha;
    light.alpha_mode = AlphaMode::Blend;
  }
  test::add_square_z(scene, 0, 0, 1.0f, 0.5f, false, add_material(scene, light));
  Material hole = test::diffuse_material(glm::vec3(0.5f));
  hole.base_color.a = 0.0f;
  hole.alpha_mode = AlphaMode::Mask;
  for (int k = 0; k < cut_outs; ++k)
    test::add_square_z(scene, 0, 0, 0.2f + 0.1f * float(k), 3.0f, k % 2 == 0, add_material(scene, hole));
  const PinholeCamera cam = PinholeCamera::look_at({0, -0.5f, 0.05f}, {0, 0.5f, 0}, {0, 0, 1}, 0.5f, 16, 16);
  return render(scene, cam, IntegratorKind::Path, 256, max_depth);
}

void expect_same_mean(const ImageRGB& a, const ImageRGB& b, double scale, const char* what) {
  const test::Estimate ea = test::estimate(a, 0), eb = test::estimate(b, 0);
  EXPECT_NEAR(ea.mean, scale * eb.mean, 5.0 * std::hypot(ea.stderr_, scale * eb.stderr_) + 1e-4)
      << what << ": " << ea.mean << " +- " << ea.stderr_ << " against " << scale << " x " << eb.mean << " +- "
      << eb.stderr_;
}

TEST(Coverage, BlendEmitterEmitsAlphaTimesItsRadiance) {
  const ImageRGB full = lit_floor(1.0f, 0, 8);
  EXPECT_GT(test::estimate(full, 0).mean, 0.01);
  expect_same_mean(lit_floor(0.4f, 0, 8), full, 0.4, "emitter of alpha 0.4");
}

TEST(Coverage, PassingASurfaceIsNeitherABounceNorAShorterDistance) {
  // Six cut-out squares between the floor and its light change nothing: not the light
  // reaching the floor after one bounce, nor MIS between light samples and BSDF samples
  // that pass them (whose density must use the distance from the floor, not from the
  // last square).
  const ImageRGB open = lit_floor(1.0f, 0, 1);
  expect_same_mean(lit_floor(1.0f, 6, 1), open, 1.0, "six cut-outs, one bounce");
}

}  // namespace
}  // namespace lancer
