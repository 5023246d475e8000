#include "ray_recorder.h"

#include <algorithm>
#include <atomic>
#include <chrono>

namespace lancer::bench {

bool RecordingAccelerator::room(std::size_t n) const {
  if (recorded_.fetch_add(n, std::memory_order_relaxed) + n <= max_calls_) return true;
  truncated_.store(true, std::memory_order_relaxed);
  return false;
}

Hit RecordingAccelerator::intersect(const Ray& ray) const {
  if (room(1)) logs_.local().push_back({ray, RecordedCall::Kind::Closest, 1});
  return inner_.intersect(ray);
}

bool RecordingAccelerator::occluded(const Ray& ray) const {
  if (room(1)) logs_.local().push_back({ray, RecordedCall::Kind::Any, 1});
  return inner_.occluded(ray);
}

void RecordingAccelerator::record_packet(const Ray* rays, int count, RecordedCall::Kind kind) const {
  if (count > 0 && room(static_cast<std::size_t>(count))) {
    std::vector<RecordedCall>& log = logs_.local();
    log.push_back({rays[0], kind, count});
    for (int i = 1; i < count; ++i) log.push_back({rays[i], RecordedCall::Kind::PacketRay, 1});
  }
}

void RecordingAccelerator::intersect_packet(const Ray* rays, Hit* hits, int count) const {
  record_packet(rays, count, RecordedCall::Kind::Packet);
  inner_.intersect_packet(rays, hits, count);
}

void RecordingAccelerator::occluded_packet(const Ray* rays, bool* occluded, int count) const {
  record_packet(rays, count, RecordedCall::Kind::AnyPacket);
  inner_.occluded_packet(rays, occluded, count);
}

std::vector<RecordedCall> RecordingAccelerator::calls() const {
  std::vector<RecordedCall> all;
  for (const auto& log : logs_) all.insert(all.end(), log.begin(), log.end());
  return all;
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The calls split by kind, each kind in the order it was traced: the replay times one
// loop per kind, so the clock is read three times, not once per call.
struct SplitCalls {
  std::vector<Ray> closest, any, packet_rays, any_packet_rays;
  std::vector<int> packet_sizes, any_packet_sizes;
};

SplitCalls split(const std::vector<RecordedCall>& calls) {
  SplitCalls s;
  std::vector<Ray>* packet = &s.packet_rays;  // the packet the PacketRay records continue
  for (const RecordedCall& c : calls) {
    switch (c.kind) {
      case RecordedCall::Kind::Closest: s.closest.push_back(c.ray); break;
      case RecordedCall::Kind::Any: s.any.push_back(c.ray); break;
      case RecordedCall::Kind::Packet:
        s.packet_sizes.push_back(c.count);
        packet = &s.packet_rays;
        packet->push_back(c.ray);
        break;
      case RecordedCall::Kind::AnyPacket:
        s.any_packet_sizes.push_back(c.count);
        packet = &s.any_packet_rays;
        packet->push_back(c.ray);
        break;
      case RecordedCall::Kind::PacketRay: packet->push_back(c.ray); break;
    }
  }
  return s;
}

ReplayTime replay_once(const Accelerator& accel, const SplitCalls& calls) {
  ReplayTime t;
  std::uint64_t sink = 0;  // keeps the answers alive
  std::vector<Hit> hits(64);
  auto start = Clock::now();
  std::size_t first = 0;
  for (const int n : calls.packet_sizes) {
    if (hits.size() < static_cast<std::size_t>(n)) hits.resize(static_cast<std::size_t>(n));
    accel.intersect_packet(&calls.packet_rays[first], hits.data(), n);
    sink += hits[0].prim;
    first += static_cast<std::size_t>(n);
  }
  t.packet_s = seconds_since(start);
  start = Clock::now();
  bool blocked[64];
  first = 0;
  for (const int n : calls.any_packet_sizes) {
    for (int i = 0; i < n; i += 64) {
      const int m = std::min(64, n - i);
      accel.occluded_packet(&calls.any_packet_rays[first + static_cast<std::size_t>(i)], blocked, m);
      sink += blocked[0] ? 1 : 0;
    }
    first += static_cast<std::size_t>(n);
  }
  t.any_packet_s = seconds_since(start);
  start = Clock::now();
  for (const Ray& r : calls.any_packet_rays) sink += accel.occluded(r) ? 1 : 0;
  t.any_packet_as_single_s = seconds_since(start);
  start = Clock::now();
  for (const Ray& r : calls.closest) sink += accel.intersect(r).prim;
  t.closest_s = seconds_since(start);
  start = Clock::now();
  for (const Ray& r : calls.any) sink += accel.occluded(r) ? 1 : 0;
  t.any_s = seconds_since(start);
  t.packet_rays = calls.packet_rays.size();
  t.closest = calls.closest.size();
  t.any = calls.any.size();
  t.any_packet_rays = calls.any_packet_rays.size();
  t.checksum = sink;
  return t;
}

}  // namespace

ReplayTime replay(const Accelerator& accel, const std::vector<RecordedCall>& calls, int reps) {
  const SplitCalls split_calls = split(calls);
  ReplayTime best;
  for (int r = 0; r < std::max(1, reps); ++r) {
    const ReplayTime t = replay_once(accel, split_calls);
    if (r == 0 || t.total_s() < best.total_s()) best = t;
  }
  return best;
}

}  // namespace lancer::bench
