// Shared helpers of the two-level accelerator tests: random instanced scenes, two
// references (every instance scanned by definition; the scene flattened into world space
// in double) and ray generators.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "accel/brute_force.h"
#include "accel/instances.h"
#include "accel/two_level.h"
#include "kd_test_support.h"
#include "scene/procedural.h"

namespace lancer::test {

struct InstancedScene {
  TriangleSoA tris;
  InstancedGeometry geometry;
};

// An instance of `mesh` through to_world = (linear, offset); to_object is its inverse in
// double, rounded, as the contract (instances.h) says.
inline Instance make_instance(std::uint32_t mesh, const glm::dmat3& linear, const glm::dvec3& offset) {
  Instance inst;
  inst.mesh = mesh;
  inst.to_world.linear = glm::mat3(linear);
  inst.to_world.offset = glm::vec3(offset);
  const glm::dmat3 inv = glm::inverse(glm::dmat3(inst.to_world.linear));
  inst.to_object.linear = glm::mat3(inv);
  inst.to_object.offset = glm::vec3(-(inv * glm::dvec3(inst.to_world.offset)));
  return inst;
}

// A random rotation (from a random unit quaternion) times a diagonal scale.
inline glm::dmat3 random_linear(TestRng& rng, glm::dvec3 scale) {
  double q[4];
  for (;;) {
    double l2 = 0.0;
    for (double& c : q) c = rng.uniform(-1.0f, 1.0f), l2 += c * c;
    if (l2 > 1e-3 && l2 <= 1.0) {
      for (double& c : q) c /= std::sqrt(l2);
      break;
    }
  }
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const glm::dmat3 rot(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y),   // column 0
                       2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x),   // column 1
                       2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));  // column 2
  return rot * glm::dmat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
}

// Three meshes: a random soup (mesh 0), a closed icosphere (mesh 1) and a soup no instance
// draws (mesh 2, stored between the others so mesh 1 starts at a nonzero offset after it).
// Instances: rotated, non-uniformly scaled, one mirrored (negative determinant), some
// overlapping, an identity one, and instance 5 drawn twice at the same place (instances 5
// and 6: exact ties in t, which the lower instance must win).
inline InstancedScene random_instanced_scene(std::uint64_t seed, int extra_instances = 8) {
  InstancedScene s;
  const Bounds3 unit{{-1, -1, -1}, {1, 1, 1}};
  const TriangleSoA soup = random_soup(300, seed, unit, 0.6f);
  Scene sphere;
  append_icosphere(sphere, {0.0f, 0.0f, 0.0f}, 1.0f, 2, 0);
  const TriangleSoA unused = random_soup(40, seed + 1, unit, 0.5f);
  auto append = [&](const TriangleSoA& t) {
    const MeshRange r{static_cast<std::uint32_t>(s.tris.size()), static_cast<std::uint32_t>(t.size())};
    for (std::size_t i = 0; i < t.size(); ++i) s.tris.push_back(t.vertex(i, 0), t.vertex(i, 1), t.vertex(i, 2));
    return r;
  };
  const MeshRange soup_range = append(soup), unused_range = append(unused), sphere_range = append(sphere.triangles);
  s.geometry.meshes = {soup_range, sphere_range, unused_range};

  TestRng rng(seed * 31 + 7);
  auto& inst = s.geometry.instances;
  inst.push_back(make_instance(0, glm::dmat3(1.0), {0, 0, 0}));                                       // identity
  inst.push_back(make_instance(1, random_linear(rng, {1.5, 0.5, 1.0}), {2.5, 0.3, -0.4}));            // ellipsoid
  inst.push_back(make_instance(0, random_linear(rng, {-1.2, 0.8, 1.1}), {-2.2, 1.0, 0.5}));           // mirrored
  inst.push_back(make_instance(1, random_linear(rng, {0.6, 0.6, 0.6}), {0.4, 0.5, 0.2}));             // overlaps 0
  inst.push_back(make_instance(0, random_linear(rng, {2.0, 0.3, 1.0}), {1.0, -2.0, 1.5}));
  const Instance twin = make_instance(1, random_linear(rng, {0.9, 1.3, 0.7}), {-1.0, -1.2, -2.0});
  inst.push_back(twin);
  inst.push_back(twin);  // coincident with instance 5
  for (int i = 0; i < extra_instances; ++i) {
    const glm::dvec3 scale(rng.uniform(0.3f, 1.6f), rng.uniform(0.3f, 1.6f), rng.uniform(0.3f, 1.6f));
    const glm::dvec3 at(rng.uniform(-4.0f, 4.0f), rng.uniform(-4.0f, 4.0f), rng.uniform(-4.0f, 4.0f));
    inst.push_back(make_instance(rng.below(2), random_linear(rng, scale), at));
  }
  return s;
}

// The definition the accelerator must meet bit for bit: every instance, in index order,
// entered with ray_to_object, its mesh tested by the brute-force oracle over the whole ray
// range; the lexicographic minimum of (t, instance, triangle) wins.
class InstanceScan {
 public:
  explicit InstanceScan(const InstancedScene& s) : geometry_(s.geometry) {
    for (const MeshRange& r : geometry_.meshes) {
      auto t = std::make_unique<TriangleSoA>();
      for (std::uint32_t i = 0; i < r.count; ++i)
        t->push_back(s.tris.vertex(r.first + i, 0), s.tris.vertex(r.first + i, 1), s.tris.vertex(r.first + i, 2));
      oracles_.push_back(std::make_unique<BruteForce>(*t));
      meshes_.push_back(std::move(t));
    }
  }

  Hit intersect(const Ray& ray) const {
    Hit best;
    for (std::uint32_t i = 0; i < geometry_.instances.size(); ++i) {
      const Instance& inst = geometry_.instances[i];
      Hit h = oracles_[inst.mesh]->intersect(ray_to_object(inst, ray));
      if (!h.valid() || !(h.t < best.t || (h.t == best.t && i < best.instance))) continue;
      h.prim += geometry_.meshes[inst.mesh].first;
      h.instance = i;
      best = h;
    }
    return best;
  }

  bool occluded(const Ray& ray) const {
    for (const Instance& inst : geometry_.instances)
      if (oracles_[inst.mesh]->occluded(ray_to_object(inst, ray))) return true;
    return false;
  }

 private:
  InstancedGeometry geometry_;
  std::vector<std::unique_ptr<TriangleSoA>> meshes_;
  std::vector<std::unique_ptr<BruteForce>> oracles_;
};

// The scene flattened: every instance's triangles moved to world space in double (then
// rounded), instance by instance, so flat index order is (instance, triangle) order.
struct FlatScene {
  TriangleSoA tris;
  std::vector<std::uint32_t> instance, prim;  // per flat triangle
};

inline FlatScene flatten(const InstancedScene& s) {
  FlatScene f;
  for (std::uint32_t i = 0; i < s.geometry.instances.size(); ++i) {
    const Instance& inst = s.geometry.instances[i];
    const MeshRange r = s.geometry.meshes[inst.mesh];
    const glm::dmat3 m(inst.to_world.linear);
    const glm::dvec3 b(inst.to_world.offset);
    for (std::uint32_t k = 0; k < r.count; ++k) {
      glm::vec3 v[3];
      for (int c = 0; c < 3; ++c) v[c] = glm::vec3(m * glm::dvec3(s.tris.vertex(r.first + k, c)) + b);
      f.tris.push_back(v[0], v[1], v[2]);
      f.instance.push_back(i);
      f.prim.push_back(r.first + k);
    }
  }
  return f;
}

inline bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

// Rays through an instanced scene (world triangles `flat`, boxed by `box`), deterministic
// in (seed, index): random, aimed at a triangle, at a vertex (edges), from inside the box
// and from the centre of an instance (inside the closed spheres), axis-parallel, finite
// segments, and from a thousand scene sizes away.
inline Ray instanced_scene_ray(const InstancedScene& s, const FlatScene& flat, const Bounds3& box, std::uint64_t seed,
                               std::size_t index) {
  TestRng rng(seed * 0x100000001B3ull + index);
  const Bounds3 outer = grown(box, 0.5f);
  Ray r;
  switch (index % 8) {
    case 0: r.org = rng.in_box(outer), r.dir = rng.direction(); break;
    case 1: r.org = rng.in_box(outer), r.dir = point_on_triangle(flat.tris, rng) - r.org; break;
    case 2: r.org = rng.in_box(outer), r.dir = random_vertex(flat.tris, rng) - r.org; break;
    case 3: r.org = rng.in_box(box), r.dir = rng.direction(); break;
    case 4: {
      const Instance& inst = s.geometry.instances[rng.below(static_cast<std::uint32_t>(s.geometry.instances.size()))];
      r.org = inst.to_world.offset;
      r.dir = rng.direction();
      break;
    }
    case 5: {
      const int axis = static_cast<int>(rng.below(3));
      r.org = point_on_triangle(flat.tris, rng);
      r.org[axis] = rng.below(2) ? outer.lo[axis] : rng.uniform(box.lo[axis], box.hi[axis]);
      r.dir = glm::vec3(0.0f);
      r.dir[axis] = rng.below(2) ? 1.0f : -1.0f;
      break;
    }
    case 6:
      r.org = rng.in_box(outer);
      r.dir = point_on_triangle(flat.tris, rng) - r.org;
      r.tnear = rng.uniform(0.0f, 0.9f);
      r.tfar = r.tnear + rng.uniform(0.0f, 0.3f);
      break;
    default: {
      const glm::vec3 target = point_on_triangle(flat.tris, rng);
      r.org = target + 1000.0f * (box.hi - box.lo) * rng.direction();
      r.dir = target - r.org;
      break;
    }
  }
  if (r.dir == glm::vec3(0.0f)) r.dir = {0.0f, 0.0f, 1.0f};
  return r;
}

}  // namespace lancer::test
