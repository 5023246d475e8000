// lancer-spd-scaling: build time, kd-tree memory and primary Mrays/s of Haines' SPD scenes
// from 10^4 to 10^7 triangles (issue 5's scaling plot; docs/performance.md). Exit codes: 0
// done (points skipped for lack of memory are reported, not failures), 1 a point failed or
// an output file could not be written, 2 bad options.
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <string>

#include "report_json.h"
#include "scaling_measure.h"
#include "scaling_options.h"
#include "scaling_points.h"
#include "scaling_report.h"
#include "simd/out_of_memory.h"

namespace {

using namespace lancer::bench;

int run(int argc, char** argv) {
  // The child process of measure_peak_in_child (not a user option).
  // `--peak-of SPD SIZE [ISA]` (the ISA's tree; default: the best this CPU runs).
  if ((argc == 4 || argc == 5) && std::string(argv[1]) == kPeakChildOption) {
    const std::optional<lancer::Isa> isa = argc == 5 ? lancer::parse_isa(argv[4]) : lancer::best_supported_isa();
    if (!isa) {
      std::cerr << "unknown instruction set '" << argv[4] << "'\n";
      return 1;
    }
    return run_peak_child(argv[2], std::atoi(argv[3]), *isa);
  }
  int code = 0;
  auto options = parse_scaling_options(argc, argv, std::cout, std::cerr, code);
  if (!options) return code;
  options->settings.peak_program = this_executable();
  const std::vector<ScalingPoint> points =
      choose_scaling_points(options->generators, options->first_decade, options->last_decade, options->max_triangles);
  if (options->list) {
    for (const ScalingPoint& p : points) std::cout << p.name() << "\t" << p.triangles << "\n";
    return 0;
  }
  std::vector<ScalingResult> results;
  int status = 0;
  for (const ScalingPoint& p : points) {
    // Checked before each point: other programs on a shared machine come and go.
    const std::int64_t available = available_memory_bytes();
    results.push_back(measure_scaling_point(p, options->settings, available, std::cerr));
    if (!results.back().failure.empty() && !results.back().skipped) status = 1;
  }
  std::ostringstream table;
  write_scaling_markdown(results, options->settings, table);
  std::cout << table.str() << std::flush;
  try {
    if (!options->markdown.empty()) {
      write_text_file(options->markdown, table.str());
      std::cerr << "lancer-spd-scaling: wrote " << options->markdown << "\n";
    }
    if (!options->plot.empty()) {
      write_text_file(options->plot, scaling_svg(results, options->settings));
      std::cerr << "lancer-spd-scaling: wrote " << options->plot << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "lancer-spd-scaling: error: " << e.what() << "\n";
    status = 1;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc& e) {
    std::cerr << "lancer-spd-scaling: error: " << lancer::out_of_memory_message(e) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "lancer-spd-scaling: error: " << e.what() << "\n";
  }
  return 1;
}
