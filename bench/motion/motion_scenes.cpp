#include "motion_scenes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "accel/accel_factory.h"
#include "render/ray_sets.h"
#include "render/sampler.h"
#include "scene/scene_instancing.h"

namespace lancer::bench {

namespace {

// Bunny i at shutter fraction f: scaled, turned about y, on its line from its grid cell.
glm::dmat4 bunny_at(int i, int n, const Bounds3& box, double f) {
  const int side = int(std::ceil(std::sqrt(double(n))));
  const double spacing = 1.6 * std::max(box.extent().x, box.extent().z);
  const double heading = 2.39996 * i;  // golden angle: every bunny its own direction
  const double travel = 0.6 * spacing * f;
  const double angle = 0.37 * i + 0.5 * (i % 4) * f;  // turns by 0, 0.5, 1 or 1.5 rad
  const double scale = 0.8 + 0.4 * (i % 7) / 6.0;
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(scale * std::cos(angle), 0.0, -scale * std::sin(angle), 0.0);
  m[1] = glm::dvec4(0.0, scale, 0.0, 0.0);
  m[2] = glm::dvec4(scale * std::sin(angle), 0.0, scale * std::cos(angle), 0.0);
  m[3] = glm::dvec4(spacing * (i % side) + travel * std::cos(heading), 0.2 * spacing * f * (i % 3),
                    spacing * (i / side) + travel * std::sin(heading), 1.0);
  return m;
}

std::uint32_t reverse6(std::uint32_t k) {
  std::uint32_t r = 0;
  for (int b = 0; b < 6; ++b) r |= ((k >> b) & 1u) << (5 - b);
  return r;
}

}  // namespace

Scene moving_bunnies(const Scene& bunny, int n) {
  Scene s;
  s.source = std::to_string(n) + " moving bunnies";
  const auto count = std::uint32_t(bunny.triangle_count());
  s.triangles = bunny.triangles;
  s.material_id.assign(count, 0);
  s.source_triangle_id.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) s.source_triangle_id[i] = i;
  s.attrib_flags.assign(count, 0);
  s.materials.emplace_back();
  s.instancing.meshes.push_back({0, count});
  const Bounds3 box = bunny.bounds();
  for (int i = 0; i < n; ++i) {
    InstanceMotion motion;
    for (int k = 0; k < kShutterSteps; ++k) {
      const std::optional<MotionKey> key = motion_key(bunny_at(i, n, box, double(k) / (kShutterSteps - 1)));
      if (!key) throw std::logic_error("moving_bunnies: a key matrix was refused");
      motion.keys.push_back(*key);
    }
    Instance inst = instance_from_key(0, motion.keys.front());
    inst.motion = std::uint32_t(s.instancing.motions.size());
    s.instancing.motions.push_back(std::move(motion));
    s.instancing.instances.push_back(inst);
    s.instance_source_base.push_back(std::uint32_t(i) * count);
  }
  return s;
}

Scene still_copy(Scene scene) {
  for (Instance& inst : scene.instancing.instances) inst.motion = kNoHit;
  scene.instancing.motions.clear();
  return scene;
}

float stratified_time(int x, int y) {
  const auto tx = std::uint32_t(x / kRayTileSide), ty = std::uint32_t(y / kRayTileSide);
  const auto within = std::uint32_t((y % kRayTileSide) * kRayTileSide + x % kRayTileSide);
  const auto scramble = std::uint32_t(PixelSampler(tx, ty, 1, 0).get(0) * 64.0f) & 63u;
  const std::uint32_t stratum = reverse6(within) ^ scramble;
  const float jitter = PixelSampler(std::uint32_t(x), std::uint32_t(y), 0, 0).get(7);
  return std::min((float(stratum) + jitter) / 64.0f, 0x1.fffffep-1f);
}

MotionReference::MotionReference(const Scene& scene) : scene_(scene) {
  if (scene.instancing.empty()) {
    trees_.push_back(make_accelerator("kdtree", scene.triangles));
    return;
  }
  for (const MeshRange& mesh : scene.instancing.meshes) {
    auto tris = std::make_unique<TriangleSoA>();
    for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i)
      tris->push_back(scene.triangles.vertex(i, 0), scene.triangles.vertex(i, 1), scene.triangles.vertex(i, 2));
    trees_.push_back(make_accelerator("kdtree", *tris));
    meshes_.push_back(std::move(tris));
  }
}

Hit MotionReference::intersect(const Ray& ray) const {
  const InstancedGeometry& geometry = scene_.instancing;
  if (geometry.empty()) return trees_.front()->intersect(ray);
  Hit best;
  for (std::uint32_t i = 0; i < geometry.instances.size(); ++i) {
    const Instance inst = instance_at(geometry, geometry.instances[i], ray.time);
    Ray local = ray_to_object(inst, ray);
    local.tfar = std::min(ray.tfar, best.t);
    Hit h = trees_[inst.mesh]->intersect(local);
    if (!h.valid() || h.t >= best.t) continue;
    h.prim += geometry.meshes[inst.mesh].first;
    h.instance = i;
    best = h;
  }
  return best;
}

}  // namespace lancer::bench
