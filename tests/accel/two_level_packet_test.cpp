// Packets of the two-level accelerator (TwoLevelAccelerator::intersect_packet and
// occluded_packet): every lane bit for bit (memcmp of Hit) the single-ray answer, and that
// the definition's (the brute-force bottoms), on every ISA, for coherent camera tiles,
// shadow packets, incoherent packets with mixed direction signs and partial packets.
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "accel/two_level.h"
#include "two_level_test_support.h"

namespace lancer::test {
namespace {

bool mixed_signs(const std::vector<Ray>& rays) {
  for (int a = 0; a < 3; ++a) {
    bool neg = false, pos = false;
    for (const Ray& r : rays) {
      if (r.dir[a] < 0.0f) neg = true;
      if (r.dir[a] > 0.0f) pos = true;
    }
    if (neg && pos) return true;
  }
  return false;
}

struct Coverage {
  std::size_t rays = 0, hits = 0, occluded = 0, coherent_packets = 0, mixed_packets = 0, partial_packets = 0;
};

class TwoLevelPacket : public KdIsaTest {
 protected:
  void SetUp() override {
    KdIsaTest::SetUp();
    if (IsSkipped()) return;
    scene_ = random_instanced_scene(isa_seed() + 21 + std::uint64_t(extra_instances()), extra_instances());
    kd_ = std::make_unique<TwoLevelAccelerator>(scene_.tris, scene_.geometry, "kdtree", KdBuildOptions{}, isa());
    ASSERT_EQ(kd_->meets_few_instances(), extra_instances() == 0);
    brute_ = std::make_unique<TwoLevelAccelerator>(scene_.tris, scene_.geometry, "brute");
    flat_ = flatten(scene_);
    box_ = flat_.tris.bounds();
  }

  void check_packet(const std::vector<Ray>& rays, Coverage& cov) {
    const int n = static_cast<int>(rays.size());
    std::vector<Hit> hits(rays.size());
    const std::unique_ptr<bool[]> blocked(new bool[rays.size() + 1]);
    kd_->intersect_packet(rays.data(), hits.data(), n);
    kd_->occluded_packet(rays.data(), blocked.get(), n);
    std::size_t hit_count = 0;
    for (int i = 0; i < n; ++i) {
      const Hit single = kd_->intersect(rays[i]);
      ASSERT_TRUE(same_bits(hits[i], single))
          << "lane " << i << " of " << n << ", " << describe(rays[i]) << ": packet instance " << hits[i].instance
          << " prim " << hits[i].prim << " t " << hits[i].t << ", single ray instance " << single.instance << " prim "
          << single.prim << " t " << single.t;
      ASSERT_TRUE(same_bits(single, brute_->intersect(rays[i]))) << "lane " << i << ", " << describe(rays[i]);
      ASSERT_EQ(blocked[i], kd_->occluded(rays[i]))
          << "occlusion lane " << i << " of " << n << ", " << describe(rays[i]);
      ASSERT_EQ(blocked[i], brute_->occluded(rays[i])) << "occlusion lane " << i << ", " << describe(rays[i]);
      hit_count += hits[i].valid() ? 1 : 0;
      cov.occluded += blocked[i] ? 1 : 0;
    }
    // The brute-force bottoms' packets (Accelerator's default, one ray at a time) too.
    std::vector<Hit> brute_hits(rays.size());
    brute_->intersect_packet(rays.data(), brute_hits.data(), n);
    for (int i = 0; i < n; ++i) ASSERT_TRUE(same_bits(brute_hits[i], hits[i])) << "brute packet lane " << i;
    cov.rays += rays.size();
    cov.hits += hit_count;
    (mixed_signs(rays) ? cov.mixed_packets : cov.coherent_packets) += 1;
    cov.partial_packets += (hit_count > 0 && hit_count < rays.size()) ? 1 : 0;
  }

  // 16: the top level's tree (23 instances); 0: few instances, met one by one.
  virtual int extra_instances() const { return 16; }

  void camera_tiles_and_shadow_packets();
  void incoherent_and_partial_packets();

  Pinhole view(glm::vec3 from, float fov) const {
    const glm::vec3 c = box_.center(), e = box_.extent();
    const float reach = std::fmax(e.x, std::fmax(e.y, e.z));
    return Pinhole::looking_at(c + from * reach, c, {0, 1, 0}, fov, 32);
  }

  InstancedScene scene_;
  std::unique_ptr<TwoLevelAccelerator> kd_, brute_;
  FlatScene flat_;
  Bounds3 box_;
};

// 8x8 camera tiles from outside at two distances and a wide view from the centre (tiles
// there have mixed signs), and shadow packets from the camera hits towards a point light.
void TwoLevelPacket::camera_tiles_and_shadow_packets() {
  Coverage cov;
  const Pinhole views[] = {view({0.3f, 0.4f, 1.1f}, 45.0f), view({-0.9f, 0.2f, -0.7f}, 60.0f),
                           view({0.01f, 0.02f, 0.03f}, 110.0f)};
  const glm::vec3 light = box_.hi + 0.5f * box_.extent();
  for (const Pinhole& v : views) {
    for (const std::vector<Ray>& tile : camera_tiles(v, 32, 32)) {
      check_packet(tile, cov);
      if (HasFatalFailure()) return;
      std::vector<Ray> shadows;
      for (const Ray& r : tile) {
        const Hit h = kd_->intersect(r);
        if (!h.valid()) continue;
        Ray s;
        s.org = light;
        s.dir = r.org + h.t * r.dir - light;
        s.tfar = 0.999f;
        shadows.push_back(s);
      }
      if (shadows.empty()) continue;
      check_packet(shadows, cov);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(cov.hits, cov.rays / 4);
  EXPECT_GT(cov.occluded, 0u);
  EXPECT_GT(cov.partial_packets, 0u);
  EXPECT_GT(cov.coherent_packets, cov.mixed_packets) << "most camera tiles should share direction signs";
  EXPECT_GT(cov.mixed_packets, 0u) << "the wide view should give mixed-sign tiles";
}

// Incoherent packets of every ray kind (mixed signs, origins inside instances, segments,
// axis-parallel and distant rays) and partial packets of 1..64 rays, coherent or not.
void TwoLevelPacket::incoherent_and_partial_packets() {
  Coverage cov;
  for (std::size_t p = 0; p < 24; ++p) {
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < 64; ++i) rays.push_back(instanced_scene_ray(scene_, flat_, box_, isa_seed() + p, i));
    check_packet(rays, cov);
    if (HasFatalFailure()) return;
  }
  const auto tiles = camera_tiles(view({0.2f, 0.9f, 0.8f}, 50.0f), 32, 32);
  for (int count = 1; count <= 64; ++count) {
    check_packet(std::vector<Ray>(tiles[count % tiles.size()].begin(), tiles[count % tiles.size()].begin() + count),
                 cov);
    if (HasFatalFailure()) return;
    std::vector<Ray> mixed;
    for (int i = 0; i < count; ++i)
      mixed.push_back(instanced_scene_ray(scene_, flat_, box_, isa_seed() + 1000 + count, std::size_t(i)));
    check_packet(mixed, cov);
    if (HasFatalFailure()) return;
  }
  // More than one packet's worth in one call.
  std::vector<Ray> many;
  for (const auto& t : tiles) many.insert(many.end(), t.begin(), t.end());
  many.resize(64 * 3 + 17);
  check_packet(many, cov);
  EXPECT_GT(cov.hits, cov.rays / 4);
  EXPECT_GT(cov.mixed_packets, 0u);
}

class TwoLevelPacketFew : public TwoLevelPacket {
 protected:
  int extra_instances() const override { return 0; }
};

TEST_P(TwoLevelPacket, CameraTilesAndShadowPackets) { camera_tiles_and_shadow_packets(); }
TEST_P(TwoLevelPacketFew, CameraTilesAndShadowPackets) { camera_tiles_and_shadow_packets(); }
TEST_P(TwoLevelPacket, IncoherentAndPartialPackets) { incoherent_and_partial_packets(); }
TEST_P(TwoLevelPacketFew, IncoherentAndPartialPackets) { incoherent_and_partial_packets(); }

// A deep top level: 3,000 small rotated boxes scattered through a volume, so packets use
// many stack levels and leaves, and two large boxes straddling many leaves (entered once
// per ray, Mailbox); packets against single rays, and a sample against the definition.
TEST_P(TwoLevelPacket, ManyInstancesDeepTopLevel) {
  InstancedScene s;
  Scene cube;
  append_box(cube, {{-1, -1, -1}, {1, 1, 1}}, 0);
  s.tris = cube.triangles;
  s.geometry.meshes = {{0, static_cast<std::uint32_t>(s.tris.size())}};
  TestRng rng(isa_seed() + 41);
  for (int i = 0; i < 3000; ++i) {
    const glm::dvec3 scale(rng.uniform(0.05f, 0.3f), rng.uniform(0.05f, 0.3f), rng.uniform(0.05f, 0.3f));
    const glm::dvec3 at(rng.uniform(-10.0f, 10.0f), rng.uniform(-10.0f, 10.0f), rng.uniform(-10.0f, 10.0f));
    s.geometry.instances.push_back(make_instance(0, random_linear(rng, scale), at));
  }
  // A floor and a tilted slab under and through them: met again in many leaves.
  s.geometry.instances.push_back(make_instance(0, glm::dmat3(12.0, 0, 0, 0, 0.05, 0, 0, 0, 12.0), {0, -10.5, 0}));
  s.geometry.instances.push_back(make_instance(0, random_linear(rng, {9.0, 0.2, 9.0}), {0, 0, 0}));
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree", {}, isa());
  ASSERT_GT(accel.top_level().nodes().size(), 1000u) << "a tree at least 10 levels deep";
  const InstanceScan scan(s);
  const auto tiles = camera_tiles(Pinhole::looking_at({3.0f, 4.0f, 25.0f}, {0, 0, 0}, {0, 1, 0}, 60.0f, 64), 64, 64);
  std::size_t hits = 0, rays = 0;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    std::vector<Hit> packet(64);
    std::unique_ptr<bool[]> blocked(new bool[64]);
    accel.intersect_packet(tiles[t].data(), packet.data(), 64);
    accel.occluded_packet(tiles[t].data(), blocked.get(), 64);
    for (int i = 0; i < 64; ++i) {
      const Hit single = accel.intersect(tiles[t][i]);
      ASSERT_TRUE(same_bits(packet[i], single)) << "tile " << t << " lane " << i << ", " << describe(tiles[t][i]);
      ASSERT_EQ(blocked[i], accel.occluded(tiles[t][i])) << "tile " << t << " lane " << i;
      if (t % 8 == 0 && i % 8 == 0) {
        ASSERT_TRUE(same_bits(single, scan.intersect(tiles[t][i]))) << describe(tiles[t][i]);
      }
      hits += single.valid() ? 1 : 0;
      ++rays;
    }
  }
  EXPECT_GT(hits, rays / 10);
  EXPECT_LT(hits, rays) << "some rays should pass between the boxes";
}

INSTANTIATE_TEST_SUITE_P(AllIsas, TwoLevelPacket, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);
INSTANTIATE_TEST_SUITE_P(AllIsas, TwoLevelPacketFew, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
