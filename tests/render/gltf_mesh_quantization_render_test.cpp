// A KHR_mesh_quantization copy of a mesh renders the uncompressed mesh's image: 16-bit
// positions scaled back by the node, 8-bit normals, 16-bit texture coordinates.
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "gltf_mesh_scenes.h"
#include "image_estimate.h"
#include "scene/gltf_test_files.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using test::lumpy_sphere;
using test::Mesh;
using test::render_lit_mesh;
using test::write_float_copy;

// Positions as SHORT in [-32767, 32767] over the mesh's box, the node scaling them back;
// normals as normalized BYTE; UVs as normalized UNSIGNED_SHORT (both padded to 4 bytes).
void write_quantized_copy(const Mesh& m, const std::filesystem::path& file) {
  constexpr int kByte = 5120, kShort = 5122;
  constexpr float kExtent = 1.2f;  // every |coordinate| is below it
  std::vector<std::int16_t> pos;
  std::vector<std::int8_t> nrm;
  std::vector<std::uint16_t> uv;
  for (std::size_t k = 0; k < m.positions.size(); ++k) {
    for (int c = 0; c < 3; ++c) pos.push_back(std::int16_t(std::lround(m.positions[k][c] / kExtent * 32767.0f)));
    pos.push_back(0);
    for (int c = 0; c < 3; ++c) nrm.push_back(std::int8_t(std::lround(m.normals[k][c] * 127.0f)));
    nrm.push_back(0);
    for (int c = 0; c < 2; ++c) uv.push_back(std::uint16_t(std::lround(m.uvs[k][c] * 65535.0f)));
  }
  GltfBuilder b;
  const std::size_t n = m.positions.size();
  const int p = b.add_accessor(b.add_view(pos.data(), pos.size() * 2, 8), kShort, n, "VEC3");
  const int q = b.add_accessor(b.add_view(nrm.data(), nrm.size(), 4), kByte, n, "VEC3", true);
  const int t = b.add_accessor(b.add_view(uv.data(), uv.size() * 2), GltfBuilder::kUShort, n, "VEC2", true);
  const int mesh = b.add_mesh({{"POSITION", p}, {"NORMAL", q}, {"TEXCOORD_0", t}}, 4, b.add_indices(m.indices));
  const float s = kExtent / 32767.0f;
  b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {s, s, s}}})});
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  b.write_data_uri_gltf(file);
}

class GltfQuantizationRender : public gltf_test::GltfTempDir {};

TEST_F(GltfQuantizationRender, QuantizedCopyGivesTheSameImage) {
  const Mesh mesh = lumpy_sphere();
  write_float_copy(mesh, path("float.gltf"));
  write_quantized_copy(mesh, path("quantized.gltf"));
  const ImageRGB reference = render_lit_mesh(path("float.gltf"));
  const ImageRGB quantized = render_lit_mesh(path("quantized.gltf"));
  double mean = 0.0;
  for (float v : reference.rgb) mean += v;
  ASSERT_GT(mean, 0.0) << "the sphere must be lit";
  // 8 x 8 blocks within 1 %: normals off by up to half a step of 1/127 (0.3 degrees),
  // positions by 1.2 / 65534.
  EXPECT_LT(test::largest_block_difference(quantized, reference, 8), 0.01);
}

}  // namespace
}  // namespace lancer
