#include "accel/kd_build_events.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_invoke.h>

#include "accel/kd_build_sort.h"

namespace lancer::kd {

void append_events(const Bounds3& box, std::uint32_t index, EventLists& out) {
  for (int a = 0; a < 3; ++a) {
    if (box.lo[a] == box.hi[a]) {
      out.axis[a].push_back(Event::make(box.lo[a], kPlanar, index));
    } else {
      out.axis[a].push_back(Event::make(box.lo[a], kStart, index));
      out.axis[a].push_back(Event::make(box.hi[a], kEnd, index));
    }
  }
}

EventLists make_sorted_events(const std::vector<Ref>& refs, bool parallel) {
  EventLists ev;
  for (int a = 0; a < 3; ++a) ev.axis[a].reserve(2 * refs.size());
  for (std::size_t i = 0; i < refs.size(); ++i) append_events(refs[i].box, static_cast<std::uint32_t>(i), ev);
  // Each list is built in ascending ref order, so the stable sort by (pos, type) gives the
  // (pos, type, ref) order of Event::operator<.
  auto sort_axis = [&ev](int a) {
    EventVector buffer;
    radix_sort_events(ev.axis[a], buffer);
  };
  if (parallel) {
    tbb::parallel_invoke([&] { sort_axis(0); }, [&] { sort_axis(1); }, [&] { sort_axis(2); });
  } else {
    for (int a = 0; a < 3; ++a) sort_axis(a);
  }
  return ev;
}

namespace {

// Surface area of the cell with its extent on `Axis` replaced by `extent`: the same
// operations in the same order as surface_area(), so the costs are bit-identical to
// split_cost() (kd_build_types.h), only without copying boxes.
template <int Axis>
inline double area_with_extent(const double cell_extent[3], double extent) {
  double d[3] = {cell_extent[0], cell_extent[1], cell_extent[2]};
  d[Axis] = extent;
  return 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

inline double sah_cost(const CostModel& m, double pl, double pr, std::size_t nl, std::size_t nr) {
  double c = m.traversal + m.intersection * (pl * double(nl) + pr * double(nr));
  if (nl == 0 || nr == 0) c *= m.empty_factor;
  return c;
}

// One axis of the sweep (Wald & Havran, Algorithm 4). At each distinct position p the
// counts are: nl = refs entirely or partly left of p, np = refs lying in p, nr = refs
// right of p or straddling it. Returns the first plane of least cost on this axis when
// that cost is below `bound` (the best of the axes already swept; infinity if none);
// otherwise what it returns is not below `bound` and loses to the earlier axis anyway.
//
// The costs are exactly those of split_cost(). To spare two divisions per position, a
// position is first priced with the reciprocal of the area, which differs from the exact
// cost by a few units in the 16th digit; only positions whose estimate comes within
// 1e-12 (relative) of the best so far are priced exactly, so the result is the same.
template <int Axis>
SplitChoice sweep_axis(const EventVector& ev, std::size_t n, const Bounds3& cell, double area,
                       const CostModel& model, double bound) {
  constexpr double kSlack = 1.0 + 1e-12;
  SplitChoice best;
  best.cost = std::numeric_limits<double>::infinity();
  double threshold = bound * kSlack;
  const double inv_area = 1.0 / area;
  const double extent[3] = {double(cell.hi.x) - cell.lo.x, double(cell.hi.y) - cell.lo.y,
                            double(cell.hi.z) - cell.lo.z};
  const float lo = cell.lo[Axis], hi = cell.hi[Axis];
  std::size_t nl = 0, nr = n;
  const Event* e = ev.data();
  const Event* const end = e + ev.size();
  while (e != end) {
    const float p = e->pos;
    std::size_t ends = 0, planars = 0, starts = 0;
    while (e != end && e->pos == p && e->type() == kEnd) ++ends, ++e;
    while (e != end && e->pos == p && e->type() == kPlanar) ++planars, ++e;
    while (e != end && e->pos == p && e->type() == kStart) ++starts, ++e;
    nr -= planars + ends;
    if (lo < p && p < hi) {
      const double area_l = area_with_extent<Axis>(extent, double(p) - lo);
      const double area_r = area_with_extent<Axis>(extent, double(hi) - p);
      double estimate = sah_cost(model, area_l * inv_area, area_r * inv_area, nl + planars, nr);
      if (planars != 0)
        estimate = std::min(estimate, sah_cost(model, area_l * inv_area, area_r * inv_area, nl, nr + planars));
      if (!(estimate > threshold)) {
        const double pl = area_l / area, pr = area_r / area;
        const double cost_left = sah_cost(model, pl, pr, nl + planars, nr);
        if (cost_left < best.cost) best = {true, Axis, p, PlanarSide::Left, cost_left};
        // Without planar triangles the right-side cost is the same number: skip it.
        if (planars != 0) {
          const double cost_right = sah_cost(model, pl, pr, nl, nr + planars);
          if (cost_right < best.cost) best = {true, Axis, p, PlanarSide::Right, cost_right};
        }
        threshold = std::min(best.cost, bound) * kSlack;
      }
    }
    nl += starts + planars;
  }
  return best;
}

SplitChoice sweep_axis(const EventVector& ev, int axis, std::size_t n, const Bounds3& cell, double area,
                       const CostModel& model, double bound) {
  switch (axis) {
    case 0: return sweep_axis<0>(ev, n, cell, area, model, bound);
    case 1: return sweep_axis<1>(ev, n, cell, area, model, bound);
    default: return sweep_axis<2>(ev, n, cell, area, model, bound);
  }
}

// The events of the reclipped refs of one child on `axis`, sorted, into `out`.
// `reclipped` is ascending, so the radix sort (for long lists) gives operator<'s order.
void regenerate_events(const std::vector<Ref>& refs, const std::vector<std::uint32_t>& reclipped, int axis,
                       EventVector& out, EventVector& buffer) {
  out.clear();
  for (std::uint32_t r : reclipped) {
    const Bounds3& b = refs[r].box;
    if (b.lo[axis] == b.hi[axis]) {
      out.push_back(Event::make(b.lo[axis], kPlanar, r));
    } else {
      out.push_back(Event::make(b.lo[axis], kStart, r));
      out.push_back(Event::make(b.hi[axis], kEnd, r));
    }
  }
  if (out.size() >= kRadixSortMin) {
    radix_sort_events(out, buffer);
  } else {
    std::sort(out.begin(), out.end());
  }
}

// Appends `e` to the list at `out`, after the regenerated events that precede it. All
// events of a list are distinct (they differ in ref or type), so the merge is unique.
inline void merge_one(const Event& e, const Event*& fresh, const Event* fresh_end, Event*& out) {
  while (fresh != fresh_end && *fresh < e) *out++ = *fresh++;
  *out++ = e;
}

}  // namespace

SplitChoice find_sah_split(const EventLists& events, std::size_t n, const Bounds3& cell, const CostModel& model,
                           bool parallel) {
  const double area = surface_area(cell);
  SplitChoice per_axis[3];
  constexpr double kNoBound = std::numeric_limits<double>::infinity();
  auto sweep = [&](int a, double bound) {
    if (cell.lo[a] < cell.hi[a]) per_axis[a] = sweep_axis(events.axis[a], a, n, cell, area, model, bound);
  };
  if (parallel) {
    tbb::parallel_invoke([&] { sweep(0, kNoBound); }, [&] { sweep(1, kNoBound); }, [&] { sweep(2, kNoBound); });
  } else {
    // Later axes only look for planes cheaper than the best found so far (same result).
    double bound = kNoBound;
    for (int a = 0; a < 3; ++a) {
      sweep(a, bound);
      if (per_axis[a].found) bound = std::min(bound, per_axis[a].cost);
    }
  }
  SplitChoice best;
  for (int a = 0; a < 3; ++a)
    if (per_axis[a].found && (!best.found || per_axis[a].cost < best.cost)) best = per_axis[a];
  return best;
}

void splice_events(const EventLists& parent, const std::vector<Ref>& left_refs, const std::vector<Ref>& right_refs,
                   BuildScratch& scratch, EventLists& left, EventLists& right, bool parallel) {
  const std::uint8_t* side = scratch.side.data();
  const std::uint32_t* remap_left = scratch.remap_left.data();
  const std::uint32_t* remap_right = scratch.remap_right.data();
  constexpr std::uint32_t kTypeBits = ~((1u << 30) - 1);
  auto splice_axis = [&](int a, EventVector& fresh_l, EventVector& fresh_r, EventVector& buffer) {
    regenerate_events(left_refs, scratch.reclipped_left, a, fresh_l, buffer);
    regenerate_events(right_refs, scratch.reclipped_right, a, fresh_r, buffer);
    // Every child ref has at most two events per axis: the bound on the lists' sizes.
    EventVector& out_l = left.axis[a];
    EventVector& out_r = right.axis[a];
    out_l.resize(2 * left_refs.size());
    out_r.resize(2 * right_refs.size());
    Event* ol = out_l.data();
    Event* orr = out_r.data();
    const Event* fl = fresh_l.data();
    const Event* fr = fresh_r.data();
    const Event* const fl_end = fl + fresh_l.size();
    const Event* const fr_end = fr + fresh_r.size();
    for (const Event& e : parent.axis[a]) {
      const std::uint32_t r = e.ref();
      const std::uint8_t s = side[r];
      if (s & kReclipped) continue;  // its new events are in fresh_l / fresh_r
      // A ref that was not reclipped lies on exactly one side.
      if (s & kInLeft) {
        merge_one(Event{e.pos, (e.key & kTypeBits) | remap_left[r]}, fl, fl_end, ol);
      } else {
        merge_one(Event{e.pos, (e.key & kTypeBits) | remap_right[r]}, fr, fr_end, orr);
      }
    }
    ol = std::copy(fl, fl_end, ol);
    orr = std::copy(fr, fr_end, orr);
    out_l.resize(static_cast<std::size_t>(ol - out_l.data()));
    out_r.resize(static_cast<std::size_t>(orr - out_r.data()));
  };
  if (parallel) {
    EventVector fresh[3][3];
    tbb::parallel_invoke([&] { splice_axis(0, fresh[0][0], fresh[0][1], fresh[0][2]); },
                         [&] { splice_axis(1, fresh[1][0], fresh[1][1], fresh[1][2]); },
                         [&] { splice_axis(2, fresh[2][0], fresh[2][1], fresh[2][2]); });
  } else {
    for (int a = 0; a < 3; ++a) splice_axis(a, scratch.fresh[0], scratch.fresh[1], scratch.fresh[2]);
  }
}

}  // namespace lancer::kd
