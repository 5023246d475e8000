// Internal types of the kd-tree build: triangle references, sweep events, split choices.
#pragma once

#include <cstdint>
#include <new>
#include <utility>
#include <vector>

#include "accel/kd_build.h"
#include "simd/big_block_allocator.h"

namespace lancer::kd {

// A triangle as seen by one node: its index and the bounds of the triangle clipped to the
// node's cell (conservative: rounded outward, then clamped to the cell).
struct Ref {
  std::uint32_t tri;
  Bounds3 box;
};

// Wald & Havran's events. At equal positions the order is end, planar, start, so the sweep
// sees triangles that end on a plane before those that start on it.
enum EventType : std::uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// `key` = type << 30 | index of the Ref in the node's ref list. Comparing (pos, key)
// orders by position, then type, then ref index: a strict total order, so sorting and
// merging give one result whatever the algorithm or thread count.
struct Event {
  float pos;
  std::uint32_t key;

  EventType type() const { return static_cast<EventType>(key >> 30); }
  std::uint32_t ref() const { return key & ((1u << 30) - 1); }
  static Event make(float pos, EventType type, std::uint32_t ref) { return {pos, (std::uint32_t(type) << 30) | ref}; }
  bool operator<(const Event& o) const { return pos < o.pos || (pos == o.pos && key < o.key); }
};

// The build's big lists (simd/big_block_allocator.h: big blocks go back to the system
// when freed; resize() leaves new elements uninitialised, as lists are sized to a bound
// and written once).
using EventVector = BigBlockVector<Event>;
using RefVector = BigBlockVector<Ref>;

// One sorted event list per axis.
struct EventLists {
  EventVector axis[3];
  bool empty() const { return axis[0].empty() && axis[1].empty() && axis[2].empty(); }
};

// Everything needed to build one node. Refs are in ascending triangle index.
struct NodeInput {
  RefVector refs;
  EventLists events;  // empty for the Middle and Median strategies
  Bounds3 cell;
  int depth = 0;
  std::size_t budget = 0;  // the most references this subtree's leaves may hold
};

// Side flags of one parent ref after classification and clipping.
enum SideFlags : std::uint8_t { kInLeft = 1, kInRight = 2, kReclipped = 4 };

// Working memory of the build, reused from node to node so that the sequential part of
// the build does not allocate for every node: the temporaries of partition_node(), and
// the vectors of finished nodes, handed on to new ones (their capacity is kept). One
// scratch belongs to one sequential builder; it is never shared between threads.
struct BuildScratch {
  std::vector<std::uint8_t> side;
  std::vector<std::uint32_t> straddling, remap_left, remap_right, reclipped_left, reclipped_right;
  std::vector<Bounds3> clip_left, clip_right;  // per straddling ref
  std::vector<Bounds3> reclipped_left_box, reclipped_right_box;  // per reclipped_left / _right entry
  EventVector fresh[3];  // regenerated events of reclipped refs (left, right, sort buffer), one axis at a time

  RefVector take_refs() { return take(spare_refs_); }
  EventVector take_events() { return take(spare_events_); }
  // Keeps the node's vectors for reuse (up to a bound) and leaves `in` empty.
  void recycle(NodeInput& in) {
    give(spare_refs_, in.refs);
    for (EventVector& e : in.events.axis) give(spare_events_, e);
  }

 private:
  static constexpr std::size_t kMaxSpares = 64;
  template <typename V>
  static V take(std::vector<V>& spares) {
    if (spares.empty()) return V();
    V v = std::move(spares.back());
    spares.pop_back();
    return v;
  }
  template <typename V>
  static void give(std::vector<V>& spares, V& v) {
    v.clear();
    if (v.capacity() != 0 && spares.size() < kMaxSpares) spares.push_back(std::move(v));
    v = V();
  }
  std::vector<RefVector> spare_refs_;
  std::vector<EventVector> spare_events_;
};

// Which side of the plane triangles lying in it go to.
enum class PlanarSide : std::uint8_t { Left, Right };

struct SplitChoice {
  bool found = false;
  int axis = 0;
  float pos = 0.0f;
  PlanarSide planar = PlanarSide::Left;
  double cost = 0.0;
};

// The SAH cost model (MacDonald & Booth 1990 with Wald & Havran's empty-space bonus).
struct CostModel {
  double traversal;
  double intersection;
  double empty_factor;
};

// Surface area in double: float extents up to 1e38 and down to 1e-38 neither overflow
// nor underflow when multiplied.
inline double surface_area(const Bounds3& b) {
  const double dx = double(b.hi.x) - b.lo.x, dy = double(b.hi.y) - b.lo.y, dz = double(b.hi.z) - b.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

// Cost of splitting `cell` at `pos` on `axis` with nl and nr triangles on the two sides.
// `area` is surface_area(cell) > 0.
inline double split_cost(const CostModel& m, const Bounds3& cell, double area, int axis, float pos,
                         std::size_t nl, std::size_t nr) {
  Bounds3 left = cell, right = cell;
  left.hi[axis] = pos;
  right.lo[axis] = pos;
  const double pl = surface_area(left) / area, pr = surface_area(right) / area;
  double cost = m.traversal + m.intersection * (pl * double(nl) + pr * double(nr));
  if (nl == 0 || nr == 0) cost *= m.empty_factor;
  return cost;
}

}  // namespace lancer::kd
