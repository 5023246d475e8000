// evaluate_shading on hand-built scenes: normal maps on a flat quad with file and
// generated tangents of both handednesses, the back side, the viewer-side rule, agreement
// with make_surface_point, and alpha modes. The glTF end-to-end test is in
// shading_inputs_gltf_test.cpp.
#include "render/shading_inputs.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/gtc/type_precision.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/color.h"
#include "render/normal_mapping.h"
#include "render/surface.h"
#include "render/texture.h"
#include "render_test_scenes.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

using test::ray_from;

void expect_vec_near(const glm::vec3& a, const glm::vec3& b, float tol, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

ShadingInputs shade(const Scene& scene, const Ray& ray) {
  const BruteForce accel(scene.triangles);
  const Hit hit = accel.intersect(ray);
  EXPECT_TRUE(hit.valid());
  return evaluate_shading(scene, ray, hit);
}

// UVs as a function of the position on the unit quad.
using UvMap = glm::vec2 (*)(const glm::vec3&);
glm::vec2 upright(const glm::vec3& p) { return {p.x, 1.0f - p.y}; }  // image top at +y
glm::vec2 mirrored_u(const glm::vec3& p) { return {1.0f - p.x, 1.0f - p.y}; }
glm::vec2 upside_down(const glm::vec3& p) { return {p.x, p.y}; }

// The unit quad [0,1]^2 in z = 0, front +z, normals +z, UVs from `uv_of`, optional file
// tangent on every corner, and a 1x1 normal map holding `texel`.
Scene normal_mapped_quad(UvMap uv_of, const glm::vec4* tangent, glm::u8vec3 texel, float scale = 1.0f) {
  Scene scene;
  Material m = test::diffuse_material(glm::vec3(0.5f));
  m.normal_texture.texture = test::add_one_texel_texture(scene, texel.r, texel.g, texel.b);
  m.normal_texture.scale = scale;
  scene.materials.push_back(m);

  const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
  SceneBuilder builder(scene, "quad");
  for (const auto& tri : {std::array<glm::vec3, 3>{a, b, c}, std::array<glm::vec3, 3>{a, c, d}}) {
    const glm::vec3 normals[3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    const glm::vec2 uv[3] = {uv_of(tri[0]), uv_of(tri[1]), uv_of(tri[2])};
    glm::vec4 tangents[3];
    CornerAttributes attribs;
    attribs.normals = normals;
    attribs.texcoords = uv;
    if (tangent) {
      for (glm::vec4& t : tangents) t = *tangent;
      attribs.tangents = tangents;
    }
    builder.add_triangle(tri.data(), 0, 0, attribs);
  }
  return scene;
}

// The normal the spec's formula gives for `texel` in the frame (T, B, +z).
glm::vec3 expected_normal(glm::u8vec3 texel, float scale, const glm::vec3& t, const glm::vec3& b) {
  const glm::vec3 tn = (2.0f * glm::vec3(texel) / 255.0f - 1.0f) * glm::vec3(scale, scale, 1.0f);
  return glm::normalize(tn.x * t + tn.y * b + tn.z * glm::vec3(0, 0, 1));
}

// A texel leaning to tangent-space +X and -Y: (0.6, -0.4, 0.69) before normalising.
constexpr glm::u8vec3 kTiltedTexel(204, 77, 215);

struct FrameCase {
  const char* name;
  UvMap uv_of;
  bool file_tangent;
  glm::vec4 tangent;  // when file_tangent
  glm::vec3 t, b;     // the frame the normal map must use
};

TEST(ShadingNormalMap, TiltsTheNormalTheWayTheFrameSays) {
  const FrameCase cases[] = {
      {"generated, upright image", upright, false, {}, {1, 0, 0}, {0, 1, 0}},
      {"generated, mirrored u", mirrored_u, false, {}, {-1, 0, 0}, {0, 1, 0}},
      {"generated, upside-down image", upside_down, false, {}, {1, 0, 0}, {0, -1, 0}},
      {"file tangent +x, w = +1", upright, true, {1, 0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
      {"file tangent +x, w = -1", upright, true, {1, 0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
      {"file tangent +y, w = +1", upright, true, {0, 1, 0, 1}, {0, 1, 0}, {-1, 0, 0}},
  };
  for (const FrameCase& c : cases) {
    const Scene scene = normal_mapped_quad(c.uv_of, c.file_tangent ? &c.tangent : nullptr, kTiltedTexel);
    for (const glm::vec3 at : {glm::vec3(0.3f, 0.6f, 0), glm::vec3(0.8f, 0.1f, 0)}) {  // both triangles
      const ShadingInputs si = shade(scene, ray_from(at + glm::vec3(0, 0, 2), {0, 0, -1}));
      const glm::vec3 expected = expected_normal(kTiltedTexel, 1.0f, c.t, c.b);
      expect_vec_near(si.ns, expected, 1e-6f, c.name);
      // The direction in words: X leans along T, -Y along -B.
      EXPECT_GT(glm::dot(si.ns, c.t), 0.5f) << c.name;
      EXPECT_LT(glm::dot(si.ns, c.b), -0.3f) << c.name;
      EXPECT_EQ(si.ng, glm::vec3(0, 0, 1)) << c.name;
      EXPECT_NEAR(glm::length(si.tangent), 1.0f, 1e-6f) << c.name;
      EXPECT_NEAR(glm::dot(si.tangent, si.ns), 0.0f, 1e-6f) << c.name;
      EXPECT_GT(glm::dot(si.tangent, c.t), 0.5f) << c.name << ": the BSDF frame keeps T's direction";
    }
  }
}

TEST(ShadingNormalMap, ScaleShrinksTheTilt) {
  const Scene scene = normal_mapped_quad(upright, nullptr, kTiltedTexel, 0.25f);
  const ShadingInputs si = shade(scene, ray_from({0.3f, 0.6f, 2}, {0, 0, -1}));
  expect_vec_near(si.ns, expected_normal(kTiltedTexel, 0.25f, {1, 0, 0}, {0, 1, 0}), 1e-6f, "scale 0.25");
}

TEST(ShadingNormalMap, BackSideFlipsTheMappedNormal) {
  const Scene scene = normal_mapped_quad(upright, nullptr, kTiltedTexel);
  const ShadingInputs si = shade(scene, ray_from({0.3f, 0.6f, -2}, {0, 0, 1}));
  EXPECT_FALSE(si.front_face);
  EXPECT_EQ(si.ng, glm::vec3(0, 0, -1));
  expect_vec_near(si.ns, -expected_normal(kTiltedTexel, 1.0f, {1, 0, 0}, {0, 1, 0}), 1e-6f, "back side");
}

TEST(ShadingNormalMap, NormalHidingTheViewerIsBentBack) {
  // Tangent space (1, 0, 0.1): the mapped normal lies almost along +x.
  const glm::u8vec3 texel(255, 128, 140);
  const Scene scene = normal_mapped_quad(upright, nullptr, texel);
  const glm::vec3 origin(-1.0f, 0.5f, 0.2f), target(0.5f, 0.5f, 0.0f);
  const glm::vec3 dir = glm::normalize(target - origin);  // low, from the -x side
  const glm::vec3 wo = -dir;
  const glm::vec3 mapped = expected_normal(texel, 1.0f, {1, 0, 0}, {0, 1, 0});
  ASSERT_LT(glm::dot(mapped, wo), 0.0f) << "the test needs a normal that hides the viewer";
  const ShadingInputs si = shade(scene, ray_from(origin, dir));
  EXPECT_NEAR(glm::length(si.ns), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(si.ns, wo), kMinShadingCosine, 1e-5f);
  EXPECT_GT(glm::dot(si.ns, si.ng), 0.0f);
  EXPECT_NEAR(glm::dot(glm::cross(mapped, wo), si.ns), 0.0f, 1e-5f) << "bent within the plane of ns and wo";
  // The same normal seen from above is left alone.
  const ShadingInputs above = shade(scene, ray_from({0.5f, 0.5f, 2}, {0, 0, -1}));
  expect_vec_near(above.ns, mapped, 1e-6f, "viewer above");
}

TEST(ShadingNormalMap, ClearcoatNormalIsItsOwnMapNotTheBases) {
  // KHR_materials_clearcoat: the coat uses clearcoatNormalTexture, else the interpolated
  // normal, never the base's normalTexture.
  Scene scene = normal_mapped_quad(upright, nullptr, kTiltedTexel);
  scene.materials[0].clearcoat = 1.0f;
  const glm::vec3 tilted = expected_normal(kTiltedTexel, 1.0f, {1, 0, 0}, {0, 1, 0});
  ShadingInputs si = shade(scene, ray_from({0.3f, 0.6f, 2}, {0, 0, -1}));
  expect_vec_near(si.ns, tilted, 1e-6f, "base normal map");
  expect_vec_near(si.clearcoat_normal, {0, 0, 1}, 1e-6f, "coat without its own map");
  // Swap the maps: the coat leans, the base does not.
  Material& m = scene.materials[0];
  m.clearcoat_normal_texture = m.normal_texture;
  m.normal_texture = TextureRef{};
  si = shade(scene, ray_from({0.3f, 0.6f, 2}, {0, 0, -1}));
  expect_vec_near(si.ns, {0, 0, 1}, 1e-6f, "base without a map");
  expect_vec_near(si.clearcoat_normal, tilted, 1e-6f, "coat with its own map");
  // Seen from below, both flip to the viewer's side.
  si = shade(scene, ray_from({0.3f, 0.6f, -2}, {0, 0, 1}));
  EXPECT_LT(si.clearcoat_normal.z, 0.0f);
}

TEST(ShadingInputs, LayerFactorsTimesTheirTextureChannels) {
  Scene scene = normal_mapped_quad(upright, nullptr, kTiltedTexel);
  Material& m = scene.materials[0];
  m.normal_texture = TextureRef{};
  const int tex = test::add_one_texel_texture(scene, 204, 102, 51);  // 0.8, 0.4, 0.2 linear
  m.clearcoat = 0.5f;
  m.clearcoat_texture.texture = tex;            // R
  m.clearcoat_roughness = 0.5f;
  m.clearcoat_roughness_texture.texture = tex;  // G
  m.sheen_color = {1.0f, 0.5f, 0.25f};
  m.sheen_color_texture.texture = tex;  // RGB, sRGB
  m.sheen_roughness = 0.5f;             // times A = 1 (an RGB image)
  m.sheen_roughness_texture.texture = tex;
  m.unlit = true;
  const ShadingInputs si = shade(scene, ray_from({0.3f, 0.6f, 2}, {0, 0, -1}));
  EXPECT_NEAR(si.clearcoat, 0.4f, 1e-6f);
  EXPECT_NEAR(si.clearcoat_roughness, 0.2f, 1e-6f);
  EXPECT_NEAR(si.sheen_color.r, srgb_to_linear(0.8f), 1e-3f);
  EXPECT_NEAR(si.sheen_color.g, 0.5f * srgb_to_linear(0.4f), 1e-3f);
  EXPECT_NEAR(si.sheen_color.b, 0.25f * srgb_to_linear(0.2f), 1e-3f);
  EXPECT_NEAR(si.sheen_roughness, 0.5f, 1e-6f);
  EXPECT_TRUE(si.unlit);
}

TEST(ShadingInputs, WithoutANormalMapTheGeometryIsMakeSurfacePoints) {
  Scene scene;
  scene.materials.push_back(test::diffuse_material(glm::vec3(0.5f)));
  const glm::vec3 p[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  const glm::vec3 normals[3] = {glm::normalize(glm::vec3(-0.3f, 0, 1)), glm::normalize(glm::vec3(0.3f, 0.2f, 1)),
                                glm::normalize(glm::vec3(0, -0.4f, 1))};
  CornerAttributes attribs;
  attribs.normals = normals;
  SceneBuilder(scene, "tri").add_triangle(p, 0, 0, attribs);
  const glm::vec3 flat_p[3] = {{0, 0, 1}, {2, 0, 1}, {0, 2, 1}};
  SceneBuilder(scene, "tri").add_triangle(flat_p, 0, 1);  // no normals: the geometric normal
  const BruteForce accel(scene.triangles);
  for (const Ray& ray : {ray_from({0.5f, 0.3f, 3}, {0, 0, -1}), ray_from({0.5f, 0.3f, -3}, {0.05f, 0.02f, 1}),
                         ray_from({0.7f, 0.6f, 0.5f}, {0, 0, -1})}) {
    const Hit hit = accel.intersect(ray);
    ASSERT_TRUE(hit.valid());
    const SurfacePoint sp = make_surface_point(scene, ray, hit);
    const ShadingInputs si = evaluate_shading(scene, ray, hit);
    EXPECT_EQ(si.p, sp.p);
    EXPECT_EQ(si.ng, sp.ng);
    EXPECT_EQ(si.ns, sp.ns);
    EXPECT_EQ(si.front_face, sp.front_face);
    EXPECT_EQ(si.material, sp.material);
    EXPECT_EQ(si.base_color, sp.base_color);
    EXPECT_NEAR(glm::dot(si.tangent, si.ns), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(si.tangent), 1.0f, 1e-6f);
  }
  const Ray down = ray_from({0.3f, 0.3f, 3}, {0, 0, -1});
  const ShadingInputs flat = shade(scene, down);
  EXPECT_EQ(flat.p.z, 1.0f);
  EXPECT_EQ(flat.ns, flat.ng) << "a primitive without normals shades with the geometric normal";
  EXPECT_EQ(flat.ng, glm::vec3(0, 0, 1));
}

TEST(ShadingInputs, AlphaFollowsTheAlphaMode) {
  Scene scene;
  const glm::vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Material m = test::diffuse_material(glm::vec3(1.0f));
  m.base_color.a = 0.4f;
  scene.materials.push_back(m);
  SceneBuilder(scene, "tri").add_triangle(p, 0, 0);
  const Ray ray = ray_from({0.2f, 0.2f, 1}, {0, 0, -1});
  EXPECT_EQ(shade(scene, ray).alpha, 1.0f) << "OPAQUE ignores alpha";
  scene.materials[0].alpha_mode = AlphaMode::Blend;
  EXPECT_EQ(shade(scene, ray).alpha, 0.4f);
  scene.materials[0].alpha_mode = AlphaMode::Mask;
  EXPECT_EQ(shade(scene, ray).alpha, 0.0f) << "0.4 < cutoff 0.5";
  scene.materials[0].alpha_cutoff = 0.4f;
  EXPECT_EQ(shade(scene, ray).alpha, 1.0f) << "alpha >= cutoff is opaque";
}

TEST(ShadingInputs, UntexturedMaterialPassesItsFactorsThrough) {
  Scene scene;
  const glm::vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Material m;
  m.base_color = {0.1f, 0.2f, 0.3f, 1.0f};
  m.metallic = 0.25f;
  m.roughness = 0.75f;
  m.emissive_factor = {1.0f, 0.5f, 0.0f};
  m.emissive_strength = 3.0f;
  m.ior = 1.33f;
  m.specular = 0.5f;
  m.specular_color = {0.9f, 0.8f, 0.7f};
  m.transmission = 0.6f;
  m.thickness = 0.02f;
  m.attenuation_distance = 4.0f;
  m.attenuation_color = {0.5f, 0.6f, 0.7f};
  scene.materials.push_back(m);
  SceneBuilder(scene, "tri").add_triangle(p, 0, 0);
  const ShadingInputs si = shade(scene, ray_from({0.2f, 0.2f, 1}, {0, 0, -1}));
  EXPECT_EQ(si.base_color, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(si.metallic, 0.25f);
  EXPECT_EQ(si.roughness, 0.75f);
  EXPECT_EQ(si.emission, glm::vec3(3.0f, 1.5f, 0.0f));
  EXPECT_EQ(si.ior, 1.33f);
  EXPECT_EQ(si.specular, 0.5f);
  EXPECT_EQ(si.specular_color, glm::vec3(0.9f, 0.8f, 0.7f));
  EXPECT_EQ(si.transmission, 0.6f);
  EXPECT_EQ(si.thickness, 0.02f);
  EXPECT_EQ(si.attenuation_distance, 4.0f);
  EXPECT_EQ(si.attenuation_color, glm::vec3(0.5f, 0.6f, 0.7f));
  EXPECT_EQ(si.uv0, glm::vec2(0.0f)) << "no TEXCOORD_0";
  EXPECT_EQ(si.uv1, glm::vec2(0.0f));
}

// ---- Folding directions where the shading and geometric normals disagree ----

// Shading inputs with ng = +z and ns leaning `lean` degrees toward +x.
ShadingInputs leaning(float lean_degrees) {
  ShadingInputs si;
  const float lean = lean_degrees * 3.14159265f / 180.0f;
  si.ng = {0, 0, 1};
  si.ns = {std::sin(lean), 0, std::cos(lean)};
  return si;
}

// Directions on a grid uniform in (z, phi), each standing for the same solid angle.
template <typename F>
void for_sphere_grid(int nz, int nphi, F&& f) {
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) {
      const float z = -1.0f + 2.0f * (float(i) + 0.5f) / float(nz), phi = 6.2831853f * (float(j) + 0.5f) / float(nphi);
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      f(glm::vec3(r * std::cos(phi), r * std::sin(phi), z), 4.0 * 3.14159265358979 / (double(nz) * nphi));
    }
}

TEST(FoldedDirections, WedgeDirectionsLandWhereBothNormalsAgreeOnTheSameSideOfNs) {
  for (float lean : {10.0f, 45.0f, 80.0f}) {
    const ShadingInputs si = leaning(lean);
    int wedge = 0;
    for_sphere_grid(64, 128, [&](const glm::vec3& d, double) {
      glm::vec3 w = d;
      const bool agreed = sides_agree(si, d);
      ASSERT_TRUE(fold_direction(si, w)) << "lean " << lean;
      EXPECT_TRUE(sides_agree(si, w));
      EXPECT_EQ(glm::dot(w, si.ns) > 0.0f, glm::dot(d, si.ns) > 0.0f) << "a reflection stays a reflection";
      if (agreed) {
        EXPECT_EQ(w, d) << "directions outside the wedge stay";
      } else {
        ++wedge;
        EXPECT_NEAR(w.z, -d.z, 1e-6f);
        EXPECT_EQ(mirror_through_surface(si, w), d) << "the mirror is its own inverse";
      }
    });
    EXPECT_GT(wedge, 0) << "lean " << lean;
  }
}

TEST(FoldedDirections, FoldedCosineLosesNothing) {
  // A Lambertian lobe around a leaning ns: the cosine over ns's upper hemisphere integrates
  // to pi. Dropping the wedge loses the part below the surface; folding it keeps all of it.
  for (float lean : {30.0f, 60.0f}) {
    const ShadingInputs si = leaning(lean);
    double folded = 0.0, dropped = 0.0;
    for_sphere_grid(1024, 1024, [&](const glm::vec3& d, double dw) {
      auto cosine = [&](const glm::vec3& w) { return std::max(0.0, double(glm::dot(si.ns, w))); };
      folded += evaluate_folded<double>(si, d, cosine) * dw;
      dropped += (sides_agree(si, d) ? cosine(d) : 0.0) * dw;
    });
    EXPECT_NEAR(folded, 3.14159265358979, 2e-3) << "lean " << lean;
    EXPECT_LT(dropped, 3.14159265358979 - 0.1) << "lean " << lean << ": the test must see the wedge";
  }
}

// The viewer's mirror image about `n`.
glm::vec3 mirror_of(const glm::vec3& wo, const glm::vec3& n) { return 2.0f * glm::dot(n, wo) * n - wo; }

TEST(BentShadingNormal, StaysWhereTheViewersMirrorImageClearsTheSurface) {
  // ns leaning 30 degrees toward +x, viewers on that side: the mirror image lies 60 - view
  // degrees off ng (toward -x past 60), above the surface for every view there.
  const ShadingInputs si = leaning(30.0f);
  for (float view : {0.0f, 20.0f, 45.0f, 59.0f}) {
    const float a = view * 3.14159265f / 180.0f;
    const glm::vec3 wo(std::sin(a), 0.0f, std::cos(a));
    EXPECT_EQ(bent_shading_normal(si.ng, si.ns, wo), si.ns) << "view " << view;
  }
  EXPECT_EQ(bent_shading_normal(si.ng, si.ng, glm::normalize(glm::vec3(1, 2, 0.001f))), si.ng) << "flat: never bent";
}

TEST(BentShadingNormal, LiftsTheMirrorImageExactlyToItsHeightBound) {
  // Views all around a normal leaning 20-80 degrees (at least 1.8 degrees over the surface,
  // so h = 0.01; grazing ones: the next test): where the image about ns falls below
  // h = min(0.9 wo.ng, 0.01), the bent normal's image rises exactly to h,
  // keeps the image's azimuth about ng, and faces the viewer; elsewhere nothing moves.
  int bent = 0;
  for (float lean : {20.0f, 50.0f, 80.0f}) {
    const ShadingInputs si = leaning(lean);
    for_sphere_grid(32, 64, [&](const glm::vec3& d, double) {
      if (!(d.z > 0.0f) || !(glm::dot(d, si.ns) > 0.0f)) return;  // ns faces the viewer (face_viewer)
      const glm::vec3 n = bent_shading_normal(si.ng, si.ns, d);
      const float h = std::min(0.9f * d.z, 0.01f);
      const glm::vec3 before = mirror_of(d, si.ns);
      if (before.z >= h) {
        EXPECT_EQ(n, si.ns);
        return;
      }
      ++bent;
      ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
      const glm::vec3 after = mirror_of(d, n);
      EXPECT_NEAR(after.z, h, 2e-5f) << "lean " << lean;
      EXPECT_NEAR(glm::length(after), 1.0f, 1e-5f);
      EXPECT_GT(glm::dot(n, d), 0.0f);
      EXPECT_GT(n.z, 0.0f);
      // The same azimuth: the tangential parts point the same way.
      const glm::vec2 t0(before.x, before.y), t1(after.x, after.y);
      if (glm::length(t0) > 1e-3f) {
        EXPECT_NEAR(glm::dot(glm::normalize(t0), glm::normalize(t1)), 1.0f, 1e-4f);
      }
    });
  }
  EXPECT_GT(bent, 100) << "the test must see bent normals";
}

TEST(BentShadingNormal, GrazingViewsLiftTheImageToNineTenthsOfTheirHeight) {
  // Views 1e-2 to 1e-3 over the surface (h = 0.9 wo.ng < 0.01), nearly across a normal
  // leaning 40 degrees, each at an azimuth where ns faces it by `facing` (at least
  // evaluate_shading's 1e-3) and its image falls below h: the image rises to exactly h,
  // to float rounding of a half vector about |wo + image| long.
  const ShadingInputs si = leaning(40.0f);
  int tested = 0;
  const float view_facing[3][2] = {{1e-2f, 5e-3f}, {3e-3f, 2e-3f}, {1e-3f, 1.1e-3f}};
  for (const auto& [height, facing] : view_facing) {
    const float r = std::sqrt(1.0f - height * height);
    // ns.wo = sin(40) r cos(phi) + cos(40) height = facing.
    const float phi = std::acos((facing - si.ns.z * height) / (si.ns.x * r));
    for (const float azimuth : {phi, -phi}) {
      const glm::vec3 wo(r * std::cos(azimuth), r * std::sin(azimuth), height);
      ASSERT_GE(glm::dot(wo, si.ns), 1e-3f);
      const glm::vec3 n = bent_shading_normal(si.ng, si.ns, wo);
      const float h = 0.9f * height;
      ASSERT_LT(mirror_of(wo, si.ns).z, h) << height;
      ASSERT_NE(n, si.ns) << height;
      EXPECT_GT(glm::dot(n, wo), 0.0f);
      const glm::vec3 after = mirror_of(wo, n);
      EXPECT_NEAR(after.z, h, 4e-7f / glm::length(wo + after)) << height << " " << azimuth;
      ++tested;
    }
  }
  EXPECT_EQ(tested, 6);
}

TEST(BentShadingNormal, DegenerateInputsGiveTheGeometricNormal) {
  const glm::vec3 ng(0, 0, 1);
  // ns the half vector of wo and -ng: the image points straight into the surface, with no
  // azimuth to lift it along.
  const glm::vec3 wo(0.6f, 0.0f, 0.8f);
  EXPECT_EQ(bent_shading_normal(ng, glm::normalize(wo - ng), wo), ng);
  // Not a number anywhere.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(bent_shading_normal(ng, glm::vec3(nan, 0, 0), glm::normalize(glm::vec3(1, 0, 1))), ng);
}

}  // namespace
}  // namespace lancer
