// EXT_mesh_gpu_instancing end to end: a 5 x 5 x 5 grid of instanced boxes is 125 distinct
// boxes in the primitive-id image (each copy's triangles get their own ids).
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/debug_integrators.h"
#include "render/renderer.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

class GltfInstancingRender : public gltf_test::GltfTempDir {};

TEST_F(GltfInstancingRender, GridOf125BoxesShows125InThePrimitiveIdImage) {
  GltfBuilder b;
  std::vector<glm::vec3> corners;
  for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? 0.1f : -0.1f, k & 2 ? 0.1f : -0.1f, k & 4 ? 0.1f : -0.1f);
  const std::vector<std::uint16_t> indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                              2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(corners)}}, 4, b.add_indices(indices));
  std::vector<glm::vec3> translations;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) translations.emplace_back(float(i), float(j), float(k));
  const json attributes = {{"TRANSLATION", b.add_vec3(translations)}};
  b.set_scene({b.add_node({{"mesh", mesh}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}})});
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.write_data_uri_gltf(path("grid.gltf"));
  const Scene scene = read_gltf(path("grid.gltf"));
  ASSERT_EQ(scene.triangle_count(), 125u * 12u);

  const KdTree kd(scene.triangles);
  const PinholeCamera cam = PinholeCamera::look_at({12.0f, 9.5f, 7.0f}, {2, 2, 2}, {0, 1, 0}, 0.6f, 256, 256);
  RenderSettings s;
  s.width = s.height = 256;
  s.spp = 1;
  s.integrator = IntegratorKind::PrimId;
  RenderStats stats;
  const ImageRGB image = render_image(scene, kd, cam, s, stats);

  // Each source triangle id's colour, back to the instance (12 triangles each).
  std::map<std::tuple<float, float, float>, std::uint32_t> instance_of;
  for (std::uint32_t id = 0; id < 1500; ++id) {
    const glm::vec3 c = primid_color(id);
    ASSERT_TRUE(instance_of.emplace(std::make_tuple(c.x, c.y, c.z), id / 12).second) << "two ids share a colour";
  }
  std::set<std::uint32_t> seen;
  for (std::size_t p = 0; p < image.rgb.size(); p += 3) {
    const auto it = instance_of.find(std::make_tuple(image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]));
    if (it != instance_of.end()) seen.insert(it->second);
  }
  EXPECT_EQ(seen.size(), 125u);
}

}  // namespace
}  // namespace lancer
