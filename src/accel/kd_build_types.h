// Internal types of the kd-tree build: triangle references, sweep events, split choices.
#pragma once

#include <cstdint>
#include <vector>

#include "accel/kd_build.h"

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

// One sorted event list per axis.
struct EventLists {
  std::vector<Event> axis[3];
  bool empty() const { return axis[0].empty() && axis[1].empty() && axis[2].empty(); }
};

// Everything needed to build one node. Refs are in ascending triangle index.
struct NodeInput {
  std::vector<Ref> refs;
  EventLists events;  // empty for the Middle and Median strategies
  Bounds3 cell;
  int depth = 0;
  std::size_t budget = 0;  // the most references this subtree's leaves may hold
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
