// lancer-bench --plot: a plain SVG bar chart written by hand (no dependencies).
#pragma once

#include <string>

#include "bench_results.h"

namespace lancer::bench {

// What the chart shows: one ray set, ISA and thread count of the run.
struct PlotSelection {
  RaySet set = RaySet::Primary;
  Isa isa = Isa::Scalar;
  int threads = 1;
};

// The run's first set, first ISA and last thread count (every thread, by default).
PlotSelection default_plot_selection(const BenchRun& run);

// Grouped bars of median Mrays/s, one group per scene and one bar per mode (a <rect> per
// bar and none elsewhere; min-max whiskers as lines), with the y axis labelled in
// Mrays/s, scene names under the groups, a legend and a title naming the selection.
// Scenes whose row failed or is missing get a "failed" label and no bars.
std::string plot_svg(const BenchRun& run, const PlotSelection& selection);

// text with the five XML special characters escaped, for SVG text and attributes.
std::string xml_escape(const std::string& text);

}  // namespace lancer::bench
