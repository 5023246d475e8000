// How much of a render is ray traversal: the render's own tracer calls, recorded, then
// replayed alone against the same accelerator and timed. A timer around every call would
// cost about as much as the call itself (tens of nanoseconds on a small scene), so the
// render is timed without any instrumentation and the calls are timed apart from it.
//
// The replay traces exactly the rays the render traced, with the same calls (closest hit,
// any hit, packets), on one thread: all packets, then all closest-hit rays, then all
// any-hit rays, each in the order the render traced them. It runs with warmer caches than
// the render did (no shading in between), so the share it gives errs low.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "accel/accelerator.h"

namespace lancer::bench {

// One recorded call: a closest-hit or any-hit ray, or the first ray of a closest-hit or
// any-hit packet of `count` (its other rays follow as records of kind PacketRay).
struct RecordedCall {
  enum class Kind : std::uint8_t { Closest, Any, Packet, AnyPacket, PacketRay };
  Ray ray;
  Kind kind = Kind::Closest;
  int count = 1;
};

// Forwards every call to `inner` and appends it to the calling thread's log; stops
// recording (and says so) after `max_calls` calls in all, so memory stays bounded.
class RecordingAccelerator final : public Accelerator {
 public:
  RecordingAccelerator(const Accelerator& inner, std::size_t max_calls) : inner_(inner), max_calls_(max_calls) {}

  Hit intersect(const Ray& ray) const override;
  bool occluded(const Ray& ray) const override;
  void intersect_packet(const Ray* rays, Hit* hits, int count) const override;
  void occluded_packet(const Ray* rays, bool* occluded, int count) const override;
  std::size_t memory_bytes() const override { return inner_.memory_bytes(); }
  std::string_view name() const override { return inner_.name(); }

  // Every thread's log, one after the other.
  std::vector<RecordedCall> calls() const;
  bool truncated() const { return truncated_; }

 private:
  bool room(std::size_t n) const;
  void record_packet(const Ray* rays, int count, RecordedCall::Kind kind) const;

  const Accelerator& inner_;
  std::size_t max_calls_;
  mutable tbb::enumerable_thread_specific<std::vector<RecordedCall>> logs_;
  mutable std::atomic<std::size_t> recorded_{0};
  mutable std::atomic<bool> truncated_{false};
};

struct ReplayTime {
  double closest_s = 0.0, any_s = 0.0, packet_s = 0.0, any_packet_s = 0.0;  // one thread's seconds per kind
  std::uint64_t closest = 0, any = 0, packet_rays = 0, any_packet_rays = 0;
  std::uint64_t checksum = 0;  // of the answers, so that no call can be optimised away
  // The any-hit packets' rays traced again one by one (not part of the total): what the
  // packets save on the render's own coherent shadow batches.
  double any_packet_as_single_s = 0.0;
  double total_s() const { return closest_s + any_s + packet_s + any_packet_s; }
};

// Traces `calls` against `accel` on the calling thread; the fastest of `reps` replays (the
// least disturbed by whatever else runs on the machine).
ReplayTime replay(const Accelerator& accel, const std::vector<RecordedCall>& calls, int reps);

}  // namespace lancer::bench
