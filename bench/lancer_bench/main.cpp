// lancer-bench: the throughput numbers users quote, with Embree 3 beside every one.
// Kept apart from `lancer` (which runs it as `lancer bench`) so the renderer never links
// Embree. Exit codes: 0 success, 1 a scene or set failed its checks (reported, the rest
// measured) or an output file could not be written, 2 bad options.
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <string_view>

#include "bench_options.h"
#include "bench_runner.h"
#include "bench_suite.h"
#include "report_json.h"
#include "report_markdown.h"
#include "report_svg.h"
#include "caustic_bench.h"
#include "render_bench.h"
#include "simd/out_of_memory.h"

namespace {

namespace fs = std::filesystem;
using namespace lancer::bench;

// The project's scenes and the shared meshes beside the project (bench/CMakeLists.txt).
const fs::path kScenesDir = fs::path(LANCER_BENCH_SCENES_DIR).lexically_normal();
const fs::path kDefaultModels = fs::path(LANCER_BENCH_MODELS_DIR).lexically_normal();

// `lancer bench --render ...`: whole renders (bench/render_bench/).
int run_render(int argc, char** argv) {
  int code = 0;
  const auto options = parse_render_bench_options(argc, argv, std::cout, std::cerr, code);
  if (!options) return code;
  return run_render_bench(*options, kScenesDir, kDefaultModels, fs::path(LANCER_BENCH_CYCLES_SCRIPT), std::cout,
                          std::cerr);
}

// `lancer bench --caustics ...`: photon mapping against path tracing at equal time.
int run_caustics(int argc, char** argv) {
  int code = 0;
  const auto options = parse_caustic_bench_options(argc, argv, std::cout, std::cerr, code);
  if (!options) return code;
  return run_caustic_bench(*options, kScenesDir, std::cout, std::cerr);
}

int run(int argc, char** argv) {
  if (argc > 1 && std::string_view(argv[1]) == "--render") return run_render(argc - 1, argv + 1);
  if (argc > 1 && std::string_view(argv[1]) == "--caustics") return run_caustics(argc - 1, argv + 1);
  int code = 0;
  const auto options = parse_bench_options(argc, argv, kDefaultModels, std::cout, std::cerr, code);
  if (!options) return code;
  const std::vector<SuiteScene> suite = default_suite(kScenesDir, options->models);
  if (options->list) {
    for (const SuiteScene& s : suite)
      std::cout << s.name << "\t" << s.origin << "\t"
                << (s.kind == SuiteScene::Kind::Spd ? "spd " + s.spd + " " + std::to_string(s.spd_size)
                                                    : s.file.string())
                << "\n";
    return 0;
  }
  std::vector<SuiteScene> scenes;
  try {
    scenes = options->scenes.empty() ? suite : select_scenes(suite, options->scenes);
  } catch (const UnknownScene& e) {
    std::cerr << "lancer-bench: " << e.what() << "\n";
    return 2;
  }
  if (options->models.empty() && options->scenes.empty())
    std::cerr << "lancer-bench: no models folder (" << kDefaultModels.string()
              << " does not exist; --models DIR adds one)\n";

  const BenchRun result = run_suite(*options, scenes, std::cerr);
  write_markdown(result, std::cout);
  std::cout.flush();
  int status = result.any_failure() ? 1 : 0;
  try {
    if (!options->json.empty()) {
      write_json(result, options->json);
      std::cerr << "lancer-bench: wrote " << options->json << "\n";
    }
    if (!options->plot.empty()) {
      const PlotSelection sel = default_plot_selection(result);
      write_text_file(options->plot, plot_svg(result, sel));
      std::cerr << "lancer-bench: wrote " << options->plot << " (" << lancer::ray_set_name(sel.set) << " rays, "
                << sel.threads << " threads, " << lancer::isa_name(sel.isa) << ")\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "lancer-bench: error: " << e.what() << "\n";
    status = 1;
  }
  if (status != 0) std::cerr << "lancer-bench: some scenes or sets failed (see Failures)\n";
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc& e) {
    std::cerr << "lancer-bench: error: " << lancer::out_of_memory_message(e) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "lancer-bench: error: " << e.what() << "\n";
  }
  return 1;
}
