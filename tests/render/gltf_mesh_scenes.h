// Meshes written as glTF files in several encodings, and the render that compares them
// (tests/render/gltf_*_render_test.cpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "accel/kd_tree.h"
#include "render/renderer.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"

namespace lancer::test {

using gltf_test::GltfBuilder;

struct Mesh {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> indices;
};

// A lumpy sphere (radius 1 +- 0.15) of 48 x 24 quads, with smooth normals and UVs, open
// at the poles (whose fans would hold degenerate triangles: the float copy keeps some by
// a rounding of sin(pi) that the quantized copy does not have).
inline Mesh lumpy_sphere() {
  Mesh m;
  constexpr int kSlices = 48, kStacks = 24;
  for (int j = 0; j <= kStacks; ++j)
    for (int i = 0; i <= kSlices; ++i) {
      const float theta = 0.2f + 2.74f * float(j) / kStacks, phi = 6.2831853f * float(i) / kSlices;
      const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      m.positions.push_back(d * (1.0f + 0.15f * std::sin(3.0f * phi) * std::sin(2.0f * theta)));
      m.normals.push_back(d);
      m.uvs.emplace_back(float(i) / kSlices, float(j) / kStacks);
    }
  for (int j = 0; j < kStacks; ++j)
    for (int i = 0; i < kSlices; ++i) {
      const std::uint32_t a = std::uint32_t(j * (kSlices + 1) + i), b = a + 1, c = a + kSlices + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, c, b, d, c});  // front outwards
    }
  return m;
}

inline void write_float_copy(const Mesh& m, const std::filesystem::path& file) {
  GltfBuilder b;
  const int mesh = b.add_mesh(
      {{"POSITION", b.add_vec3(m.positions)}, {"NORMAL", b.add_vec3(m.normals)}, {"TEXCOORD_0", b.add_vec2(m.uvs)}}, 4,
      b.add_indices(m.indices));
  b.single_node_scene(mesh);
  b.write_data_uri_gltf(file);
}

// The glTF file `file` under a point light, path-traced at 64 x 64, direct light only
// (the same camera samples for any copy of the same mesh).
inline ImageRGB render_lit_mesh(const std::filesystem::path& file) {
  Scene scene = read_gltf(file);
  PunctualLight lamp;
  lamp.position = {3, 4, 5};
  lamp.intensity = 40.0f;
  scene.lights.push_back(lamp);
  const KdTree kd(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({0, 1, 4}, {0, 0, 0}, {0, 1, 0}, 0.7f, 64, 64);
  RenderSettings s;
  s.width = s.height = 64;
  s.spp = 16;
  s.max_depth = 1;
  s.seed = 4;
  RenderStats stats;
  return render_image(scene, kd, cam, s, stats);
}

}  // namespace lancer::test
