// The path tracer's wavefront: the paths of one or more blocks advanced together give, lane
// by lane, exactly the radiance of each path traced alone, whatever the wavefront holds; and
// the batch counts add up to the rays traced.
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/environment.h"
#include "render/path.h"
#include "render/primary_block.h"
#include "render/renderer.h"
#include "scene/load_scene.h"
#include "test_paths.h"

namespace lancer {
namespace {

bool same_bits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every lane of a block against the same path alone, with the environment, two light
// samples and the punctual-free Cornell lights; blocks of 64, of 7 and of 1, and a
// wavefront of four blocks (256 paths).
TEST(PathBlock, EachLaneIsThePathTracedAlone) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const KdTree kd(scene.triangles);
  const AreaLights lights(scene);
  const Environment sky(glm::vec3(0.3f, 0.4f, 0.5f));
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), 40, 40);
  for (const int light_samples : {1, 2}) {
    const PathIntegrator path(scene, kd, lights, &sky, 16, light_samples);
    PathIntegrator::Scratch scratch;
    // Single blocks, and a whole wavefront of kWavefrontBlocks blocks (256 paths).
    const std::vector<std::vector<PixelBlock>> wavefronts = {
        {{8, 16, 16, 24}},
        {{30, 3, 37, 4}},
        {{20, 20, 21, 21}},
        {{0, 0, 8, 8}, {8, 0, 16, 8}, {0, 8, 8, 16}, {8, 8, 16, 16}}};
    for (const std::vector<PixelBlock>& blocks : wavefronts) {
      PrimaryBlock primary;
      for (const PixelBlock& block : blocks) primary.add(camera, PixelFilter::box(), block, 5, 9);
      primary.trace(kd, TraceMode::Packet);
      std::vector<SobolSampler> alone(primary.samplers(), primary.samplers() + primary.size());
      std::vector<glm::vec3> together(static_cast<std::size_t>(primary.size()));
      std::uint64_t block_rays = 0, lane_rays = 0;
      path.radiance_block(primary.rays(), primary.hits(), primary.samplers(), primary.size(), together.data(),
                          block_rays, scratch);
      int lit = 0;
      for (int i = 0; i < primary.size(); ++i) {
        const glm::vec3 L = path.radiance_from_hit(primary.ray(i), primary.hit(i), alone[static_cast<std::size_t>(i)],
                                                   lane_rays);
        EXPECT_TRUE(same_bits(L, together[static_cast<std::size_t>(i)])) << "lane " << i;
        lit += L.x + L.y + L.z > 0.0f;
      }
      EXPECT_EQ(block_rays, lane_rays);
      EXPECT_GT(lit, 0);
    }
  }
}

TEST(PathBlock, BatchCountsAddUpToTheRaysTraced) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = s.height = 32;
  s.spp = 2;
  s.threads = 2;
  const PinholeCamera camera = PinholeCamera::from_desc(scene.cameras.at(0), s.width, s.height);
  RenderStats stats;
  render_image(scene, kd, camera, s, stats);
  const PathBatchStats& b = stats.path_batches;
  EXPECT_EQ(stats.setup_rays + stats.primary_rays + b.continuation_rays + b.shadow_rays + b.crossing_rays +
                b.emission_rays + stats.light_rays,
            stats.rays);
  EXPECT_GT(stats.light_rays, 0u);  // the spheres' caustics are light-traced
  // The light shows: its blocks were found, and their samples traced the emission's own rays.
  EXPECT_GT(stats.setup_rays, 0u);
  EXPECT_GT(b.emission_rays, 0u);
  EXPECT_GT(b.shadow_batches, 0u);
  // One batch per bounce of a wavefront (a 16x16 tile: four blocks): at least one and at
  // most max_depth per wavefront and pass.
  static_assert(kWavefrontBlocks == 4, "a 16x16 tile is one wavefront");
  ASSERT_EQ(s.tile_size, 16);
  const std::uint64_t wavefronts = 2 * 2 * 2;  // 32x32 pixels in 16x16 tiles, 2 passes
  EXPECT_GE(b.continuation_batches, wavefronts);
  EXPECT_LE(b.continuation_batches, wavefronts * static_cast<std::uint64_t>(s.max_depth));
  EXPECT_LE(b.packet_rays, b.continuation_rays);
  // A block's first-bounce shadow rays towards the ceiling light are mostly of one octant.
  EXPECT_GT(b.shadow_packet_rays, b.shadow_rays / 10);
  EXPECT_LE(b.shadow_packet_rays, b.shadow_rays);
}

}  // namespace
}  // namespace lancer
