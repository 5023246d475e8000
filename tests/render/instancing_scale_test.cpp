// 10,000 instances of the Stanford bunny (690 million triangles drawn) load, build and
// render in the memory of one bunny plus a few hundred bytes per instance.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "render/camera.h"
#include "render/renderer.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// What each instance may cost beyond the one stored mesh and its tree, in the scene and
// the accelerator together: two transforms and an id base (104 bytes) and its share of the
// top-level tree.
constexpr std::size_t kBytesPerInstance = 512;

class InstancingScale : public gltf_test::GltfTempDir {};

TEST_F(InstancingScale, TenThousandBunniesTakeOneBunnyPlusAFewHundredBytesEach) {
  const std::filesystem::path obj = test::models_dir() / "stanford-bunny.obj";
  if (!std::filesystem::exists(obj)) GTEST_SKIP() << "shared meshes absent: " << obj;
  const Scene bunny = load_scene(obj);

  GltfBuilder b;
  std::vector<glm::vec3> corners;
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i < bunny.triangle_count(); ++i)
    for (int k = 0; k < 3; ++k) {
      indices.push_back(std::uint32_t(corners.size()));
      corners.push_back(bunny.triangles.vertex(i, k));
    }
  const int mesh = b.add_mesh({{"POSITION", b.add_vec3(corners)}}, 4, b.add_indices(indices));
  constexpr int kSide = 100;
  std::vector<glm::vec3> t, s;
  std::vector<glm::vec4> r;
  for (int i = 0; i < kSide * kSide; ++i) {
    const float angle = 0.37f * float(i);
    t.emplace_back(0.3f * float(i % kSide), 0.0f, 0.3f * float(i / kSide));
    r.emplace_back(0.0f, std::sin(angle), 0.0f, std::cos(angle));
    s.emplace_back(0.8f + 0.4f * float(i % 7) / 6.0f);
  }
  const json attributes = {{"TRANSLATION", b.add_vec3(t)}, {"ROTATION", b.add_vec4(r)}, {"SCALE", b.add_vec3(s)}};
  b.set_scene({b.add_node({{"mesh", mesh}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes}}}}}})});
  b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.write_data_uri_gltf(path("bunnies.gltf"));

  const Scene scene = read_gltf(path("bunnies.gltf"));
  ASSERT_EQ(scene.instancing.instances.size(), std::size_t(kSide * kSide));
  ASSERT_EQ(scene.triangle_count(), bunny.triangle_count());
  EXPECT_EQ(scene.drawn_triangle_count(), std::size_t(kSide * kSide) * bunny.triangle_count());

  const std::unique_ptr<Accelerator> one = make_accelerator("kdtree", bunny.triangles);
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", scene.triangles, scene.instancing);
  const std::size_t scene_bytes = scene.instancing.instances.size() * sizeof(Instance) +
                                  scene.instancing.meshes.size() * sizeof(MeshRange) +
                                  scene.instance_source_base.size() * sizeof(std::uint32_t);
  const std::size_t bound = one->memory_bytes() + std::size_t(kSide * kSide) * kBytesPerInstance;
  EXPECT_LE(accel->memory_bytes() + scene_bytes, bound)
      << "accelerator " << accel->memory_bytes() << " bytes, instances " << scene_bytes << " bytes, one bunny's tree "
      << one->memory_bytes() << " bytes";

  // Seen from above the grid's corner: many bunnies, each drawing its own ids.
  RenderSettings settings;
  settings.width = settings.height = 64;
  settings.spp = 1;
  settings.integrator = IntegratorKind::PrimId;
  const PinholeCamera camera = PinholeCamera::look_at({-3.0f, 6.0f, -3.0f}, {12.0f, 0.0f, 12.0f}, {0, 1, 0}, 0.9f, 64, 64);
  RenderStats stats;
  const ImageRGB image = render_image(scene, *accel, camera, settings, stats);
  std::set<std::vector<float>> colours;
  for (std::size_t p = 0; p < image.rgb.size(); p += 3) colours.insert({image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]});
  EXPECT_GT(colours.size(), 1000u);
}

}  // namespace
}  // namespace lancer
