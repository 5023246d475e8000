// Small hand-built scenes for the renderer's tests: materials and axis-aligned squares.
#pragma once

#include <cstdint>
#include <utility>

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "render/texture.h"
#include "scene/procedural.h"
#include "scene/scene.h"

namespace lancer::test {

// The materials below are double-sided (both sides seen, shaded and casting shadows) unless
// they say otherwise; single_sided_test.cpp tests glTF's default, single-sided faces.
inline Material diffuse_material(const glm::vec3& albedo) {
  Material m;
  m.double_sided = true;
  m.base_color = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  return m;
}

inline Material mirror_material(const glm::vec3& color) {
  Material m;
  m.double_sided = true;
  m.base_color = glm::vec4(color, 1.0f);
  m.metallic = 1.0f;
  m.roughness = 0.0f;
  return m;
}

inline Material glass_material(float ior) {
  Material m = diffuse_material(glm::vec3(1.0f));
  m.roughness = 0.0f;
  m.transmission = 1.0f;
  m.ior = ior;
  return m;
}

// A black diffuse surface emitting `radiance` from its front side; single-sided, so its
// back is not there at all (render/shading_inputs.h, culls_back_faces).
inline Material emissive_material(const glm::vec3& radiance, float strength = 1.0f) {
  Material m = diffuse_material(glm::vec3(0.0f));
  m.double_sided = false;
  m.emissive_factor = radiance;
  m.emissive_strength = strength;
  return m;
}

// A 1x1 RGB image holding `texel` and a nearest-filtered texture of it; returns the
// texture's index, for a material's TextureRef.
inline int add_one_texel_texture(Scene& scene, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image image;
  image.width = image.height = 1;
  image.channels = 3;
  image.pixels = {r, g, b};
  scene.images.push_back(image);
  Texture texture;
  texture.image = static_cast<int>(scene.images.size() - 1);
  texture.mag_filter = kFilterNearest;
  scene.textures.push_back(texture);
  return static_cast<int>(scene.textures.size() - 1);
}

inline std::uint32_t add_material(Scene& scene, const Material& m) {
  scene.materials.push_back(m);
  return static_cast<std::uint32_t>(scene.materials.size() - 1);
}

// The square [cx - half, cx + half] x [cy - half, cy + half] in the plane z, its front side
// facing +z (facing_up) or -z.
inline void add_square_z(Scene& scene, float cx, float cy, float z, float half, bool facing_up,
                         std::uint32_t material) {
  const glm::vec3 a(cx - half, cy - half, z), b(cx + half, cy - half, z), c(cx + half, cy + half, z),
      d(cx - half, cy + half, z);
  if (facing_up)
    append_quad(scene, a, b, c, d, material);
  else
    append_quad(scene, a, d, c, b, material);
}

// Turns the triangles from `first` on inside out (their front sides face the other way).
inline void flip_winding(Scene& scene, std::size_t first) {
  TriangleSoA& t = scene.triangles;
  for (std::size_t i = first; i < t.size(); ++i) {
    std::swap(t.x[1][i], t.x[2][i]);
    std::swap(t.y[1][i], t.y[2][i]);
    std::swap(t.z[1][i], t.z[2][i]);
    std::swap(scene.normals[3 * i + 1], scene.normals[3 * i + 2]);
    for (glm::vec3* n : {&scene.normals[3 * i], &scene.normals[3 * i + 1], &scene.normals[3 * i + 2]}) *n = -*n;
  }
}

inline Ray ray_from(const glm::vec3& org, const glm::vec3& dir) {
  Ray r;
  r.org = org;
  r.dir = dir;
  return r;
}

}  // namespace lancer::test
