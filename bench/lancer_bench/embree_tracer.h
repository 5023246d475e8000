// Embree 3 as lancer-bench's baseline, behind an interface free of Embree's headers, so the
// program builds without Embree (embree_tracer_none.cpp: every call reports it missing).
//
// The scene is what a renderer would ask Embree for: one triangle mesh, high-quality BVH
// (RTC_BUILD_QUALITY_HIGH for scene and geometry), default scene flags, on a device whose
// ISA is capped at Lancer's (config max_isa; scalar has no Embree counterpart and gets
// SSE2). Rays go in and answers come out in Lancer's Ray/Hit layout, converted inside the
// timed calls, as Lancer's own calls take Ray and give Hit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "accel/ray.h"
#include "accel/triangle_soa.h"
#include "simd/isa.h"

namespace lancer::bench {

// The Embree calls lancer-bench may time. The packet calls take up to 16 rays (the rest
// of the packet masked off); "coherent" sets RTC_INTERSECT_CONTEXT_FLAG_COHERENT.
enum class EmbreeCall {
  Intersect1,
  Intersect16,
  Intersect16Coherent,
  Occluded1,
  Occluded16,
  Occluded16Coherent,
};

// "rtcIntersect16 (coherent)" and so on.
std::string_view embree_call_name(EmbreeCall call);
bool embree_call_is_occlusion(EmbreeCall call);

// True when this program was built with Embree (LANCER_HAVE_EMBREE).
bool embree_available();
// One line: version and the natively supported packet widths, or why Embree is missing.
std::string embree_description();
// The Embree config string's ISA for Lancer's `isa` ("sse2", "sse4.2", "avx2", "avx512").
std::string_view embree_isa_cap(Isa isa);

class EmbreeScene {
 public:
  // Builds the BVH of `tris` on a device capped at `isa` with `threads` build threads
  // (0: all). Times rtcCommitScene alone, and sums through the device's memory monitor
  // what Embree allocates during it and still holds afterwards (the BVH; the vertex and
  // index buffers are set up before and are not counted). Throws std::runtime_error with
  // Embree's message on any Embree error, or when Embree is not built in.
  EmbreeScene(const TriangleSoA& tris, Isa isa, int threads);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  double build_ms() const;
  std::int64_t memory_bytes() const;

  // Closest hits of rays[0..count) with an Intersect* call (count <= 64: one 8x8 tile;
  // 16-wide calls take the rays 16 at a time). Thread-safe.
  void intersect(EmbreeCall call, const Ray* rays, Hit* hits, std::size_t count) const;
  // occluded[i] = 1 when rays[i] is blocked, with an Occluded* call. Thread-safe.
  void occluded(EmbreeCall call, const Ray* rays, std::uint8_t* occluded, std::size_t count) const;
  // Throws std::runtime_error naming the first Embree error since the last check.
  void check_errors() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lancer::bench
