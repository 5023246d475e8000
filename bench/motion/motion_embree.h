// Embree 3 as lancer-motion-bench's baseline: a Lancer scene drawn through instances,
// moving ones with time steps, behind an interface free of Embree's headers so the program
// builds without Embree (motion_embree_none.cpp: the constructor says Embree is absent).
//
// The Embree scene is what a renderer would ask for: each mesh (InstancedGeometry::meshes)
// one RTC_GEOMETRY_TYPE_TRIANGLE geometry in its own committed scene, drawn by one
// RTC_GEOMETRY_TYPE_INSTANCE per Lancer instance (geometry ID = instance index), BVHs of
// high quality, on a device whose ISA is capped at Lancer's best. A moving instance gets
// one time step per MotionKey (rtcSetGeometryTimeStepCount), evenly spaced over [0, 1] as
// Lancer's keys are. Embree interpolates a quaternion decomposition T R S as Lancer does
// (T and S linearly, R by slerp), but its S is upper triangular while Lancer's stretch is
// symmetric: the two agree exactly only when every key's stretch is diagonal. Such an
// instance gets rtcSetGeometryTransformQuaternion per step (quaternion signs chosen so
// neighbours lie on the shorter arc, as Lancer's slerp takes it); any other gets
// rtcSetGeometryTransform per step, which Embree interpolates as matrices, linearly:
// exact at the keys, apart from Lancer between keys where the key turns (or stretches).
// A scene without instances is one world-space mesh drawn once, with Hit::instance kNoHit.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "accel/ray.h"
#include "scene/scene.h"

namespace lancer::bench {

// True when this program was built with Embree.
bool motion_embree_available();
// One line: Embree's version, or why it is missing.
std::string motion_embree_description();

class EmbreeMotionScene {
 public:
  // Builds the scenes of `scene` (meshes, instances, motions; `scene` may be destroyed
  // afterwards) with `threads` build threads (0: all). Throws std::runtime_error with
  // Embree's message on any Embree error, or when Embree is not built in.
  EmbreeMotionScene(const Scene& scene, int threads);
  ~EmbreeMotionScene();
  EmbreeMotionScene(const EmbreeMotionScene&) = delete;
  EmbreeMotionScene& operator=(const EmbreeMotionScene&) = delete;

  // Closest hits of rays[0..count) at each ray's Ray::time, in Lancer's Hit: prim the
  // triangle's index in scene.triangles, instance Lancer's instance index. Single: one
  // rtcIntersect1 per ray; otherwise rtcIntersect16 on up to 16 rays at a time (the rest of
  // the packet masked off). Thread-safe.
  void intersect(bool single, const Ray* rays, Hit* hits, std::size_t count) const;

  double build_ms() const;
  // Moving instances given as quaternion decompositions, and as matrices (see above).
  std::size_t quaternion_instances() const;
  std::size_t matrix_instances() const;
  // Throws std::runtime_error naming the first Embree error since the last check.
  void check_errors() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lancer::bench
