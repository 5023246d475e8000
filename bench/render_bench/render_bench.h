// `lancer bench --render`: what a person rendering an image gets. For each scene: paths/s
// and Mrays/s of the path tracer, the share of its CPU time spent in ray traversal
// (ray_recorder.h), and, when Blender is installed, Cycles on the same glTF file with the
// same camera, resolution, samples and bounce limit (bench/cycles/cycles_render.py), each
// renderer's error against a long reference render and the speed at equal error,
// 1 / (mean squared error x seconds), Lancer / Cycles.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace lancer::bench {

enum class CyclesUse { Auto, On, Off };  // Auto: when `blender` is found
enum class ReferenceFrom { Cycles, Lancer };

struct RenderBenchOptions {
  std::vector<std::string> scenes;  // empty: the render suite (render_suite_names())
  int size = 256;                   // square image side in pixels
  int spp = 64;
  int max_depth = 64;
  int light_samples = 1;  // area-light samples per bounce
  int threads = 2;         // 0: every hardware thread
  int reps = 3;            // timed renders per scene; the median is reported
  int trace_passes = 4;    // passes recorded for the traversal share
  CyclesUse cycles = CyclesUse::Auto;
  ReferenceFrom reference = ReferenceFrom::Cycles;
  int reference_spp = 4096;
  std::filesystem::path cache = "out/render-bench";  // reference renders, kept between runs
  std::string blender = "blender";
  std::string json;  // results as JSON; empty: none
};

// The scenes `lancer bench --render` measures by default, in order.
std::vector<std::string> render_suite_names();

// Parses the arguments after --render; std::nullopt with exit_code set (0 after --help,
// 2 for a bad command line).
std::optional<RenderBenchOptions> parse_render_bench_options(int argc, const char* const* argv, std::ostream& out,
                                                             std::ostream& err, int& exit_code);

// Runs the benchmark; the table on `out`, progress on `err`. Returns the exit code: 0, or 1
// when a scene or a Cycles render failed (reported, the rest measured).
int run_render_bench(const RenderBenchOptions& options, const std::filesystem::path& scenes_dir,
                     const std::filesystem::path& models_dir, const std::filesystem::path& cycles_script,
                     std::ostream& out, std::ostream& err);

}  // namespace lancer::bench
