// Scenes and rays shared by the benchmark programs (lancer_bench_micro and
// lancer_bench_embree), so that Lancer and the Embree baseline run on the same triangles
// and the same rays.
//
// Scenes: "spheres" (procedural, about 100k triangles of spheres of different sizes and
// tessellations) and "bunny" (stanford-bunny.obj from LANCER_MODELS_DIR, only when present).
// Rays: a 256 x 256 pinhole camera ("primary") and one diffuse bounce from every primary hit
// ("diffuse"); both are deterministic.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "accel/accelerator.h"
#include "accel/ray_offset.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "simd/splitmix64.h"

namespace lancer::bench {

// The shared meshes: the compile definition LANCER_MODELS_DIR (set in bench/CMakeLists.txt),
// unless the environment variable of the same name overrides it.
inline std::filesystem::path models_dir() {
  if (const char* env = std::getenv("LANCER_MODELS_DIR")) return env;
  return LANCER_MODELS_DIR;
}

// The scenes available on this machine: "spheres", and "bunny" when the mesh is present.
inline std::vector<std::string> scene_names() {
  std::vector<std::string> names{"spheres"};
  if (std::filesystem::exists(models_dir() / "stanford-bunny.obj")) names.push_back("bunny");
  return names;
}

// Scenes are built or loaded once, on first use, and kept for the program's lifetime.
inline const TriangleSoA& scene(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Scene>();
    if (name == "bunny") {
      *slot = load_scene(models_dir() / "stanford-bunny.obj");
    } else {  // "spheres"
      append_icosphere(*slot, {0.0f, 0.0f, 0.0f}, 1.0f, 6, 0);
      append_icosphere(*slot, {2.5f, 0.0f, 0.5f}, 0.6f, 4, 0);
      append_uv_sphere(*slot, {-2.0f, 0.5f, -0.5f}, 0.8f, 96, 48, 0);
      for (int i = 0; i < 8; ++i) append_icosphere(*slot, {-3.0f + 0.8f * float(i), -1.8f, 0.0f}, 0.3f, 2, 0);
    }
  }
  return slot->triangles;
}

// A float in [0, 1) from a splitmix64 stream whose state is `s`.
inline float unit(std::uint64_t& s) { return float(splitmix64_mix(s += 0x9E3779B97F4A7C15ull) >> 40) * 0x1.0p-24f; }

// A 256 x 256 pinhole camera looking at the scene's centre from 1.2 box diagonals away.
inline std::vector<Ray> primary_rays(const TriangleSoA& t) {
  const Bounds3 b = t.bounds();
  const glm::vec3 c = b.center(), e = b.extent();
  const float diag = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  const glm::vec3 eye = c + glm::vec3(0.3f, 0.4f, 1.0f) * (1.2f * diag);
  const glm::vec3 fwd = glm::normalize(c - eye);
  const glm::vec3 right = glm::normalize(glm::vec3(fwd.z, 0.0f, -fwd.x));
  const glm::vec3 up = glm::vec3(right.y * fwd.z - right.z * fwd.y, right.z * fwd.x - right.x * fwd.z,
                                 right.x * fwd.y - right.y * fwd.x);
  const int n = 256;
  std::vector<Ray> rays;
  rays.reserve(n * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Ray r;
      r.org = eye;
      const float sx = (x + 0.5f) / n - 0.5f, sy = (y + 0.5f) / n - 0.5f;
      r.dir = fwd + 0.8f * (sx * right + sy * up);
      rays.push_back(r);
    }
  return rays;
}

// One diffuse bounce from every primary hit found by `accel` (pass Lancer's kd-tree, which
// gives exactly the oracle's hits, so every program gets the same rays): origin offset
// along the normal, direction uniform in the hemisphere (not normalised).
inline std::vector<Ray> diffuse_rays(const TriangleSoA& t, const Accelerator& accel) {
  std::vector<Ray> out;
  std::uint64_t seed = 7;
  for (const Ray& r : primary_rays(t)) {
    const Hit h = accel.intersect(r);
    if (!h.valid()) continue;
    const glm::vec3 a = t.vertex(h.prim, 0);
    glm::vec3 n = glm::cross(t.vertex(h.prim, 1) - a, t.vertex(h.prim, 2) - a);
    if (glm::dot(n, r.dir) > 0.0f) n = -n;
    n = glm::normalize(n);
    Ray s;
    s.org = offset_ray_origin(r.org + h.t * r.dir, n);
    do {
      s.dir = glm::vec3(unit(seed), unit(seed), unit(seed)) * 2.0f - 1.0f;
    } while (glm::dot(s.dir, s.dir) > 1.0f || glm::dot(s.dir, s.dir) < 1e-4f);
    if (glm::dot(s.dir, n) < 0.0f) s.dir = -s.dir;
    out.push_back(s);
  }
  return out;
}

}  // namespace lancer::bench
