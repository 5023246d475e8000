// lancer-spd-scaling's reports: a markdown table and a log-log SVG of three panels (build
// time, kd-tree memory, primary Mrays/s against the triangle count), drawn by hand.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "scaling_measure.h"

namespace lancer::bench {

// One row per result (skipped and failed points say why), after a line naming the
// settings: image, ISA, threads, repetitions.
void write_scaling_markdown(const std::vector<ScalingResult>& results, const ScalingSettings& settings,
                            std::ostream& out);

// A log10 axis: whole decades [lo, hi] covering every value (> 0) given; lo < hi always.
struct LogAxis {
  int lo = 0, hi = 1;
};
LogAxis log_axis(const std::vector<double>& values);

// Three panels side by side, x = triangles on a log axis in each: kd-tree build CPU
// seconds (one thread), kd-tree MiB, and primary Mrays per CPU second (packet solid,
// single-ray dashed). One
// <polyline class="series"> per generator and quantity with two or more measured points,
// a <circle class="point"> (with a <title>) per measured value; skipped or failed points
// are left out and listed under the panels.
std::string scaling_svg(const std::vector<ScalingResult>& results, const ScalingSettings& settings);

}  // namespace lancer::bench
