#include "accel/kd_build_naive.h"

#include <algorithm>

namespace lancer::kd {
namespace {

// Axes by decreasing cell extent (computed in double: float extents may overflow).
void axes_by_extent(const Bounds3& cell, int order[3]) {
  double ext[3];
  for (int a = 0; a < 3; ++a) {
    ext[a] = double(cell.hi[a]) - cell.lo[a];
    order[a] = a;
  }
  std::stable_sort(order, order + 3, [&](int a, int b) { return ext[a] > ext[b]; });
}

bool strictly_inside(const Bounds3& cell, int axis, float pos) { return cell.lo[axis] < pos && pos < cell.hi[axis]; }

float middle(const Bounds3& cell, int axis) {
  return static_cast<float>(0.5 * (double(cell.lo[axis]) + double(cell.hi[axis])));
}

}  // namespace

SplitChoice choose_middle_split(const NodeInput& in) {
  int order[3];
  axes_by_extent(in.cell, order);
  for (int a : order) {
    const float pos = middle(in.cell, a);
    if (strictly_inside(in.cell, a, pos)) return {true, a, pos, PlanarSide::Left, 0.0};
  }
  return {};
}

SplitChoice choose_median_split(const NodeInput& in) {
  int order[3];
  axes_by_extent(in.cell, order);
  const int axis = order[0];
  if (!in.refs.empty()) {
    std::vector<float> centres(in.refs.size());
    for (std::size_t i = 0; i < in.refs.size(); ++i)
      centres[i] = static_cast<float>(0.5 * (double(in.refs[i].box.lo[axis]) + double(in.refs[i].box.hi[axis])));
    auto mid = centres.begin() + static_cast<std::ptrdiff_t>(centres.size() / 2);
    std::nth_element(centres.begin(), mid, centres.end());
    if (strictly_inside(in.cell, axis, *mid)) return {true, axis, *mid, PlanarSide::Left, 0.0};
  }
  return choose_middle_split(in);
}

}  // namespace lancer::kd
