// The two-level accelerator (two_level.h) on random instanced scenes: bit for bit the
// definition (every instance scanned) with kd-tree and brute-force bottoms on every ISA,
// the flattened world-space scene within stated tolerances, and its input checks.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "accel/kd_tree.h"
#include "accel/two_level.h"
#include "two_level_test_support.h"

namespace lancer::test {
namespace {

std::string describe_hit(const Hit& h) {
  std::ostringstream s;
  s.precision(9);
  s << "instance " << h.instance << " prim " << h.prim << " t " << h.t << " u " << h.u << " v " << h.v;
  return s.str();
}

class TwoLevel : public KdIsaTest {
 protected:
  void check_against_definition(int extra);
};

// (a) kd-tree bottoms, brute-force bottoms and the definition agree bit for bit, for
// closest hit and occlusion, on every ray kind; each ISA gets its own scene and rays.
// Both ways through the top level: its tree (15 instances) and one by one (6 besides the
// direct one).
TEST_P(TwoLevel, KdBottomsMatchBruteBottomsAndTheDefinition) {
  for (const int extra : {8, 0}) check_against_definition(extra);
}

void TwoLevel::check_against_definition(int extra) {
  SCOPED_TRACE(extra == 0 ? "few instances" : "the top level's tree");
  const InstancedScene s = random_instanced_scene(isa_seed() + 11 + std::uint64_t(extra), extra);
  const TwoLevelAccelerator kd(s.tris, s.geometry, "kdtree", {}, isa());
  const TwoLevelAccelerator brute(s.tris, s.geometry, "brute");
  ASSERT_EQ(kd.meets_few_instances(), extra == 0);
  ASSERT_EQ(kd.direct_count(), 1u);
  const InstanceScan scan(s);
  const FlatScene flat = flatten(s);
  const Bounds3 box = flat.tris.bounds();
  std::size_t hits = 0, ties = 0, occluded = 0;
  constexpr std::size_t kRays = 4000;
  for (std::size_t i = 0; i < kRays; ++i) {
    const Ray r = instanced_scene_ray(s, flat, box, isa_seed() + 3, i);
    const Hit expected = scan.intersect(r);
    const Hit a = kd.intersect(r), b = brute.intersect(r);
    ASSERT_TRUE(same_bits(a, expected)) << describe(r) << "\n kd bottoms: " << describe_hit(a)
                                        << "\n definition: " << describe_hit(expected);
    ASSERT_TRUE(same_bits(b, expected)) << describe(r) << "\n brute bottoms: " << describe_hit(b)
                                        << "\n definition: " << describe_hit(expected);
    const bool blocked = scan.occluded(r);
    ASSERT_EQ(kd.occluded(r), blocked) << describe(r);
    ASSERT_EQ(brute.occluded(r), blocked) << describe(r);
    ASSERT_EQ(blocked, expected.valid()) << describe(r);
    hits += expected.valid() ? 1 : 0;
    ties += expected.instance == 5 ? 1 : 0;  // instance 6 coincides with 5 and must lose every tie
    occluded += blocked ? 1 : 0;
    ASSERT_NE(expected.instance, 6u) << describe(r);
  }
  EXPECT_GT(hits, kRays / 4) << "most ray kinds should mostly hit";
  EXPECT_GT(ties, 0u) << "some rays should hit the coincident instances";
}

// (b) Against the scene flattened into world space in double (a different rounding of the
// same geometry). The two agree up to the rounding of the transforms: a few float ulps of
// the coordinates, times the transforms' condition (< 10 here), i.e. about 1e-6 of the
// scene's size. So, for each ray:
//  - t agrees within 1e-4 relative (plus 1e-4 of the scene size over |dir|), far above
//    that rounding, far below any error a wrong transform or a skipped instance makes;
//    the (instance, triangle) may then differ only in a near tie (coincident instances,
//    shared edges, crossing triangles);
//  - otherwise (a hit against a miss, or against a farther hit) the nearer hit must lie
//    within 1e-3 of its triangle's edge (barycentric): rounding can move a ray across
//    that silhouette, and the other answer then sees what lies behind.
// Such excused rays must stay rare: under 1% of all rays, and under half of those aimed
// exactly at a vertex (one kind in eight, all on edges).
TEST(TwoLevelWorld, MatchesTheFlattenedSceneWithinTolerance) {
  const InstancedScene s = random_instanced_scene(77, 24);
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree");
  const FlatScene flat = flatten(s);
  const BruteForce oracle(flat.tris);
  const Bounds3 box = flat.tris.bounds();
  const glm::vec3 e = box.extent();
  const double size = std::fmax(e.x, std::fmax(e.y, e.z));
  constexpr std::size_t kRays = 6000;
  std::size_t hits = 0, excused = 0, excused_at_vertices = 0, instances_hit = 0;
  std::vector<bool> seen(s.geometry.instances.size(), false);
  auto near_edge = [](const Hit& h) { return std::fmin(std::fmin(h.u, h.v), 1.0f - h.u - h.v) < 1e-3f; };
  for (std::size_t i = 0; i < kRays; ++i) {
    const Ray r = instanced_scene_ray(s, flat, box, 99, i);
    const Hit a = accel.intersect(r);
    Hit b = oracle.intersect(r);
    if (b.valid()) {
      const std::uint32_t k = b.prim;
      b.instance = flat.instance[k];
      b.prim = flat.prim[k];
    }
    if (a.valid() != b.valid()) {
      const Hit& h = a.valid() ? a : b;
      ASSERT_TRUE(near_edge(h)) << describe(r) << ": only one hits, away from an edge\n two-level: " << describe_hit(a)
                                << "\n flattened: " << describe_hit(b);
      ++(i % 8 == 2 ? excused_at_vertices : excused);
      continue;
    }
    if (!a.valid()) continue;
    ++hits;
    if (!seen[a.instance]) seen[a.instance] = true, ++instances_hit;
    const double dir_len = std::sqrt(double(r.dir.x) * r.dir.x + double(r.dir.y) * r.dir.y + double(r.dir.z) * r.dir.z);
    const double tol = 1e-4 * std::fabs(double(b.t)) + 1e-4 * size / dir_len;
    if (std::fabs(double(a.t) - double(b.t)) > tol) {
      // Only the nearer hit's silhouette can explain it: the other answer missed it.
      ASSERT_TRUE(near_edge(a.t < b.t ? a : b))
          << describe(r) << "\n two-level: " << describe_hit(a) << "\n flattened: " << describe_hit(b);
      ++(i % 8 == 2 ? excused_at_vertices : excused);
    } else if (a.instance != b.instance || a.prim != b.prim) {
      ++(i % 8 == 2 ? excused_at_vertices : excused);  // a near tie
    }
  }
  EXPECT_LT(excused, kRays / 100) << "too many rays excused by the tolerances";
  EXPECT_LT(excused_at_vertices, kRays / 8 / 2) << "too many rays aimed at vertices excused";
  EXPECT_GT(hits, kRays / 4);
  EXPECT_EQ(instances_hit, s.geometry.instances.size() - 1) << "every instance but the losing twin should be hit";
}

// 64 rays through the quad at x = 0 (|y|, |z| < 1 there): 32 going -x from x = 10, then
// 32 going +x from x = -10.
std::vector<Ray> rays_through_quad(std::uint64_t seed) {
  TestRng rng(seed);
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) {
    Ray r;
    const float sign = i < 32 ? -1.0f : 1.0f;
    r.org = {-10.0f * sign, rng.uniform(-0.4f, 0.4f), rng.uniform(-0.4f, 0.4f)};
    r.dir = {sign, 0.05f * rng.uniform(-1.0f, 1.0f), 0.05f * rng.uniform(-1.0f, 1.0f)};
    rays.push_back(r);
  }
  return rays;
}

// The tie rule whatever the visit order: two instances share a quad in the plane x = 0
// (the same float vertices and the same transform, a shift by 0.5 along x: bit-identical
// t; not the identity, which would make them direct and keep them out of the top level),
// instance 0 reaching to x = -4 and instance 1 to x = +4, so the top level gives instance 1
// a leaf of its own beyond the quad (the boxes' margins overlap around the quad). Rays
// going -x visit instance 1 first, rays going +x instance 0; instance 0 must win both ways,
// in single rays and in packets.
TEST_P(TwoLevel, TiesGoToTheLowerInstanceInAnyVisitOrder) {
  InstancedScene s;
  auto quad_and = [&](float x) {
    const auto first = static_cast<std::uint32_t>(s.tris.size());
    s.tris.push_back({0, -1, -1}, {0, 1, -1}, {0, 1, 1});
    s.tris.push_back({0, -1, -1}, {0, 1, 1}, {0, -1, 1});
    s.tris.push_back({x, 5, -1}, {x, 6, -1}, {x, 5, 1});  // off the rays, widening the box
    return MeshRange{first, 3};
  };
  s.geometry.meshes = {quad_and(-4.0f), quad_and(4.0f)};
  s.geometry.instances = {make_instance(0, glm::dmat3(1.0), {0.5, 0, 0}),
                          make_instance(1, glm::dmat3(1.0), {0.5, 0, 0})};
  for (const char* bottom : {"kdtree", "brute"}) {
    const TwoLevelAccelerator accel(s.tris, s.geometry, bottom, {}, isa());
    ASSERT_EQ(accel.direct_count(), 0u);
    bool apart = false;  // some leaf lists instance 1 alone
    for (const KdNode& n : accel.top_level().nodes())
      apart = apart || (n.is_leaf() && n.count() == 1 && accel.top_level().items()[n.first_slot()] == 1);
    ASSERT_TRUE(apart) << "the top level should give instance 1 a leaf of its own";
    const std::vector<Ray> rays = rays_through_quad(isa_seed() + 5);
    std::vector<Hit> packet(rays.size());
    accel.intersect_packet(rays.data(), packet.data(), 32);  // the -x rays, one coherent packet
    accel.intersect_packet(rays.data() + 32, packet.data() + 32, 32);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Hit h = accel.intersect(rays[i]);
      ASSERT_TRUE(h.valid()) << describe(rays[i]);
      EXPECT_EQ(h.instance, 0u) << bottom << ", " << describe(rays[i]);
      EXPECT_LT(h.prim, 2u) << "the shared quad";
      EXPECT_TRUE(same_bits(packet[i], h)) << bottom << " packet lane " << i;
    }
  }
}

// Direct instances (exactly the identity: entered before the top level, outside it) keep
// the tie rule against the top level's: a quad at x = 0 drawn by the identity and, shifted
// by 2 along x from a copy at x = -2, by a top-level instance (shifts by 2 are exact for
// these rays, so both report bit-identical t). The lower instance wins whichever of the
// two is direct, in single rays and packets.
TEST_P(TwoLevel, DirectAndTopLevelInstancesTieByIndex) {
  for (const bool direct_first : {true, false}) {
    InstancedScene s;
    auto quad_at = [&](float x) {
      const auto first = static_cast<std::uint32_t>(s.tris.size());
      s.tris.push_back({x, -1, -1}, {x, 1, -1}, {x, 1, 1});
      s.tris.push_back({x, -1, -1}, {x, 1, 1}, {x, -1, 1});
      return MeshRange{first, 2};
    };
    s.geometry.meshes = {quad_at(0.0f), quad_at(-2.0f)};
    const Instance direct = make_instance(0, glm::dmat3(1.0), {0, 0, 0});
    const Instance shifted = make_instance(1, glm::dmat3(1.0), {2, 0, 0});
    s.geometry.instances = direct_first ? std::vector<Instance>{direct, shifted} : std::vector<Instance>{shifted, direct};
    for (const char* bottom : {"kdtree", "brute"}) {
      const TwoLevelAccelerator accel(s.tris, s.geometry, bottom, {}, isa());
      ASSERT_EQ(accel.direct_count(), 1u);
      for (const std::uint32_t item : accel.top_level().items())
        ASSERT_EQ(item, direct_first ? 1u : 0u) << "a direct instance in the top level";
      const std::vector<Ray> rays = rays_through_quad(isa_seed() + 6);
      std::vector<Hit> packet(rays.size());
      std::vector<char> blocked(rays.size());
      accel.intersect_packet(rays.data(), packet.data(), 32);
      accel.intersect_packet(rays.data() + 32, packet.data() + 32, 32);
      accel.occluded_packet(rays.data(), reinterpret_cast<bool*>(blocked.data()), 64);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        // A true tie: each drawing alone reports the same t bits.
        InstancedGeometry alone = s.geometry;
        alone.instances = {direct};
        const Hit a = TwoLevelAccelerator(s.tris, alone, bottom, {}, isa()).intersect(rays[i]);
        alone.instances = {shifted};
        const Hit b = TwoLevelAccelerator(s.tris, alone, bottom, {}, isa()).intersect(rays[i]);
        ASSERT_TRUE(a.valid() && b.valid()) << describe(rays[i]);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t)) << "not a tie";
        const Hit h = accel.intersect(rays[i]);
        ASSERT_TRUE(h.valid()) << describe(rays[i]);
        EXPECT_EQ(h.instance, 0u) << bottom << (direct_first ? ", direct first, " : ", direct second, ")
                                  << describe(rays[i]);
        EXPECT_TRUE(same_bits(packet[i], h)) << bottom << " packet lane " << i;
        EXPECT_TRUE(accel.occluded(rays[i]));
        EXPECT_TRUE(blocked[i]) << bottom << " occluded packet lane " << i;
      }
    }
  }
}

// Where the top level's margins matter: axis-aligned instances (scaled by factors no float
// holds exactly, some mirrored, some with axes swapped) and rotated cubes put vertices on
// the faces of their world boxes, and rays lying in the plane of a world vertex (or a few
// ulps beside it) graze those faces, some from far away (where rounding the origin into
// object space moves the ray most). Whether the bottom tree sees such a ray hit depends on the
// rounding of ray_to_object; the top level must visit the instance whenever it does.
TEST_P(TwoLevel, RaysGrazingInstanceBoxesMatchTheDefinition) {
  InstancedScene s = random_instanced_scene(isa_seed() + 31, 0);
  s.geometry.instances.clear();
  Scene cube;  // mesh 3: its corners are the extreme points of its world box in any rotation
  append_box(cube, {{-1, -1, -1}, {1, 1, 1}}, 0);
  s.geometry.meshes.push_back(
      {static_cast<std::uint32_t>(s.tris.size()), static_cast<std::uint32_t>(cube.triangles.size())});
  for (std::size_t i = 0; i < cube.triangles.size(); ++i)
    s.tris.push_back(cube.triangles.vertex(i, 0), cube.triangles.vertex(i, 1), cube.triangles.vertex(i, 2));
  TestRng rng(isa_seed() + 32);
  for (std::uint32_t j = 0; j < 16; ++j) {
    if (j % 4 == 3) {  // a rotated, scaled cube
      const glm::dvec3 scale(rng.uniform(0.3f, 1.7f), rng.uniform(0.3f, 1.7f), rng.uniform(0.3f, 1.7f));
      const glm::dvec3 at(rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f));
      s.geometry.instances.push_back(make_instance(3, random_linear(rng, scale), at));
      continue;
    }
    glm::dmat3 m(0.0);
    const int swap = j % 3 == 2 ? 1 : 0;  // x and y exchanged in every third instance
    for (int a = 0; a < 3; ++a) {
      const double scale = rng.uniform(0.3f, 1.7f) * (rng.below(4) == 0 ? -1.0 : 1.0);
      m[a][a < 2 ? (a + swap) % 2 : 2] = scale;
    }
    const glm::dvec3 at(rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f));
    s.geometry.instances.push_back(make_instance(j % 2, m, at));
  }
  const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree", {}, isa());
  const InstanceScan scan(s);
  std::size_t hits = 0;
  constexpr std::size_t kRays = 6000;
  for (std::size_t i = 0; i < kRays; ++i) {
    const auto j = static_cast<std::uint32_t>(i % s.geometry.instances.size());
    const Instance& inst = s.geometry.instances[j];
    const MeshRange mesh = s.geometry.meshes[inst.mesh];
    const glm::vec3 v = inst.to_world.point(s.tris.vertex(mesh.first + rng.below(mesh.count), int(rng.below(3))));
    const int axis = static_cast<int>(rng.below(3));
    Ray r;
    r.org = v + (i % 2 ? 4.0f : 4000.0f) * rng.direction();  // far origins round ray_to_object coarsely
    r.org[axis] = v[axis];
    for (int k = static_cast<int>(rng.below(5)) - 2; k != 0; k += k > 0 ? -1 : 1)
      r.org[axis] = std::nextafter(r.org[axis], k > 0 ? kInfinity : -kInfinity);
    r.dir = v - r.org;
    r.dir[axis] = 0.0f;
    if (r.dir == glm::vec3(0.0f)) continue;
    const Hit expected = scan.intersect(r);
    ASSERT_TRUE(same_bits(accel.intersect(r), expected))
        << describe(r) << "\n two-level: " << describe_hit(accel.intersect(r)) << "\n definition: "
        << describe_hit(expected);
    ASSERT_EQ(accel.occluded(r), scan.occluded(r)) << describe(r);
    hits += expected.valid() ? 1 : 0;
  }
  EXPECT_GT(hits, kRays / 10);
}

// (e) Invalid input is refused with std::invalid_argument.
TEST(TwoLevelInput, InvalidInputThrows) {
  const InstancedScene good = random_instanced_scene(5, 0);
  auto expect_throw = [&](const InstancedScene& s, const char* what) {
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "kdtree"), std::invalid_argument) << what;
    EXPECT_THROW(TwoLevelAccelerator(s.tris, s.geometry, "brute"), std::invalid_argument) << what;
  };
  {
    InstancedScene s = good;
    s.geometry.meshes[1].count += 1;  // runs past the end of the triangles
    expect_throw(s, "mesh range past the end");
  }
  {
    InstancedScene s = good;
    s.geometry.meshes[0] = {0xFFFFFFFFu, 2};  // first + count overflows 32 bits
    expect_throw(s, "mesh range overflowing");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[2].mesh = 3;
    expect_throw(s, "instance of a missing mesh");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[1].to_world.linear[1][2] = std::numeric_limits<float>::quiet_NaN();
    expect_throw(s, "NaN in to_world");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[3].to_object.offset.y = kInfinity;
    expect_throw(s, "infinite to_object");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[0].to_world.linear = glm::mat3(0.0f);
    expect_throw(s, "singular to_world");
  }
  {
    InstancedScene s = good;
    s.geometry.instances[0] = make_instance(0, glm::dmat3(1e20), {0, 0, 0});
    expect_throw(s, "scale beyond 2^40");
  }
  EXPECT_THROW(TwoLevelAccelerator(good.tris, good.geometry, "bvh"), std::invalid_argument);
  EXPECT_THROW(make_accelerator("bvh", good.tris, good.geometry), std::invalid_argument);
  const TwoLevelAccelerator accel(good.tris, good.geometry, "kdtree");
  Ray r;
  Hit h;
  bool b = false;
  EXPECT_THROW(accel.intersect_packet(&r, &h, -1), std::invalid_argument);
  EXPECT_THROW(accel.occluded_packet(&r, &b, -1), std::invalid_argument);
  EXPECT_NO_THROW(accel.intersect_packet(&r, &h, 0));
}

// The factory: empty geometry gives today's one-level accelerator, otherwise a two-level
// one over the named bottom; meshes no instance draws get no tree.
TEST(TwoLevelFactory, PicksOneOrTwoLevels) {
  const InstancedScene s = random_instanced_scene(6, 2);
  EXPECT_EQ(make_accelerator("kdtree", s.tris, InstancedGeometry{})->name(), "kdtree");
  EXPECT_EQ(make_accelerator("brute", s.tris, InstancedGeometry{})->name(), "brute");
  for (const char* bottom : {"kdtree", "brute"}) {
    const auto accel = make_accelerator(bottom, s.tris, s.geometry);
    ASSERT_EQ(accel->name(), "twolevel");
    const auto& two = dynamic_cast<const TwoLevelAccelerator&>(*accel);
    EXPECT_EQ(two.bottom_name(), bottom);
    EXPECT_EQ(two.instance_count(), s.geometry.instances.size());
    EXPECT_EQ(two.mesh_count(), 3u);
    EXPECT_EQ(two.bottom_count(), 2u) << "mesh 2 is drawn by no instance";
    EXPECT_GT(two.top_level().nodes().size(), 1u);
  }
}

// Edge cases of the input: no instances, an instance of an empty mesh, non-finite rays
// (the scan path) and a zero direction give the definition's answers, as single rays and
// as packets (a packet's scanned lanes enter every instance with the others when the top
// level is met instance by instance, and go one by one when it is walked as a tree).
TEST(TwoLevelInput, EmptyAndDegenerateCases) {
  {
    InstancedScene none = random_instanced_scene(8, 0);
    none.geometry.instances.clear();
    const TwoLevelAccelerator accel(none.tris, none.geometry, "kdtree");
    EXPECT_FALSE(accel.intersect(Ray{}).valid());
    EXPECT_FALSE(accel.occluded(Ray{}));
  }
  for (const int extra : {0, 12}) {
    InstancedScene s = random_instanced_scene(8, extra);
    s.geometry.meshes.push_back({5, 0});  // an empty mesh, drawn
    s.geometry.instances.push_back(make_instance(3, glm::dmat3(1.0), {0, 0, 0}));
    const TwoLevelAccelerator accel(s.tris, s.geometry, "kdtree");
    ASSERT_EQ(accel.meets_few_instances(), extra == 0);
    const InstanceScan scan(s);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Ray rays[] = {
        Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity},
        Ray{{nan, 0.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity},
        Ray{{-10.0f, 0.0f, 0.0f}, 0.0f, {kInfinity, 0.0f, 0.0f}, kInfinity},
        Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {0.0f, 0.0f, 0.0f}, kInfinity},
        Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {1e-30f, 1e-31f, 0.0f}, kInfinity},
        Ray{{1e25f, 0.1f, 0.2f}, 0.0f, {-1.0f, 0.0f, 0.0f}, kInfinity},
        Ray{{-10.0f, 0.1f, 0.2f}, 0.0f, {1.0f, 0.0f, 0.0f}, nan},
    };
    constexpr int kRays = sizeof(rays) / sizeof(rays[0]);
    for (const Ray& r : rays) {
      EXPECT_TRUE(same_bits(accel.intersect(r), scan.intersect(r))) << describe(r);
      EXPECT_EQ(accel.occluded(r), scan.occluded(r)) << describe(r);
    }
    EXPECT_TRUE(accel.intersect(rays[0]).valid());
    // A packet of them all, each beside ordinary rays from the same origin.
    std::vector<Ray> packet;
    for (int k = 0; k < 64; ++k) {
      Ray r = rays[k % kRays];
      if (k >= kRays && (k / kRays) % 2 == 1) r = Ray{{-10.0f, 0.05f * float(k % 7), 0.2f}, 0.0f, {1.0f, 0.01f * float(k % 5), 0.0f}, kInfinity};
      packet.push_back(r);
    }
    std::vector<Hit> hits(packet.size());
    accel.intersect_packet(packet.data(), hits.data(), int(packet.size()));
    bool occluded[64];
    accel.occluded_packet(packet.data(), occluded, int(packet.size()));
    for (std::size_t k = 0; k < packet.size(); ++k) {
      EXPECT_TRUE(same_bits(hits[k], accel.intersect(packet[k]))) << "lane " << k << ": " << describe(packet[k]);
      EXPECT_EQ(occluded[k], accel.occluded(packet[k])) << "lane " << k << ": " << describe(packet[k]);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, TwoLevel, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
