// `lancer bench --caustics`: photon mapping against path tracing at equal time (issue 17).
// Each integrator renders the scene for the same wall time; at log-spaced times on the way
// its image's mean squared error is measured against a long path-traced reference, over the
// whole image and inside a region (by default the caustic under the glass sphere of the
// mirror/glass Cornell box). The reference is two independent path-traced halves A and B,
// so that its own noise can be taken out: E|X - (A + B) / 2|^2 = MSE(X) + E|A - B|^2 / 4.
// Reports the errors at the end, their ratio (SPPM over path), and the log-log slope of
// error against time for each.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace lancer::bench {

struct CausticBenchOptions {
  std::string scene = "cornell-box-spheres";
  int size = 256;
  double seconds = 60.0;  // per integrator
  int max_depth = 64;
  int threads = 2;
  int reference_spp = 4096;  // per half of the reference
  std::vector<std::string> integrators = {"path", "sppm"};
  // The region [x0, x1) x [y0, y1) in pixels of a 256-pixel image, scaled to --size: the
  // caustic under the glass sphere of cornell-box-spheres.
  std::vector<int> region = {140, 220, 188, 242};
  std::filesystem::path cache = "out/render-bench";
  std::string json;
  std::string plot;  // an SVG of error against time; empty: none
};

std::optional<CausticBenchOptions> parse_caustic_bench_options(int argc, const char* const* argv, std::ostream& out,
                                                               std::ostream& err, int& exit_code);

int run_caustic_bench(const CausticBenchOptions& options, const std::filesystem::path& scenes_dir, std::ostream& out,
                      std::ostream& err);

}  // namespace lancer::bench
