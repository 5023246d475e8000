// Event lists and the SAH sweep of Wald & Havran (2006), sections 4.2 to 4.4.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/kd_build_types.h"

namespace lancer::kd {

// Appends the events on `axis` of a ref (index `index` in its node's ref list) with bounds
// `box`: a planar event where the box has no extent on the axis, else a start and an end.
void append_events(const Bounds3& box, int axis, std::uint32_t index, EventVector& out);

// Events of all refs, each axis sorted by (position, type, ref). One axis at a time, so
// that one sort buffer at a time adds to the build's peak memory.
EventLists make_sorted_events(const RefVector& refs);
// The same for one axis, into `list` (`buffer`: the radix sort's).
void make_sorted_axis_events(const RefVector& refs, int axis, EventVector& list, EventVector& buffer);

// The cheapest plane strictly inside `cell` on any axis whose cell extent is not zero,
// by the SAH sweep over the sorted events of a node with `n` refs. Planar triangles on
// the plane go to the side that gives the lower cost (left on a tie). Ties between
// planes go to the lowest axis, then the lowest position. `found` is false when no plane
// lies strictly inside the cell. Requires surface_area(cell) > 0.
SplitChoice find_sah_split(const EventLists& events, std::size_t n, const Bounds3& cell, const CostModel& model,
                           bool parallel);

// find_sah_split's answer for a node that holds refs only: each axis's events are made,
// sorted, swept and dropped in turn, so that one axis of events (and one sort buffer) is
// held at a time instead of three. Sequential.
SplitChoice find_sah_split_axis_by_axis(const RefVector& refs, const Bounds3& cell, const CostModel& model);

// Splices the parent's sorted events into the children (section 4.3) in one pass per
// axis: events of refs that stay whole on one side keep their order and get the child's
// ref index (scratch.remap_left/right); refs marked kReclipped in scratch.side straddled
// the plane and got new bounds, so their events are made afresh from
// scratch.reclipped_left/right and their boxes, sorted (few of them) and merged in during
// the same pass. `left_refs` and `right_refs` are the children's ref counts.
//
// SpliceTo::LeftOnly (big nodes, see kd_build.cpp) leaves `right` empty, for the right
// child to sort its own when it starts, and frees each axis of `parent` once spliced:
// parent and left child then hold at most one axis of events both.
enum class SpliceTo { Both, LeftOnly };
void splice_events(EventLists& parent, std::size_t left_refs, std::size_t right_refs, BuildScratch& scratch,
                   EventLists& left, EventLists& right, SpliceTo to);

}  // namespace lancer::kd
