#include "accel/ray_offset_batch.h"


namespace lancer {

// The per-ISA solvers (ray_offset_batch_<isa>.cpp); nothing here is built with ISA flags.
#if defined(__x86_64__) || defined(_M_X64)
namespace sse4 {
std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]);
}
namespace avx2 {
std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]);
}
namespace avx512 {
std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]);
}
#endif

namespace ray_offset_batch {
namespace {

// The solver of one ISA; null for scalar (every ray goes to SurfaceOffset itself).
SolveLanesFn solver_for(Isa isa) {
#if defined(__x86_64__) || defined(_M_X64)
  return isa_version<SolveLanesFn>(isa, "solve_origins", &sse4::solve_origin_lanes, &avx2::solve_origin_lanes,
                                   &avx512::solve_origin_lanes);
#else
  return isa_version<SolveLanesFn>(isa, "solve_origins", nullptr, nullptr, nullptr);
#endif
}

// The widest solver's vector, in lanes: the count is padded to a multiple of it.
constexpr int kPadLanes = 8;

void copy_lane(Lanes& lanes, int from, int to) {
  for (auto& row : lanes.tri) row[to] = row[from];
  for (int k = 0; k < 3; ++k) {
    lanes.p[k][to] = lanes.p[k][from];
    lanes.n[k][to] = lanes.n[k][from];
    lanes.target[k][to] = lanes.target[k][from];
  }
  lanes.towards[to] = lanes.towards[from];
}

}  // namespace
}  // namespace ray_offset_batch

bool SurfaceOffset::fill_lane(const glm::vec3& target, bool towards, ray_offset_batch::Lanes& lanes, int i) const {
  // The batch solvers know no instance: a triangle drawn through one is solved in solve().
  if (inst_) return false;
  for (int v = 0; v < 3; ++v) {
    lanes.tri[3 * v][i] = tri_[static_cast<std::size_t>(v)].x;
    lanes.tri[3 * v + 1][i] = tri_[static_cast<std::size_t>(v)].y;
    lanes.tri[3 * v + 2][i] = tri_[static_cast<std::size_t>(v)].z;
  }
  const float p[3] = {p_.x, p_.y, p_.z}, n[3] = {n_.x, n_.y, n_.z}, t[3] = {target.x, target.y, target.z};
  for (int k = 0; k < 3; ++k) {
    lanes.p[k][i] = p[k];
    lanes.n[k][i] = n[k];
    lanes.target[k][i] = t[k];
  }
  lanes.towards[i] = towards ? 1 : 0;
  return true;
}

int solve_origins(const OriginRequest* requests, glm::vec3* origins, int count) {
  // best_supported_isa() probes the CPU and builds a list: once, not per bounce.
  static const Isa best = best_supported_isa();
  return solve_origins(requests, origins, count, best);
}

int solve_origins(const OriginRequest* requests, glm::vec3* origins, int count, Isa isa) {
  using namespace ray_offset_batch;
  const SolveLanesFn solve = solver_for(isa);
  const auto scalar = [&](int i) {
    const OriginRequest& r = requests[i];
    origins[i] = r.towards ? r.leave->origin_towards(r.target) : r.leave->origin(r.target);
  };
  if (!solve) {
    for (int i = 0; i < count; ++i) scalar(i);
    return count;
  }
  int scalar_lanes = 0;
  alignas(64) Lanes lanes;
  alignas(64) float out[3][kMaxLanes];
  int lane_request[kMaxLanes];
  for (int first = 0; first < count;) {
    // Fill up to kMaxLanes lanes; rays through an instance are solved at once.
    int n = 0;
    for (; first < count && n < kMaxLanes; ++first) {
      const OriginRequest& r = requests[first];
      if (r.leave->fill_lane(r.target, r.towards, lanes, n)) {
        lane_request[n++] = first;
      } else {
        scalar(first);
        ++scalar_lanes;
      }
    }
    if (n == 0) continue;
    // The last vector's unused lanes repeat lane 0, so no solver reads unset memory.
    for (int l = n; l % kPadLanes != 0; ++l) copy_lane(lanes, 0, l);
    const std::uint64_t done = solve(lanes, n, out);
    for (int l = 0; l < n; ++l) {
      const int i = lane_request[l];
      if ((done >> l) & 1u) {
        origins[i] = glm::vec3(out[0][l], out[1][l], out[2][l]);
      } else {
        scalar(i);
        ++scalar_lanes;
      }
    }
  }
  return scalar_lanes;
}

}  // namespace lancer
