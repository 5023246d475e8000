// Perfect splits: the bounds of a triangle clipped to a kd-tree cell.
#pragma once

#include "accel/triangle_soa.h"

namespace lancer::kd {

// Bounds of (triangle `tri` of `tris`) intersected with `cell`, or an empty Bounds3 when
// they do not meet. Clips the triangle polygon against the six planes of the cell
// (Sutherland & Hodgman 1974) in double precision, then rounds the bounds outward to
// float and clamps them to the cell and to the triangle's own bounds: the result always
// contains the exact intersection (conservative) and is never larger than needed by more
// than one float ulp per side.
Bounds3 clipped_triangle_bounds(const TriangleSoA& tris, std::uint32_t tri, const Bounds3& cell);

}  // namespace lancer::kd
