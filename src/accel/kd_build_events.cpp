#include "accel/kd_build_events.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_invoke.h>

#include "accel/kd_build_sort.h"

namespace lancer::kd {

void append_events(const Bounds3& box, int axis, std::uint32_t index, EventVector& out) {
  if (box.lo[axis] == box.hi[axis]) {
    out.push_back(Event::make(box.lo[axis], kPlanar, index));
  } else {
    out.push_back(Event::make(box.lo[axis], kStart, index));
    out.push_back(Event::make(box.hi[axis], kEnd, index));
  }
}

void make_sorted_axis_events(const RefVector& refs, int a, EventVector& list, EventVector& buffer) {
  list.resize(2 * refs.size());  // the most there can be; uninitialised (EventVector)
  Event* out = list.data();
  for (std::size_t i = 0; i < refs.size(); ++i) {
    const float lo = refs[i].box.lo[a], hi = refs[i].box.hi[a];
    const auto index = static_cast<std::uint32_t>(i);
    // Written branch-free: a planar ref writes one event, a start and an end otherwise.
    const bool planar = lo == hi;
    out[0] = Event::make(lo, planar ? kPlanar : kStart, index);
    out[1] = Event::make(hi, kEnd, index);
    out += planar ? 1 : 2;
  }
  list.resize(static_cast<std::size_t>(out - list.data()));
  // Built in ascending ref order, so the stable sort by (pos, type) gives the
  // (pos, type, ref) order of Event::operator<.
  if (list.size() >= kRadixSortMin) {
    radix_sort_events(list, buffer);
  } else {
    std::sort(list.begin(), list.end());
  }
}

EventLists make_sorted_events(const RefVector& refs) {
  EventLists ev;
  EventVector buffer;
  for (int a = 0; a < 3; ++a) make_sorted_axis_events(refs, a, ev.axis[a], buffer);
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

// The events of the reclipped refs of one child on `axis` (child ref indices `reclipped`,
// ascending, with their new bounds `boxes`), sorted, into `out`. The indices ascend, so
// the stable radix sort (for long lists) gives operator<'s order.
void regenerate_events(const std::vector<std::uint32_t>& reclipped, const std::vector<Bounds3>& boxes, int axis,
                       EventVector& out, EventVector& buffer) {
  out.clear();
  for (std::size_t j = 0; j < reclipped.size(); ++j) append_events(boxes[j], axis, reclipped[j], out);
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

// The cheapest of the axes' answers; a tie goes to the lower axis.
SplitChoice cheapest(const SplitChoice (&per_axis)[3]) {
  SplitChoice best;
  for (int a = 0; a < 3; ++a)
    if (per_axis[a].found && (!best.found || per_axis[a].cost < best.cost)) best = per_axis[a];
  return best;
}

// The axes in turn, each looking only for planes cheaper than the best of those before
// (the same result as sweeping each without a bound). events_of(a) gives axis a's sorted
// events; it is called once per axis whose cell extent is not zero.
template <typename EventsOf>
SplitChoice sweep_axes_in_turn(std::size_t n, const Bounds3& cell, const CostModel& model, EventsOf events_of) {
  const double area = surface_area(cell);
  SplitChoice per_axis[3];
  double bound = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (!(cell.lo[a] < cell.hi[a])) continue;
    per_axis[a] = sweep_axis(events_of(a), a, n, cell, area, model, bound);
    if (per_axis[a].found) bound = std::min(bound, per_axis[a].cost);
  }
  return cheapest(per_axis);
}

}  // namespace

SplitChoice find_sah_split(const EventLists& events, std::size_t n, const Bounds3& cell, const CostModel& model,
                           bool parallel) {
  if (!parallel)
    return sweep_axes_in_turn(n, cell, model, [&](int a) -> const EventVector& { return events.axis[a]; });
  const double area = surface_area(cell);
  SplitChoice per_axis[3];
  constexpr double kNoBound = std::numeric_limits<double>::infinity();
  auto sweep = [&](int a) {
    if (cell.lo[a] < cell.hi[a]) per_axis[a] = sweep_axis(events.axis[a], a, n, cell, area, model, kNoBound);
  };
  tbb::parallel_invoke([&] { sweep(0); }, [&] { sweep(1); }, [&] { sweep(2); });
  return cheapest(per_axis);
}

SplitChoice find_sah_split_axis_by_axis(const RefVector& refs, const Bounds3& cell, const CostModel& model) {
  EventVector list, buffer;
  return sweep_axes_in_turn(refs.size(), cell, model, [&](int a) -> const EventVector& {
    make_sorted_axis_events(refs, a, list, buffer);
    return list;
  });
}

void splice_events(EventLists& parent, std::size_t left_refs, std::size_t right_refs, BuildScratch& scratch,
                   EventLists& left, EventLists& right, SpliceTo to) {
  const bool both = to == SpliceTo::Both;
  const std::uint8_t* side = scratch.side.data();
  const std::uint32_t* remap_left = scratch.remap_left.data();
  const std::uint32_t* remap_right = scratch.remap_right.data();
  constexpr std::uint32_t kTypeBits = ~((1u << 30) - 1);
  EventVector& fresh_l = scratch.fresh[0];
  EventVector& fresh_r = scratch.fresh[1];
  EventVector& buffer = scratch.fresh[2];
  for (int a = 0; a < 3; ++a) {
    regenerate_events(scratch.reclipped_left, scratch.reclipped_left_box, a, fresh_l, buffer);
    if (both) regenerate_events(scratch.reclipped_right, scratch.reclipped_right_box, a, fresh_r, buffer);
    // Every child ref has at most two events per axis: the bound on the lists' sizes.
    EventVector& out_l = left.axis[a];
    EventVector& out_r = right.axis[a];
    out_l.resize(2 * left_refs);
    if (both) out_r.resize(2 * right_refs);
    Event* ol = out_l.data();
    Event* orr = out_r.data();
    const Event* fl = fresh_l.data();
    const Event* fr = fresh_r.data();
    const Event* const fl_end = fl + fresh_l.size();
    const Event* const fr_end = both ? fr + fresh_r.size() : fr;
    for (const Event& e : parent.axis[a]) {
      const std::uint32_t r = e.ref();
      const std::uint8_t s = side[r];
      if (s & kReclipped) continue;  // its new events are in fresh_l / fresh_r
      // A ref that was not reclipped lies on exactly one side.
      if (s & kInLeft) {
        merge_one(Event{e.pos, (e.key & kTypeBits) | remap_left[r]}, fl, fl_end, ol);
      } else if (both) {
        merge_one(Event{e.pos, (e.key & kTypeBits) | remap_right[r]}, fr, fr_end, orr);
      }
    }
    out_l.resize(static_cast<std::size_t>(std::copy(fl, fl_end, ol) - out_l.data()));
    if (both) out_r.resize(static_cast<std::size_t>(std::copy(fr, fr_end, orr) - out_r.data()));
    if (!both) EventVector().swap(parent.axis[a]);
  }
}

}  // namespace lancer::kd
