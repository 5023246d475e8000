#include "accel/kd_build_events.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_invoke.h>

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
  auto sort_axis = [&ev](int a) { std::sort(ev.axis[a].begin(), ev.axis[a].end()); };
  if (parallel) {
    tbb::parallel_invoke([&] { sort_axis(0); }, [&] { sort_axis(1); }, [&] { sort_axis(2); });
  } else {
    for (int a = 0; a < 3; ++a) sort_axis(a);
  }
  return ev;
}

namespace {

// One axis of the sweep (Wald & Havran, Algorithm 4). At each distinct position p the
// counts are: nl = refs entirely or partly left of p, np = refs lying in p, nr = refs
// right of p or straddling it.
SplitChoice sweep_axis(const std::vector<Event>& ev, int axis, std::size_t n, const Bounds3& cell, double area,
                       const CostModel& model) {
  SplitChoice best;
  best.cost = std::numeric_limits<double>::infinity();
  std::size_t nl = 0, nr = n;
  for (std::size_t i = 0; i < ev.size();) {
    const float p = ev[i].pos;
    std::size_t ends = 0, planars = 0, starts = 0;
    while (i < ev.size() && ev[i].pos == p && ev[i].type() == kEnd) ++ends, ++i;
    while (i < ev.size() && ev[i].pos == p && ev[i].type() == kPlanar) ++planars, ++i;
    while (i < ev.size() && ev[i].pos == p && ev[i].type() == kStart) ++starts, ++i;
    nr -= planars + ends;
    if (cell.lo[axis] < p && p < cell.hi[axis]) {
      const double cost_left = split_cost(model, cell, area, axis, p, nl + planars, nr);
      const double cost_right = split_cost(model, cell, area, axis, p, nl, nr + planars);
      if (cost_left < best.cost) best = {true, axis, p, PlanarSide::Left, cost_left};
      if (cost_right < best.cost) best = {true, axis, p, PlanarSide::Right, cost_right};
    }
    nl += starts + planars;
  }
  return best;
}

// Regenerated events of the reclipped refs of one child, sorted, merged into `spliced`.
void merge_new_events(const std::vector<Ref>& refs, const std::vector<std::uint32_t>& reclipped,
                      EventLists& spliced, int axis) {
  if (reclipped.empty()) return;
  std::vector<Event> fresh;
  fresh.reserve(2 * reclipped.size());
  for (std::uint32_t r : reclipped) {
    const Bounds3& b = refs[r].box;
    if (b.lo[axis] == b.hi[axis]) {
      fresh.push_back(Event::make(b.lo[axis], kPlanar, r));
    } else {
      fresh.push_back(Event::make(b.lo[axis], kStart, r));
      fresh.push_back(Event::make(b.hi[axis], kEnd, r));
    }
  }
  std::sort(fresh.begin(), fresh.end());
  std::vector<Event> merged(spliced.axis[axis].size() + fresh.size());
  std::merge(spliced.axis[axis].begin(), spliced.axis[axis].end(), fresh.begin(), fresh.end(), merged.begin());
  spliced.axis[axis].swap(merged);
}

}  // namespace

SplitChoice find_sah_split(const EventLists& events, std::size_t n, const Bounds3& cell, const CostModel& model,
                           bool parallel) {
  const double area = surface_area(cell);
  SplitChoice per_axis[3];
  auto sweep = [&](int a) {
    if (cell.lo[a] < cell.hi[a]) per_axis[a] = sweep_axis(events.axis[a], a, n, cell, area, model);
  };
  if (parallel) {
    tbb::parallel_invoke([&] { sweep(0); }, [&] { sweep(1); }, [&] { sweep(2); });
  } else {
    for (int a = 0; a < 3; ++a) sweep(a);
  }
  SplitChoice best;
  for (int a = 0; a < 3; ++a)
    if (per_axis[a].found && (!best.found || per_axis[a].cost < best.cost)) best = per_axis[a];
  return best;
}

void splice_events(const EventLists& parent, const std::vector<std::uint8_t>& side,
                   const std::vector<std::uint32_t>& remap_left, const std::vector<std::uint32_t>& remap_right,
                   const std::vector<Ref>& left_refs, const std::vector<Ref>& right_refs,
                   const std::vector<std::uint32_t>& reclipped_left, const std::vector<std::uint32_t>& reclipped_right,
                   EventLists& left, EventLists& right, bool parallel) {
  auto splice_axis = [&](int a) {
    std::vector<Event>& out_l = left.axis[a];
    std::vector<Event>& out_r = right.axis[a];
    out_l.reserve(2 * left_refs.size());
    out_r.reserve(2 * right_refs.size());
    for (const Event& e : parent.axis[a]) {
      const std::uint32_t r = e.ref();
      const std::uint8_t s = side[r];
      if (s & kReclipped) continue;
      if (s & kInLeft) out_l.push_back(Event::make(e.pos, e.type(), remap_left[r]));
      if (s & kInRight) out_r.push_back(Event::make(e.pos, e.type(), remap_right[r]));
    }
    merge_new_events(left_refs, reclipped_left, left, a);
    merge_new_events(right_refs, reclipped_right, right, a);
  };
  if (parallel) {
    tbb::parallel_invoke([&] { splice_axis(0); }, [&] { splice_axis(1); }, [&] { splice_axis(2); });
  } else {
    for (int a = 0; a < 3; ++a) splice_axis(a);
  }
}

}  // namespace lancer::kd
