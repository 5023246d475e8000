#include "accel/top_level_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace lancer {

namespace {

// One box edge on one axis. Within a run of equal positions the sweep counts by type, so
// the order inside the run does not matter (the first sort still fixes it, for determinism).
enum EventType : std::uint8_t { kEnd = 0, kFlat = 1, kStart = 2 };

struct Event {
  float pos;
  std::uint32_t box;
  std::uint8_t type;
};

using EventLists = std::array<std::vector<Event>, 3>;

struct Split {
  int axis = -1;
  float pos = 0.0f;
  double cost = 0.0;
  std::size_t left_count = 0, right_count = 0;
};

class Builder {
 public:
  Builder(const std::vector<Bounds3>& boxes, const TopLevelBuildOptions& options, int depth_bound)
      : options_(options), depth_bound_(depth_bound), lo_(boxes.size()), hi_(boxes.size()), side_(boxes.size()) {}

  void build(std::uint32_t node, const Bounds3& cell, EventLists events, std::size_t count, int depth) {
    const Split split = depth < depth_bound_ && count > 1 ? best_split(cell, events, count) : Split{};
    if (split.axis < 0) return make_leaf(node, events[0]);

    EventLists left, right;
    classify_and_split(split, events, left, right);
    for (auto& list : events) std::vector<Event>().swap(list);  // free the parent's lists before recursing
    Bounds3 left_cell = cell, right_cell = cell;
    left_cell.hi[split.axis] = split.pos;
    right_cell.lo[split.axis] = split.pos;

    const auto left_child = static_cast<std::uint32_t>(nodes.size());
    if (left_child + 2 > kKdMaxOffset) throw std::length_error("top-level tree: too many nodes");
    nodes.resize(nodes.size() + 2);
    nodes[node] = KdNode::inner(split.axis, split.pos, left_child);
    build(left_child, left_cell, std::move(left), split.left_count, depth + 1);
    build(left_child + 1, right_cell, std::move(right), split.right_count, depth + 1);
  }

  std::vector<KdNode> nodes;
  std::vector<std::uint32_t> items;

 private:
  // Each box has exactly one start or flat event per axis.
  void make_leaf(std::uint32_t node, const std::vector<Event>& list) {
    const std::size_t first = items.size();
    for (const Event& e : list)
      if (e.type != kEnd) items.push_back(e.box);
    if (items.size() > kKdMaxOffset) throw std::length_error("top-level tree: too many leaf references");
    std::sort(items.begin() + static_cast<std::ptrdiff_t>(first), items.end());
    nodes[node] = KdNode::leaf(static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(items.size() - first));
  }

  // SAH over the box edges strictly inside the cell; no split when none beats a leaf.
  // A cell flat on some axis (flat scenes) has zero area: its parts are then measured by
  // the sum of their extents, so flat and line-like sets of boxes still split.
  Split best_split(const Bounds3& cell, const EventLists& events, std::size_t count) const {
    const glm::dvec3 ext(cell.hi - cell.lo);
    const bool by_area = area(ext) > 0.0;
    const double whole = by_area ? area(ext) : ext.x + ext.y + ext.z;
    if (!(whole > 0.0) || !std::isfinite(whole)) return {};
    const double n = static_cast<double>(count);
    Split best;
    best.cost = options_.visit_cost * n;  // the leaf's cost
    for (int axis = 0; axis < 3; ++axis) {
      const std::vector<Event>& list = events[axis];
      std::size_t starts_before = 0, ends_upto = 0;
      for (std::size_t i = 0; i < list.size();) {
        const float p = list[i].pos;
        std::size_t starts = 0, ends = 0, flats = 0;
        for (; i < list.size() && list[i].pos == p; ++i)
          (list[i].type == kStart ? starts : list[i].type == kEnd ? ends : flats) += 1;
        ends_upto += ends + flats;
        const std::size_t nl = starts_before + flats;  // boxes with lo < p, and flat ones at p
        const std::size_t nr = count - ends_upto;      // boxes with hi > p
        starts_before += starts + flats;
        if (!(p > cell.lo[axis] && p < cell.hi[axis]) || (nl == count && nr == count)) continue;
        glm::dvec3 el = ext, er = ext;
        el[axis] = double(p) - double(cell.lo[axis]);
        er[axis] = double(cell.hi[axis]) - double(p);
        const double pl = (by_area ? area(el) : el.x + el.y + el.z) / whole;
        const double pr = (by_area ? area(er) : er.x + er.y + er.z) / whole;
        double cost = options_.traversal_cost + options_.visit_cost * (pl * double(nl) + pr * double(nr));
        if (nl == 0 || nr == 0) cost *= options_.empty_space_factor;
        if (cost < best.cost) best = {axis, p, cost, nl, nr};
      }
    }
    return best;
  }

  static double area(const glm::dvec3& e) { return e.x * e.y + e.y * e.z + e.z * e.x; }

  // Splits every axis's sorted list into the children's, keeping the order. On the split
  // axis a straddling box's end moves onto the plane in the left list (after every other
  // left event, all at or below the plane) and its start onto the plane in the right list
  // (before every other right event), so both lists stay sorted.
  void classify_and_split(const Split& split, const EventLists& events, EventLists& left, EventLists& right) {
    const int a = split.axis;
    const float p = split.pos;
    for (const Event& e : events[a]) {
      if (e.type != kEnd) lo_[e.box] = e.pos;
      if (e.type != kStart) hi_[e.box] = e.pos;
    }
    for (const Event& e : events[a]) {
      if (e.type == kEnd) continue;
      const float lo = lo_[e.box], hi = hi_[e.box];
      const bool to_left = lo < p || (lo == p && hi == p), to_right = hi > p;
      side_[e.box] = static_cast<std::uint8_t>((to_left ? 1 : 0) | (to_right ? 2 : 0));
    }
    for (int k = 0; k < 3; ++k) {
      left[k].reserve(2 * split.left_count);
      right[k].reserve(2 * split.right_count);
    }
    for (const Event& e : events[a])  // the straddlers' starts, moved onto the plane, come first on the right
      if (e.type == kStart && (side_[e.box] & 2) && lo_[e.box] < p) right[a].push_back({p, e.box, kStart});
    for (int k = 0; k < 3; ++k) {
      for (const Event& e : events[k]) {
        const std::uint8_t s = side_[e.box];
        if ((s & 1) && !(k == a && e.type == kEnd && hi_[e.box] > p)) left[k].push_back(e);
        if ((s & 2) && !(k == a && e.type == kStart && lo_[e.box] < p)) right[k].push_back(e);
      }
    }
    for (const Event& e : events[a])  // and their ends come last on the left
      if (e.type == kEnd && (side_[e.box] & 1) && hi_[e.box] > p) left[a].push_back({p, e.box, kEnd});
  }

  TopLevelBuildOptions options_;
  int depth_bound_;
  std::vector<float> lo_, hi_;  // the current node's box extents on its split axis
  std::vector<std::uint8_t> side_;
};

int top_level_depth_bound(std::size_t n, int requested) {
  int bound = requested > 0 ? requested
                            : static_cast<int>(std::lround(8.0 + 1.3 * std::log2(static_cast<double>(n > 1 ? n : 1))));
  return std::min(bound, kTopLevelMaxDepth);
}

bool usable(const Bounds3& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !(b.lo[a] <= b.hi[a])) return false;
  return true;
}

}  // namespace

TopLevelTree::TopLevelTree(const std::vector<Bounds3>& boxes, const TopLevelBuildOptions& options) {
  if (boxes.size() > kKdMaxOffset) throw std::length_error("top-level tree: too many boxes");
  EventLists events;
  std::size_t count = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Bounds3& b = boxes[i];
    if (!usable(b)) continue;
    ++count;
    bounds_.extend(b);
    const auto id = static_cast<std::uint32_t>(i);
    for (int a = 0; a < 3; ++a) {
      if (b.lo[a] == b.hi[a]) {
        events[a].push_back({b.lo[a], id, kFlat});
      } else {
        events[a].push_back({b.lo[a], id, kStart});
        events[a].push_back({b.hi[a], id, kEnd});
      }
    }
  }
  for (auto& list : events)
    std::sort(list.begin(), list.end(), [](const Event& x, const Event& y) {
      if (x.pos != y.pos) return x.pos < y.pos;
      if (x.type != y.type) return x.type < y.type;
      return x.box < y.box;
    });
  depth_bound_ = top_level_depth_bound(count, options.max_depth);
  Builder builder(boxes, options, depth_bound_);
  builder.nodes.resize(1);
  builder.build(0, bounds_, std::move(events), count, 0);
  nodes_ = std::move(builder.nodes);
  items_ = std::move(builder.items);
  nodes_.shrink_to_fit();
  items_.shrink_to_fit();
}

}  // namespace lancer
