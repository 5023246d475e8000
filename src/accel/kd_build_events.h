// Event lists and the SAH sweep of Wald & Havran (2006), sections 4.2 to 4.4.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/kd_build_types.h"

namespace lancer::kd {

// Appends the events of `ref` (index `index` in its node's ref list) to the three lists:
// a planar event where the box has no extent on an axis, else a start and an end event.
void append_events(const Bounds3& box, std::uint32_t index, EventLists& out);

// Events of all refs, each axis sorted by (position, type, ref). With `parallel` the
// three axes are sorted at the same time; the result is the same either way.
EventLists make_sorted_events(const std::vector<Ref>& refs, bool parallel);

// The cheapest plane strictly inside `cell` on any axis whose cell extent is not zero,
// by the SAH sweep over the sorted events of a node with `n` refs. Planar triangles on
// the plane go to the side that gives the lower cost (left on a tie). Ties between
// planes go to the lowest axis, then the lowest position. `found` is false when no plane
// lies strictly inside the cell. Requires surface_area(cell) > 0.
SplitChoice find_sah_split(const EventLists& events, std::size_t n, const Bounds3& cell, const CostModel& model,
                           bool parallel);

// Splices the parent's sorted events into the children (section 4.3) in one pass per
// axis: events of refs that stay whole on one side keep their order and get the child's
// ref index (scratch.remap_left/right); refs marked kReclipped in scratch.side straddled
// the plane and got new bounds, so their events are regenerated from the child refs
// (scratch.reclipped_left/right index left_refs/right_refs), sorted (few of them) and
// merged in during the same pass. With `parallel` the three axes are spliced at the same
// time, and `scratch.fresh` is not used.
void splice_events(const EventLists& parent, const std::vector<Ref>& left_refs, const std::vector<Ref>& right_refs,
                   BuildScratch& scratch, EventLists& left, EventLists& right, bool parallel);

}  // namespace lancer::kd
