// Meshes stored once and drawn many times: the input of the two-level accelerator.
// A mesh is a range of the scene's TriangleSoA, in its own (object) space; an instance
// draws one mesh through an affine transform. Hits name the instance (Hit::instance) and
// the triangle's index in the whole TriangleSoA (Hit::prim), so shading reads per-corner
// attributes exactly as for a one-level scene.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"

namespace lancer {

// Triangles [first, first + count) of the TriangleSoA.
struct MeshRange {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

// x -> linear * x + offset, in float. The two-level accelerator moves rays into an
// instance's space with exactly these operations (the build keeps -ffp-contract=off, so
// every translation unit rounds them alike); the renderer's ray offsets repeat them to
// prove a ray cannot hit the triangle it leaves.
struct Affine {
  glm::mat3 linear{1.0f};
  glm::vec3 offset{0.0f};

  glm::vec3 point(const glm::vec3& p) const { return vector(p) + offset; }
  glm::vec3 vector(const glm::vec3& v) const {
    return {linear[0][0] * v.x + linear[1][0] * v.y + linear[2][0] * v.z,
            linear[0][1] * v.x + linear[1][1] * v.y + linear[2][1] * v.z,
            linear[0][2] * v.x + linear[1][2] * v.y + linear[2][2] * v.z};
  }
};

// One drawing of mesh `mesh`. to_object is the inverse of to_world (computed in double,
// then rounded), and to_world's linear part is invertible. A moving instance (`motion` an
// index into InstancedGeometry::motions) has these at shutter open, and instance_at gives
// them at any time.
struct Instance {
  std::uint32_t mesh = 0;
  Affine to_world;
  Affine to_object;
  std::uint32_t motion = kNoHit;
};

// A transform as moving geometry interpolates it: translation, and the polar decomposition
// linear = rotation * stretch (Shoemake & Duff, "Matrix Animation and Polar Decomposition",
// Graphics Interface 1992), the rotation proper (a mirror stays in the stretch, which is
// symmetric).
struct MotionKey {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // unit, w first
  glm::mat3 stretch{1.0f};
};

// A moving instance's transform at evenly spaced times from shutter open (time 0, keys[0])
// to close (time 1, keys.back()), at least two keys. Between neighbours translation and
// stretch are interpolated linearly, rotation by slerp on the shorter arc.
struct InstanceMotion {
  std::vector<MotionKey> keys;
};

// The ray as the accelerator traces it inside `inst`: origin and direction in object space,
// the same tnear and tfar (the direction is not renormalised, so t keeps its meaning).
inline Ray ray_to_object(const Instance& inst, const Ray& ray) {
  return Ray{inst.to_object.point(ray.org), ray.tnear, inst.to_object.vector(ray.dir), ray.tfar, ray.time};
}

// A scene whose triangles are drawn through instances. Empty: the triangles are in world
// space and drawn once (the one-level case). Otherwise every triangle belongs to exactly
// one mesh, and a mesh drawn in world space has an instance with identity transforms.
struct InstancedGeometry {
  std::vector<MeshRange> meshes;
  std::vector<Instance> instances;
  std::vector<InstanceMotion> motions;  // of the moving instances (Instance::motion)

  bool empty() const { return instances.empty(); }
};

// The transforms of `key` (to_world from it, to_object its inverse, both computed in double
// and rounded once): the one routine the accelerator and the renderer's ray offsets use.
Instance instance_from_key(std::uint32_t mesh, const MotionKey& key);

// Where `time` falls among key_count >= 2 evenly spaced keys (clamped to [0, 1], NaN as 0):
// the key interval instance_at interpolates in, and the fraction f in [0, 1] within it.
struct KeyTime {
  std::size_t interval;
  double f;
};
inline KeyTime key_time(std::size_t key_count, float time) {
  const double t = std::clamp(std::isnan(time) ? 0.0 : double(time), 0.0, 1.0);
  const double x = t * double(key_count - 1);
  // Through int: x is below 2^31 (key counts are small), and the conversion to int is one
  // instruction where the one to size_t is not.
  const std::size_t i = std::min(std::size_t(int(x)), key_count - 2);
  return {i, x - double(i)};
}

// `inst` at `time` in [0, 1] (clamped; NaN counts as 0): itself when it does not move, else
// its motion's keys interpolated and made an Instance by instance_from_key. Deterministic:
// the same time gives the same bits wherever it is called. Results are memoised per
// thread (instances.cpp), keyed by all they depend on.
Instance instance_at(const InstancedGeometry& geometry, const Instance& inst, float time);
// Empties this thread's memo, so that the next instance_at or PreparedMotions::at computes
// afresh (tests compare the two computations).
void forget_moved_instances();

// One key interval of a motion, with what every time inside it needs computed once: the
// slerp's angle and direction (an acos per call otherwise), and the stretch's inverse when
// the stretch does not change (a rigid motion: the stretch blends to itself).
struct MotionSpan {
  glm::dquat from{1.0, 0.0, 0.0, 0.0}, to{1.0, 0.0, 0.0, 0.0};  // unit; `to` on from's side
  glm::dquat across{0.0, 0.0, 0.0, 0.0};  // unit, orthogonal to `from`, in the plane of `to`
  double theta = 0.0;                     // 0: the rotations blend linearly (nearly equal)
  glm::dmat3 stretch_from{1.0}, stretch_to{1.0}, stretch_inverse{1.0};
  bool constant_stretch = true;
  glm::dvec3 translation_from{0.0}, translation_to{0.0};
};

// The motions of an InstancedGeometry as spans, for callers that interpolate often (the
// accelerator enters a moving instance once per ray). at() gives instance_at's bits.
class PreparedMotions {
 public:
  PreparedMotions() = default;
  explicit PreparedMotions(const InstancedGeometry& geometry);
  Instance at(const Instance& inst, float time) const;
  // The same for an instance that moves, by reference into this thread's memo: good until
  // the thread's next at, moving_at or instance_at.
  const Instance& moving_at(const Instance& inst, float time) const;
  std::size_t memory_bytes() const;

 private:
  std::vector<std::vector<MotionKey>> keys_;    // per motion
  std::vector<std::vector<MotionSpan>> spans_;  // per motion, per key interval
};

}  // namespace lancer
