// Shared helpers of the moving-instance tests: scenes whose instances move over the
// shutter (far translations, large rotations, changing and mirroring stretches, static
// instances among them), the definition with instance_at per ray, and rays at random times
// aimed at where the meshes are then.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "accel/brute_force.h"
#include "accel/instances.h"
#include "two_level_test_support.h"

namespace lancer::test {

inline glm::quat about(glm::vec3 axis, float degrees) {
  return glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
}

// A symmetric positive definite stretch: diag(scale) turned by a random rotation.
inline glm::mat3 random_stretch(TestRng& rng, glm::dvec3 scale) {
  const glm::dmat3 q = random_linear(rng, {1.0, 1.0, 1.0});
  return glm::mat3(q * glm::dmat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z) * glm::transpose(q));
}

inline MotionKey make_key(glm::vec3 translation, glm::quat rotation, glm::mat3 stretch = glm::mat3(1.0f)) {
  MotionKey k;
  k.translation = translation;
  k.rotation = glm::normalize(rotation);
  k.stretch = stretch;
  return k;
}

// Makes instance i of `s` move along `keys` (its static transforms become the first key's).
inline void set_motion(InstancedScene& s, std::size_t i, std::vector<MotionKey> keys) {
  Instance& inst = s.geometry.instances[i];
  inst = instance_from_key(inst.mesh, keys[0]);
  inst.motion = static_cast<std::uint32_t>(s.geometry.motions.size());
  s.geometry.motions.push_back(InstanceMotion{std::move(keys)});
}

// Appends `tris` as a new mesh of `s`; returns its index.
inline std::uint32_t add_mesh(InstancedScene& s, const TriangleSoA& tris) {
  const MeshRange r{static_cast<std::uint32_t>(s.tris.size()), static_cast<std::uint32_t>(tris.size())};
  for (std::size_t i = 0; i < tris.size(); ++i) s.tris.push_back(tris.vertex(i, 0), tris.vertex(i, 1), tris.vertex(i, 2));
  s.geometry.meshes.push_back(r);
  return static_cast<std::uint32_t>(s.geometry.meshes.size() - 1);
}

// random_instanced_scene with most instances moving: far translations over three keys,
// rotations by up to 179 degrees between keys, stretches that change (non-uniform, turned),
// a mirrored instance whose keys all mirror, and a cube off its instance's origin sweeping
// a half circle (the box bulge). Instances 0, 5 and 6 stay still (6 coincides with 5).
inline InstancedScene random_moving_scene(std::uint64_t seed, int extra_instances = 8) {
  InstancedScene s = random_instanced_scene(seed, extra_instances);
  Scene cube;
  append_box(cube, {{4.9f, -0.05f, -0.05f}, {5.0f, 0.05f, 0.05f}}, 0);  // small: its corners share one phase
  const std::uint32_t off_centre = add_mesh(s, cube.triangles);
  TestRng rng(seed * 17 + 3);
  auto axis = [&] { return rng.direction(); };
  auto at = [&](float reach) { return reach * rng.direction(); };
  // Instance 1: far translation, turning a little.
  set_motion(s, 1, {make_key(at(4), about(axis(), 10)), make_key(at(4) + glm::vec3(30, -20, 10), about(axis(), 40)),
                    make_key(at(4) + glm::vec3(-25, 15, 20), about(axis(), 60))});
  // Instance 2: mirrored at both keys (negative definite stretches), rotating 150 degrees.
  {
    const glm::vec3 ax = axis();
    set_motion(s, 2, {make_key(at(3), about(ax, 0), -random_stretch(rng, {1.2, 0.8, 1.1})),
                      make_key(at(3), about(ax, 150), -random_stretch(rng, {0.6, 1.4, 0.9}))});
  }
  // Instance 3: growing and squashing.
  set_motion(s, 3, {make_key(at(2), about(axis(), 30), random_stretch(rng, {0.3, 0.3, 0.3})),
                    make_key(at(2), about(axis(), 35), random_stretch(rng, {1.8, 0.4, 1.0}))});
  // Instance 4: 179 degrees per key about a fixed axis, with a stretch that changes.
  {
    const glm::vec3 ax = axis(), base = at(3);
    set_motion(s, 4, {make_key(base, about(ax, 0)), make_key(base, about(ax, 179), random_stretch(rng, {1.5, 0.7, 1.0})),
                      make_key(base, about(ax, 358))});
  }
  // The extra instances: every other one moves, with a random large turn.
  for (std::size_t i = 7; i < s.geometry.instances.size(); i += 2) {
    const glm::vec3 ax = axis(), base = at(5);
    const float turn = rng.uniform(20.0f, 179.0f);
    set_motion(s, i, {make_key(base, about(ax, 0), random_stretch(rng, {0.8, 1.0, 1.2})),
                      make_key(base + at(3), about(ax, turn), random_stretch(rng, {1.1, 0.7, 0.9}))});
  }
  // Two off-centre cubes sweeping half circles about the z and another axis.
  for (int k = 0; k < 2; ++k) {
    s.geometry.instances.push_back(Instance{off_centre});
    const glm::vec3 ax = k == 0 ? glm::vec3(0, 0, 1) : axis(), base = at(2);
    set_motion(s, s.geometry.instances.size() - 1,
               {make_key(base, about(ax, 0)), make_key(base, about(ax, 175)), make_key(base, about(ax, 350))});
  }
  return s;
}

// The definition at every time: every instance, in index order, entered with
// ray_to_object(instance_at(geometry, inst, ray.time), ray), its mesh tested by the
// brute-force oracle; the lexicographic minimum of (t, instance, triangle) wins.
class MotionScan {
 public:
  explicit MotionScan(const InstancedScene& s) : geometry_(s.geometry) {
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
      Hit h = oracles_[inst.mesh]->intersect(ray_to_object(fresh_instance_at(inst, ray.time), ray));
      if (!h.valid() || !(h.t < best.t || (h.t == best.t && i < best.instance))) continue;
      h.prim += geometry_.meshes[inst.mesh].first;
      h.instance = i;
      best = h;
    }
    return best;
  }

  bool occluded(const Ray& ray) const {
    for (const Instance& inst : geometry_.instances)
      if (oracles_[inst.mesh]->occluded(ray_to_object(fresh_instance_at(inst, ray.time), ray))) return true;
    return false;
  }

 private:
  // instance_at computed afresh, not taken from the per-thread memo the accelerator also
  // uses: the definition stays independent of it.
  Instance fresh_instance_at(const Instance& inst, float time) const {
    if (inst.motion == kNoHit) return inst;
    forget_moved_instances();
    return instance_at(geometry_, inst, time);
  }

  InstancedGeometry geometry_;
  std::vector<std::unique_ptr<TriangleSoA>> meshes_;
  std::vector<std::unique_ptr<BruteForce>> oracles_;
};

// The world box of every instance at every time, loosely (from samples): where rays start.
inline Bounds3 sampled_scene_box(const InstancedScene& s) {
  Bounds3 box;
  for (const Instance& inst : s.geometry.instances) {
    const MeshRange r = s.geometry.meshes[inst.mesh];
    for (int j = 0; j <= 8; ++j) {
      const Instance at = instance_at(s.geometry, inst, float(j) / 8.0f);
      for (std::uint32_t k = 0; k < r.count; k += 7) box.extend(at.to_world.point(s.tris.vertex(r.first + k, 0)));
    }
  }
  return box;
}

// Rays at random times, deterministic in (seed, index): random; aimed at a point of a
// random instance's triangle where it is at the ray's time; aimed just inside a corner of
// a triangle then (the extreme points of a sweeping mesh: they test the box margins);
// axis-parallel through such a point; segments; and from far away.
inline Ray moving_scene_ray(const InstancedScene& s, const Bounds3& box, std::uint64_t seed, std::size_t index) {
  TestRng rng(seed * 0x100000001B3ull + index);
  const Bounds3 outer = grown(box, 0.3f);
  Ray r;
  r.time = rng.uniform(0.0f, 1.0f);
  const auto j = rng.below(static_cast<std::uint32_t>(s.geometry.instances.size()));
  const Instance inst = instance_at(s.geometry, s.geometry.instances[j], r.time);
  const MeshRange mesh = s.geometry.meshes[inst.mesh];
  glm::vec3 target(0.0f);
  if (mesh.count > 0) {
    const std::uint32_t k = mesh.first + rng.below(mesh.count);
    const glm::vec3 a = s.tris.vertex(k, 0), b = s.tris.vertex(k, 1), c = s.tris.vertex(k, 2);
    float u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    if (index % 6 == 2) u = rng.uniform(0.0f, 1e-3f), v = rng.uniform(0.0f, 1e-3f);  // by the corner a
    target = inst.to_world.point((1.0f - u - v) * a + u * b + v * c);
  }
  switch (index % 6) {
    case 0: r.org = rng.in_box(outer), r.dir = rng.direction(); break;
    case 1:
    case 2: r.org = rng.in_box(outer), r.dir = target - r.org; break;
    case 3: {
      const int axis = static_cast<int>(rng.below(3));
      r.org = target;
      r.org[axis] = rng.below(2) ? outer.lo[axis] : outer.hi[axis];
      r.dir = glm::vec3(0.0f);
      r.dir[axis] = target[axis] > r.org[axis] ? 1.0f : -1.0f;
      break;
    }
    case 4:
      r.org = rng.in_box(outer);
      r.dir = target - r.org;
      r.tnear = rng.uniform(0.0f, 0.9f);
      r.tfar = r.tnear + rng.uniform(0.0f, 0.3f);
      break;
    default: r.org = target + 1000.0f * (box.hi - box.lo) * rng.direction(), r.dir = target - r.org; break;
  }
  if (r.dir == glm::vec3(0.0f)) r.dir = {0.0f, 0.0f, 1.0f};
  return r;
}

inline std::string describe_moving(const Ray& r) {
  std::ostringstream o;
  o.precision(9);
  o << describe(r) << " time " << r.time;
  return o.str();
}

inline std::string describe_moving_hit(const Hit& h) {
  std::ostringstream o;
  o.precision(9);
  o << "instance " << h.instance << " prim " << h.prim << " t " << h.t << " u " << h.u << " v " << h.v;
  return o.str();
}

}  // namespace lancer::test
