// The naive split strategies kept for comparison with the SAH: spatial middle and object
// median. They share the node layout, the partitioning and the traversal with SAH trees.
#pragma once

#include "accel/kd_build_types.h"

namespace lancer::kd {

// The middle of the cell's longest axis (the next longest when the middle is not strictly
// inside the cell, as happens for extents of a few ulps). Not found for a point cell.
SplitChoice choose_middle_split(const NodeInput& in);

// The median of the refs' box centres along the cell's longest axis; the middle of that
// axis when the median is not strictly inside the cell.
SplitChoice choose_median_split(const NodeInput& in);

}  // namespace lancer::kd
