// Lancer's rays in Embree 3's ray structures, and Embree's config name for an ISA: what
// every Embree baseline of the benchmarks (lancer-bench, lancer-motion-bench) needs alike.
// Include only where Embree is found.
#pragma once

#include <embree3/rtcore.h>

#include <array>
#include <cstddef>

#include "accel/ray.h"
#include "simd/isa.h"

namespace lancer::bench {

// Embree's config name ("max_isa=...") for a Lancer ISA; scalar has no Embree counterpart.
inline const char* embree_config_isa(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return "sse2";
    case Isa::Sse4: return "sse4.2";
    case Isa::Avx2: return "avx2";
    case Isa::Avx512: return "avx512";
  }
  return "sse2";
}

// Every lane on, or off from `count` on; rtcIntersect16 wants the mask aligned like the packet.
struct alignas(64) ValidMask16 {
  std::array<int, 16> lanes{};
  explicit ValidMask16(std::size_t count) {
    for (std::size_t i = 0; i < lanes.size(); ++i) lanes[i] = i < count ? -1 : 0;
  }
};

inline void set_ray(RTCRay& out, const Ray& r) {
  out.org_x = r.org.x;
  out.org_y = r.org.y;
  out.org_z = r.org.z;
  out.tnear = r.tnear;
  out.dir_x = r.dir.x;
  out.dir_y = r.dir.y;
  out.dir_z = r.dir.z;
  out.time = r.time;
  out.tfar = r.tfar;
  out.mask = 0xFFFFFFFFu;
  out.id = 0;
  out.flags = 0;
}

inline void set_ray16(RTCRay16& out, std::size_t i, const Ray& r) {
  out.org_x[i] = r.org.x;
  out.org_y[i] = r.org.y;
  out.org_z[i] = r.org.z;
  out.tnear[i] = r.tnear;
  out.dir_x[i] = r.dir.x;
  out.dir_y[i] = r.dir.y;
  out.dir_z[i] = r.dir.z;
  out.time[i] = r.time;
  out.tfar[i] = r.tfar;
  out.mask[i] = 0xFFFFFFFFu;
  out.id[i] = static_cast<unsigned>(i);
  out.flags[i] = 0;
}

}  // namespace lancer::bench
