// Moving instances in the two-level accelerator (issue 19, motion blur): a moving instance
// at time t is the static instance instance_at gives then, bit for bit; the whole scene
// meets the definition (every instance scanned at the ray's time) on every ISA; packets
// whose lanes have different times match single rays; bad motions are refused; and
// instance_at itself.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "accel/two_level.h"
#include "accel/two_level_motion.h"
#include "two_level_motion_test_support.h"

namespace lancer::test {
namespace {

class TwoLevelMotion : public KdIsaTest {
 protected:
  void check_against_definition(int extra);
  void packets_match_single_rays(int extra);
};

// (a) At a time t, a moving instance answers exactly as a static instance holding
// instance_at(geometry, inst, t)'s transforms: same hits, same bits, kd-tree and
// brute-force bottoms. Times include 0, 1, a key (0.5 of three keys) and random ones.
TEST_P(TwoLevelMotion, MovingInstanceIsItsStaticSelfAtEachTime) {
  const InstancedScene s = random_moving_scene(isa_seed() + 101);
  const Bounds3 box = sampled_scene_box(s);
  TestRng rng(isa_seed() + 102);
  std::vector<float> times = {0.0f, 1.0f, 0.5f};
  while (times.size() < 12) times.push_back(rng.uniform());
  for (const char* bottom : {"kdtree", "brute"}) {
    const TwoLevelAccelerator moving(s.tris, s.geometry, bottom, {}, isa());
    for (std::size_t ti = 0; ti < times.size(); ++ti) {
      InstancedScene still = s;
      for (Instance& inst : still.geometry.instances) {
        inst = instance_at(s.geometry, inst, times[ti]);
        inst.motion = kNoHit;
      }
      still.geometry.motions.clear();
      const TwoLevelAccelerator fixed(still.tris, still.geometry, bottom, {}, isa());
      for (std::size_t i = 0; i < 150; ++i) {
        Ray r = moving_scene_ray(s, box, isa_seed() + 103 + ti, i);
        r.time = times[ti];
        const Hit a = moving.intersect(r), b = fixed.intersect(r);
        ASSERT_TRUE(same_bits(a, b)) << bottom << ", " << describe_moving(r) << "\n moving: " << describe_moving_hit(a)
                                     << "\n static: " << describe_moving_hit(b);
        ASSERT_EQ(moving.occluded(r), fixed.occluded(r)) << bottom << ", " << describe_moving(r);
      }
    }
  }
}

// (b) Against the definition, rays at random times: far translations, turns of up to 179
// degrees per key (cubes off their origin sweep half circles, whose bulge between the box's
// time samples the margin must hold), changing and mirrored stretches, still instances.
// Both ways through the top level: its tree (15 instances besides the direct one) and one
// by one (7).
TEST_P(TwoLevelMotion, MatchesTheDefinitionAtRandomTimes) {
  for (const int extra : {8, 0}) check_against_definition(extra);
}

void TwoLevelMotion::check_against_definition(int extra) {
  SCOPED_TRACE(extra == 0 ? "few instances" : "the top level's tree");
  const InstancedScene s = random_moving_scene(isa_seed() + 201 + std::uint64_t(extra), extra);
  const Bounds3 box = sampled_scene_box(s);
  const TwoLevelAccelerator kd(s.tris, s.geometry, "kdtree", {}, isa());
  const TwoLevelAccelerator brute(s.tris, s.geometry, "brute");
  ASSERT_EQ(kd.meets_few_instances(), extra == 0);
  const MotionScan scan(s);
  std::size_t hits = 0, ties = 0;
  std::vector<bool> seen(s.geometry.instances.size(), false);
  constexpr std::size_t kRays = 4000;
  for (std::size_t i = 0; i < kRays; ++i) {
    const Ray r = moving_scene_ray(s, box, isa_seed() + 202, i);
    const Hit expected = scan.intersect(r);
    const Hit a = kd.intersect(r), b = brute.intersect(r);
    ASSERT_TRUE(same_bits(a, expected)) << describe_moving(r) << "\n kd bottoms: " << describe_moving_hit(a)
                                        << "\n definition: " << describe_moving_hit(expected);
    ASSERT_TRUE(same_bits(b, expected)) << describe_moving(r) << "\n brute bottoms: " << describe_moving_hit(b)
                                        << "\n definition: " << describe_moving_hit(expected);
    const bool blocked = scan.occluded(r);
    ASSERT_EQ(kd.occluded(r), blocked) << describe_moving(r);
    ASSERT_EQ(brute.occluded(r), blocked) << describe_moving(r);
    hits += expected.valid() ? 1 : 0;
    ties += expected.instance == 5 ? 1 : 0;
    if (expected.valid()) seen[expected.instance] = true;
  }
  EXPECT_GT(hits, kRays / 3);
  EXPECT_GT(ties, 0u) << "the still twins 5 and 6 should be hit";
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (i == 6) continue;  // loses every tie to 5
    EXPECT_TRUE(seen[i]) << "instance " << i << " is never hit";
  }
}

// The sweeping cubes alone, each cube corner at the time it reaches farthest along an
// axis (to 1/4096 of the shutter), the point farthest out of the chords between the box's
// time samples: rays level with the corner then along the other axes, aimed just inside
// it. Without the margin for the arc's bulge many of them would pass outside the instance's
// box (and the top level would never enter it).
TEST_P(TwoLevelMotion, SweepingCornersStayInsideTheBoxes) {
  const InstancedScene all = random_moving_scene(isa_seed() + 301, 0);
  const Bounds3 object{{4.9f, -0.05f, -0.05f}, {5.0f, 0.05f, 0.05f}};  // the cube of random_moving_scene
  TestRng rng(isa_seed() + 302);
  std::size_t rays = 0, hits = 0;
  for (std::size_t j = all.geometry.instances.size() - 2; j < all.geometry.instances.size(); ++j) {
    InstancedScene s = all;  // the cube alone: its box is the root's
    s.geometry.instances = {all.geometry.instances[j]};
    const Instance& inst = s.geometry.instances[0];
    const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree", {}, isa());
    const MotionScan scan(s);
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1 ? object.hi : object.lo).x, (c & 2 ? object.hi : object.lo).y,
                             (c & 4 ? object.hi : object.lo).z);
      for (int a = 0; a < 3; ++a) {
        for (float sign : {-1.0f, 1.0f}) {
          float best_time = 0.0f, best = -kInfinity;
          for (int k = 0; k <= 4096; ++k) {
            const float t = float(k) / 4096.0f;
            const float x = sign * instance_at(s.geometry, inst, t).to_world.point(corner)[a];
            if (x > best) best = x, best_time = t;
          }
          for (int jitter = 0; jitter < 4; ++jitter) {
            Ray r;
            r.time = std::fmin(1.0f, std::fmax(0.0f, best_time + rng.uniform(-1e-4f, 1e-4f)));
            const Instance at = instance_at(s.geometry, inst, r.time);
            const glm::vec3 w = at.to_world.point(corner), centre = at.to_world.point(object.center());
            const glm::vec3 target = w + 1e-4f * (centre - w);
            const int b = (a + 1 + jitter % 2) % 3;  // along another axis, level with the corner
            r.org = target;
            r.org[b] += jitter < 2 ? 2.0f : -2.0f;
            r.dir = glm::vec3(0.0f);
            r.dir[b] = jitter < 2 ? -1.0f : 1.0f;
            const Hit expected = scan.intersect(r);
            ASSERT_TRUE(same_bits(accel.intersect(r), expected))
                << describe_moving(r) << "\n two-level: " << describe_moving_hit(accel.intersect(r))
                << "\n definition: " << describe_moving_hit(expected);
            ASSERT_EQ(accel.occluded(r), scan.occluded(r)) << describe_moving(r);
            ++rays;
            hits += expected.valid() ? 1 : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(hits, rays * 9 / 10);
}

// Each piece of a moving instance's shutter (ShutterBounds::pieces) holds the mesh at
// every time piece_of assigns to it: the mesh box's corners through instance_at at each
// piece boundary and one float step either side of it, and at random times, for every
// moving instance of the random scene (far travel, half turns, mirrors, squashing). And the
// pieces cull: for the instance that travels far, each is a small part of the whole box.
TEST(ShutterPieces, HoldTheMeshAtEveryTimeOfTheirPiece) {
  const InstancedScene s = random_moving_scene(41);
  TestRng rng(42);
  std::size_t moving = 0;
  for (std::size_t i = 0; i < s.geometry.instances.size(); ++i) {
    const Instance& inst = s.geometry.instances[i];
    if (inst.motion == kNoHit) continue;
    ++moving;
    const MeshRange& r = s.geometry.meshes[inst.mesh];
    Bounds3 object;
    for (std::uint32_t k = 0; k < r.count; ++k) object.extend(s.tris.triangle_bounds(r.first + k));
    const two_level::ShutterBounds b = two_level::shutter_bounds(s.geometry, inst, object);
    const std::size_t pieces = b.pieces.size();
    const std::size_t intervals = s.geometry.motions[inst.motion].keys.size() - 1;
    ASSERT_EQ(pieces % intervals, 0u) << "instance " << i;
    ASSERT_LE(pieces, std::max(two_level::kMaxShutterPieces, intervals)) << "instance " << i;
    std::vector<float> times;
    for (std::size_t p = 0; p <= pieces; ++p) {
      const float t = float(double(p) / double(pieces));
      for (float u : {std::nextafter(t, -1.0f), t, std::nextafter(t, 2.0f)})
        if (u >= 0.0f && u <= 1.0f) times.push_back(u);
    }
    while (times.size() < 3 * pieces + 400) times.push_back(rng.uniform());
    for (float t : times) {
      const std::size_t p = two_level::piece_of(pieces, t);
      const Bounds3& box = b.pieces[p];
      const Instance at = instance_at(s.geometry, inst, t);
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1 ? object.hi : object.lo).x, (c & 2 ? object.hi : object.lo).y,
                               (c & 4 ? object.hi : object.lo).z);
        const glm::vec3 w = at.to_world.point(corner);
        for (int a = 0; a < 3; ++a)
          ASSERT_TRUE(w[a] >= box.lo[a] && w[a] <= box.hi[a])
              << "instance " << i << " at " << t << " (piece " << p << " of " << pieces << "), corner " << c << " axis "
              << a << ": " << w[a] << " outside [" << box.lo[a] << ", " << box.hi[a] << "]";
      }
    }
    if (i == 1) {  // travels about 70 units over two keys
      double piece_extent = 0.0;
      for (const Bounds3& piece : b.pieces) piece_extent += glm::length(piece.extent());
      EXPECT_LT(piece_extent / double(pieces), 0.25 * glm::length(b.box.extent()));
    }
  }
  EXPECT_GE(moving, 6u);
}

// (c) Packets match single rays bit for bit when lanes have different times: every lane
// its own time, runs of lanes sharing one (the transform reused), one time for all, and
// partial packets; camera tiles, shadow packets and incoherent rays.
TEST_P(TwoLevelMotion, PacketsWithMixedTimesMatchSingleRays) {
  for (const int extra : {12, 0}) packets_match_single_rays(extra);
}

void TwoLevelMotion::packets_match_single_rays(int extra) {
  SCOPED_TRACE(extra == 0 ? "few instances" : "the top level's tree");
  const InstancedScene s = random_moving_scene(isa_seed() + 401 + std::uint64_t(extra), extra);
  const Bounds3 box = sampled_scene_box(s);
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree", {}, isa());
  ASSERT_EQ(accel.meets_few_instances(), extra == 0);
  TestRng rng(isa_seed() + 402);
  std::size_t rays = 0, hits = 0, occluded = 0;
  auto check = [&](const std::vector<Ray>& packet) {
    const int n = static_cast<int>(packet.size());
    std::vector<Hit> got(packet.size());
    const std::unique_ptr<bool[]> blocked(new bool[packet.size() + 1]);
    accel.intersect_packet(packet.data(), got.data(), n);
    accel.occluded_packet(packet.data(), blocked.get(), n);
    for (int i = 0; i < n; ++i) {
      const Hit single = accel.intersect(packet[i]);
      ASSERT_TRUE(same_bits(got[i], single)) << "lane " << i << " of " << n << ", " << describe_moving(packet[i])
                                             << "\n packet: " << describe_moving_hit(got[i])
                                             << "\n single: " << describe_moving_hit(single);
      ASSERT_EQ(blocked[i], accel.occluded(packet[i])) << "lane " << i << ", " << describe_moving(packet[i]);
      hits += single.valid() ? 1 : 0;
      occluded += blocked[i] ? 1 : 0;
    }
    rays += packet.size();
  };
  auto set_times = [&](std::vector<Ray>& packet, int mode) {
    float shared = rng.uniform();
    for (std::size_t i = 0; i < packet.size(); ++i) {
      if (mode == 0 || (mode == 1 && i % 4 == 0)) shared = rng.uniform();  // own times / runs of 4
      packet[i].time = shared;
    }
  };
  // Looking at the crowd around the origin (the far-travelling instance stretches `box`).
  const Pinhole cam = Pinhole::looking_at({3.0f, 4.0f, 11.0f}, {0, 0, 0}, {0, 1, 0}, 55.0f, 32);
  const glm::vec3 light = box.hi + 0.5f * box.extent();
  int mode = 0;
  for (std::vector<Ray> tile : camera_tiles(cam, 32, 32)) {
    set_times(tile, mode++ % 3);
    check(tile);
    if (HasFatalFailure()) return;
    std::vector<Ray> shadows;
    for (const Ray& r : tile) {
      const Hit h = accel.intersect(r);
      if (!h.valid()) continue;
      Ray sh;
      sh.org = light;
      sh.dir = r.org + h.t * r.dir - light;
      sh.tfar = 0.999f;
      sh.time = r.time;
      shadows.push_back(sh);
    }
    if (!shadows.empty()) check(shadows);
    if (HasFatalFailure()) return;
  }
  for (int count = 1; count <= 64; count += 3) {
    std::vector<Ray> packet;
    for (int i = 0; i < count; ++i) packet.push_back(moving_scene_ray(s, box, isa_seed() + 403 + count, std::size_t(i)));
    set_times(packet, count % 3);
    check(packet);
    if (HasFatalFailure()) return;
  }
  // The few-instance crowd is sparser (7 instances, not 19): fewer of its rays hit.
  EXPECT_GT(hits, rays / (extra == 0 ? 6 : 4));
  EXPECT_GT(occluded, 0u);
}

// (d) Bad motions are refused with std::invalid_argument.
TEST(TwoLevelMotionInput, InvalidMotionsThrow) {
  const InstancedScene good = random_moving_scene(7, 2);
  EXPECT_NO_THROW(TwoLevelAccelerator(good.tris, good.geometry, "brute"));
  auto expect_throw = [&](const InstancedScene& s, const char* what) {
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "kdtree"), std::invalid_argument) << what;
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "brute"), std::invalid_argument) << what;
  };
  const std::uint32_t m = good.geometry.instances[3].motion;
  {
    InstancedScene s = good;
    s.geometry.motions[m].keys.resize(1);
    expect_throw(s, "one key");
    s.geometry.motions[m].keys.clear();
    expect_throw(s, "no key");
  }
  {
    InstancedScene s = good;  // proper at key 0, mirroring at key 1
    s.geometry.motions[m].keys[1].stretch = glm::mat3(-1.0f);
    expect_throw(s, "determinant changing sign");
  }
  {
    InstancedScene s = good;  // det +1 at both keys, but the blend of diag(1,1,1) and diag(-1,-1,1) is singular
    s.geometry.motions[m].keys[0].stretch = glm::mat3(1.0f);
    s.geometry.motions[m].keys[1].stretch = glm::mat3(-1.0f, 0, 0, 0, -1.0f, 0, 0, 0, 1.0f);
    expect_throw(s, "an indefinite stretch");
    s.geometry.motions[m].keys[1].stretch = glm::mat3(1.0f, 0, 0, 0, 1.0f, 0, 0, 0, 1e-14f);
    expect_throw(s, "a stretch nearly singular");
  }
  {
    InstancedScene s = good;
    s.geometry.motions[m].keys[1].translation.y = std::numeric_limits<float>::quiet_NaN();
    expect_throw(s, "NaN translation");
    s = good;
    s.geometry.motions[m].keys[0].rotation.x = std::numeric_limits<float>::quiet_NaN();
    expect_throw(s, "NaN rotation");
    s = good;
    s.geometry.motions[m].keys[0].stretch[2][1] = kInfinity;
    expect_throw(s, "infinite stretch");
  }
  {
    InstancedScene s = good;
    s.geometry.motions[m].keys[1].rotation = glm::quat(1.2f, 0.0f, 0.0f, 0.0f);
    expect_throw(s, "rotation not a unit quaternion");
  }
  {
    InstancedScene s = good;
    s.geometry.motions[m].keys[1].stretch = glm::mat3(1e20f);
    expect_throw(s, "scale beyond 2^40");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[3].motion = static_cast<std::uint32_t>(s.geometry.motions.size());
    expect_throw(s, "motion index out of range");
  }
}

Instance moving_instance(InstancedGeometry& g, std::vector<MotionKey> keys) {
  Instance inst = instance_from_key(0, keys[0]);
  inst.motion = static_cast<std::uint32_t>(g.motions.size());
  g.motions.push_back(InstanceMotion{std::move(keys)});
  return inst;
}

bool same_transforms(const Instance& a, const Instance& b) {
  return std::memcmp(&a.to_world, &b.to_world, sizeof(Affine)) == 0 &&
         std::memcmp(&a.to_object, &b.to_object, sizeof(Affine)) == 0;
}

// (e) instance_at: the keys exactly at 0 and 1 (and an inner key at its time), times
// clamped, NaN as 0, slerp and lerp in between; a still instance is itself.
TEST(InstanceAt, KeysClampingAndInterpolation) {
  InstancedGeometry g;
  TestRng rng(9);
  const std::vector<MotionKey> keys = {
      make_key({1, 2, 3}, about(rng.direction(), 33), random_stretch(rng, {1.1, 0.7, 1.3})),
      make_key({-4, 0, 5}, about(rng.direction(), 120), random_stretch(rng, {0.5, 1.0, 1.5})),
      make_key({2, -6, 1}, about(rng.direction(), 70), random_stretch(rng, {0.9, 0.9, 0.9}))};
  const Instance inst = moving_instance(g, keys);
  EXPECT_TRUE(same_transforms(instance_at(g, inst, 0.0f), instance_from_key(0, keys[0])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, 0.5f), instance_from_key(0, keys[1])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, 1.0f), instance_from_key(0, keys[2])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, -3.0f), instance_from_key(0, keys[0])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, -kInfinity), instance_from_key(0, keys[0])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, 7.0f), instance_from_key(0, keys[2])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, kInfinity), instance_from_key(0, keys[2])));
  EXPECT_TRUE(same_transforms(instance_at(g, inst, std::numeric_limits<float>::quiet_NaN()),
                              instance_from_key(0, keys[0])));
  EXPECT_EQ(instance_at(g, inst, 0.3f).motion, inst.motion);
  for (float t : {0.1f, 0.25f, 0.77f}) {  // deterministic
    EXPECT_TRUE(same_transforms(instance_at(g, inst, t), instance_at(g, inst, t)));
  }

  // 90 degrees about z over the shutter, translating from a to b: 45 degrees and the
  // midpoint at time 0.5.
  InstancedGeometry g2;
  const Instance turn = moving_instance(g2, {make_key({0, 0, 0}, about({0, 0, 1}, 0)),
                                             make_key({4, -2, 6}, about({0, 0, 1}, 90))});
  const Instance mid = instance_at(g2, turn, 0.5f);
  const float h = std::sqrt(0.5f);
  const glm::mat3 expected(h, h, 0, -h, h, 0, 0, 0, 1);  // columns: x -> (h, h, 0), y -> (-h, h, 0)
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(mid.to_world.linear[c][r], expected[c][r], 1e-6f) << c << "," << r;
  EXPECT_NEAR(mid.to_world.offset.x, 2.0f, 1e-6f);
  EXPECT_NEAR(mid.to_world.offset.y, -1.0f, 1e-6f);
  EXPECT_NEAR(mid.to_world.offset.z, 3.0f, 1e-6f);
  const Instance quarter = instance_at(g2, turn, 0.25f);
  EXPECT_NEAR(quarter.to_world.linear[0][1], std::sin(glm::radians(22.5f)), 1e-6f);
  EXPECT_NEAR(quarter.to_world.offset.x, 1.0f, 1e-6f);
  const glm::vec3 back = mid.to_object.point(mid.to_world.point({1, 2, 3}));
  EXPECT_NEAR(back.x, 1.0f, 1e-5f);
  EXPECT_NEAR(back.y, 2.0f, 1e-5f);
  EXPECT_NEAR(back.z, 3.0f, 1e-5f);

  Instance still = instance_from_key(0, keys[1]);
  EXPECT_TRUE(same_transforms(instance_at(g, still, 0.6f), still));
  EXPECT_EQ(instance_at(g, still, 0.6f).motion, kNoHit);
}

// PreparedMotions (the accelerator's interpolation, with each span's constants computed
// once) gives instance_at's bits (the renderer's), which the ray offsets rely on: changing
// stretches, rigid spans (the stretch's inverse kept), nearly equal rotations (the linear
// blend) and half turns, at keys, between them and clamped.
TEST(InstanceAt, PreparedMotionsGiveInstanceAtsBits) {
  InstancedGeometry g;
  TestRng rng(21);
  std::vector<Instance> moving;
  moving.push_back(moving_instance(
      g, {make_key({1, 2, 3}, about(rng.direction(), 33), random_stretch(rng, {1.1, 0.7, 1.3})),
          make_key({-4, 0, 5}, about(rng.direction(), 120), random_stretch(rng, {0.5, 1.0, 1.5})),
          make_key({2, -6, 1}, about(rng.direction(), 70), random_stretch(rng, {0.9, 0.9, 0.9}))}));
  const glm::mat3 rigid = random_stretch(rng, {1.2, 0.8, 1.0});
  moving.push_back(moving_instance(g, {make_key({0, 0, 0}, about({0, 0, 1}, 0), rigid),
                                       make_key({3, 1, 0}, about({0, 1, 1}, 179), rigid)}));
  moving.push_back(moving_instance(g, {make_key({0, 0, 0}, about({1, 0, 0}, 10)),
                                       make_key({0, 0, 1}, about({1, 0, 0}, 10.5f))}));  // lerp
  const PreparedMotions prepared(g);
  std::vector<float> times = {0.0f, 0.5f, 1.0f, -1.0f, 2.0f, std::numeric_limits<float>::quiet_NaN()};
  while (times.size() < 200) times.push_back(rng.uniform());
  for (std::size_t m = 0; m < moving.size(); ++m)
    for (float t : times) {
      // Each computed afresh: the per-thread memo would otherwise answer the second call.
      forget_moved_instances();
      const Instance a = prepared.at(moving[m], t);
      forget_moved_instances();
      const Instance b = instance_at(g, moving[m], t);
      ASSERT_TRUE(same_transforms(a, b)) << "motion " << m << " at " << t;
      ASSERT_EQ(a.motion, b.motion);
      // to_object inverts to_world (the rigid span's stretch^-1 rotation^T included).
      const glm::vec3 p(0.3f, -1.7f, 2.2f), back = a.to_object.point(a.to_world.point(p));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], p[c], 1e-5f) << "motion " << m << " at " << t;
    }
}

// The per-thread memo of interpolated transforms: a remembered answer has the bits of a
// fresh computation (each asked twice in a row, the second from the memo); motions that
// differ only in one key get their own at the same time, called in turn from one thread;
// and an instance of another mesh or motion index with the same keys gets its own mesh and
// motion index back.
TEST(InstanceAt, MemoAnswersAsAFreshComputation) {
  TestRng rng(23);
  InstancedGeometry g, h;
  const std::vector<MotionKey> keys = {make_key({1, 2, 3}, about(rng.direction(), 33)),
                                       make_key({-4, 0, 5}, about(rng.direction(), 120)),
                                       make_key({2, -6, 1}, about(rng.direction(), 70))};
  std::vector<MotionKey> other = keys;
  other[1].translation.y += 0.5f;  // the inner key: every time but 0 and 1 differs
  const Instance a = moving_instance(g, keys);
  const Instance b = moving_instance(h, other);
  // Motion 1 of g has a's keys; drawn with mesh 1.
  Instance twin = moving_instance(g, keys);
  twin.mesh = 1;
  ASSERT_EQ(twin.motion, 1u);
  std::vector<float> times = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  while (times.size() < 60) times.push_back(rng.uniform());
  std::size_t differ = 0;
  for (float t : times) {
    forget_moved_instances();
    const Instance fresh_a = instance_at(g, a, t);
    forget_moved_instances();
    const Instance fresh_b = instance_at(h, b, t);
    forget_moved_instances();
    for (int round = 0; round < 2; ++round) {
      ASSERT_TRUE(same_transforms(instance_at(g, a, t), fresh_a)) << "at " << t;
      ASSERT_TRUE(same_transforms(instance_at(g, a, t), fresh_a)) << "at " << t << ", from the memo";
      ASSERT_TRUE(same_transforms(instance_at(h, b, t), fresh_b)) << "at " << t;
      ASSERT_TRUE(same_transforms(instance_at(h, b, t), fresh_b)) << "at " << t << ", from the memo";
      const Instance t_twin = instance_at(g, twin, t);
      ASSERT_EQ(t_twin.mesh, 1u);
      ASSERT_EQ(t_twin.motion, 1u);
      ASSERT_TRUE(same_transforms(t_twin, fresh_a)) << "the same keys give the same transforms";
      const Instance t_a = instance_at(g, a, t);
      ASSERT_EQ(t_a.mesh, a.mesh);
      ASSERT_EQ(t_a.motion, a.motion);
    }
    differ += same_transforms(fresh_a, fresh_b) ? 0 : 1;
  }
  EXPECT_GT(differ, 20u) << "the two motions should differ over the inner key's spans";
}

// Two accelerators over the same instances moving differently, queried in turn at the same
// times from one thread: each answers by its own motions (the per-thread memo of moved
// transforms is keyed by the keys themselves).
TEST_P(TwoLevelMotion, AcceleratorsKeepTheirOwnMovedTransforms) {
  const InstancedScene a = random_moving_scene(isa_seed() + 701);
  InstancedScene b = a;
  for (InstanceMotion& m : b.geometry.motions)
    for (MotionKey& k : m.keys) k.translation += glm::vec3(0.5f, -0.25f, 0.125f);
  const TwoLevelAccelerator first(a.tris, a.geometry, "kdtree", {}, isa());
  const TwoLevelAccelerator second(b.tris, b.geometry, "kdtree", {}, isa());
  const MotionScan scan_a(a), scan_b(b);
  const Bounds3 box = sampled_scene_box(a);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < 1500; ++i) {
    Ray r = moving_scene_ray(a, box, isa_seed() + 702, i);
    r.time = float(i % 5) / 4.0f + (i % 5 == 4 ? -0.125f : 0.0625f);  // few times, shared by both
    const Hit ea = scan_a.intersect(r), eb = scan_b.intersect(r);
    ASSERT_TRUE(same_bits(first.intersect(r), ea)) << describe_moving(r);
    ASSERT_TRUE(same_bits(second.intersect(r), eb)) << describe_moving(r);
    ASSERT_TRUE(same_bits(first.intersect(r), ea)) << describe_moving(r);
    differ += same_bits(ea, eb) ? 0 : 1;
  }
  EXPECT_GT(differ, 100u) << "the two motions should give different answers";
}

INSTANTIATE_TEST_SUITE_P(AllIsas, TwoLevelMotion, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
