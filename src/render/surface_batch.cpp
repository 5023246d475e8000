#include "render/surface_batch.h"


namespace lancer {

// The per-ISA solvers (surface_batch_<isa>.cpp); nothing here is built with ISA flags.
#if defined(__x86_64__) || defined(_M_X64)
namespace sse4 {
std::uint64_t solve_surface_lanes(const surface_batch::Lanes& lanes, int count, surface_batch::Out& out);
}
namespace avx2 {
std::uint64_t solve_surface_lanes(const surface_batch::Lanes& lanes, int count, surface_batch::Out& out);
}
namespace avx512 {
std::uint64_t solve_surface_lanes(const surface_batch::Lanes& lanes, int count, surface_batch::Out& out);
}
#endif

namespace {

using namespace surface_batch;

SolveLanesFn solver_for(Isa isa) {
#if defined(__x86_64__) || defined(_M_X64)
  return isa_version<SolveLanesFn>(isa, "surface_geometry", &sse4::solve_surface_lanes, &avx2::solve_surface_lanes,
                                   &avx512::solve_surface_lanes);
#else
  return isa_version<SolveLanesFn>(isa, "surface_geometry", nullptr, nullptr, nullptr);
#endif
}

constexpr int kPadLanes = 8;  // the widest solver's vector

void fill_lane(const Scene& scene, const Ray& ray, const Hit& hit, Lanes& lanes, int l) {
  const std::size_t i = hit.prim;
  for (int v = 0; v < 3; ++v) {
    const glm::vec3 c = scene.triangles.vertex(i, v);
    lanes.corner[3 * v][l] = c.x;
    lanes.corner[3 * v + 1][l] = c.y;
    lanes.corner[3 * v + 2][l] = c.z;
  }
  const bool normals = i < scene.attrib_flags.size() && (scene.attrib_flags[i] & kHasNormals);
  lanes.has_normals[l] = normals ? 1 : 0;
  for (int v = 0; v < 3; ++v) {
    const glm::vec3 n = normals ? scene.normals[3 * i + static_cast<std::size_t>(v)] : glm::vec3(0.0f);
    lanes.normal[3 * v][l] = n.x;
    lanes.normal[3 * v + 1][l] = n.y;
    lanes.normal[3 * v + 2][l] = n.z;
  }
  lanes.u[l] = hit.u;
  lanes.v[l] = hit.v;
  lanes.dir[0][l] = ray.dir.x;
  lanes.dir[1][l] = ray.dir.y;
  lanes.dir[2][l] = ray.dir.z;
}

void copy_lane(Lanes& lanes, int from, int to) {
  for (int k = 0; k < 9; ++k) {
    lanes.corner[k][to] = lanes.corner[k][from];
    lanes.normal[k][to] = lanes.normal[k][from];
  }
  lanes.u[to] = lanes.u[from];
  lanes.v[to] = lanes.v[from];
  for (int k = 0; k < 3; ++k) lanes.dir[k][to] = lanes.dir[k][from];
  lanes.has_normals[to] = lanes.has_normals[from];
}

}  // namespace

int surface_geometry(const Scene& scene, const Ray* rays, const Hit* hits, int count, SurfaceGeometry* geometry) {
  static const Isa best = best_supported_isa();  // probed once, not per bounce
  return surface_geometry(scene, rays, hits, count, geometry, best);
}

int surface_geometry(const Scene& scene, const Ray* rays, const Hit* hits, int count, SurfaceGeometry* geometry,
                     Isa isa) {
  const SolveLanesFn solve = solver_for(isa);
  int left = 0;
  alignas(64) Lanes lanes;
  alignas(64) Out out;
  int lane_hit[kMaxLanes];
  for (int first = 0; first < count;) {
    int n = 0;
    for (; first < count && n < kMaxLanes; ++first) {
      geometry[first].valid = false;
      const Hit& hit = hits[first];
      if (!hit.valid()) continue;
      // Drawn through an instance, or no solver: make_surface_point's.
      if (!solve || hit.instance != kNoHit) {
        ++left;
        continue;
      }
      fill_lane(scene, rays[first], hit, lanes, n);
      lane_hit[n++] = first;
    }
    if (n == 0) continue;
    for (int l = n; l % kPadLanes != 0; ++l) copy_lane(lanes, 0, l);
    const std::uint64_t done = solve(lanes, n, out);
    for (int l = 0; l < n; ++l) {
      if (!((done >> l) & 1u)) {
        ++left;
        continue;
      }
      SurfaceGeometry& g = geometry[lane_hit[l]];
      g.p = glm::vec3(out.p[0][l], out.p[1][l], out.p[2][l]);
      g.ng = glm::vec3(out.ng[0][l], out.ng[1][l], out.ng[2][l]);
      g.ns = glm::vec3(out.ns[0][l], out.ns[1][l], out.ns[2][l]);
      g.front_face = out.front[l] != 0;
      g.valid = true;
    }
  }
  return left;
}

}  // namespace lancer
