#include "bench_options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <ostream>
#include <stdexcept>

#include "embree_tracer.h"

namespace lancer::bench {

namespace {

// The --quick subset: small enough to finish in well under a minute on two cores.
const std::vector<std::string> kQuickScenes{"cornell-box", "balls-3"};
constexpr int kQuickSize = 256;
constexpr int kQuickReps = 3;
constexpr int kMaxSize = 8192;
constexpr int kMaxReps = 1000;
constexpr int kMaxThreads = 4096;

// Thrown for a bad value; parse_bench_options reports it as a command-line error.
struct BadOption : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T, class Parse>
std::vector<T> parse_names(const std::vector<std::string>& names, const std::string& option, const std::string& valid,
                           const Parse& parse) {
  std::vector<T> out;
  for (const std::string& n : names) {
    const auto parsed = parse(n);
    if (!parsed) throw BadOption(option + ": unknown value '" + n + "' (valid: " + valid + ")");
    if (std::find(out.begin(), out.end(), *parsed) == out.end()) out.push_back(*parsed);
  }
  if (out.empty()) throw BadOption(option + ": empty list");
  return out;
}

int parse_int(const std::string& text, const std::string& option, int lo, int hi) {
  std::size_t used = 0;
  int value = 0;
  try {
    value = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || value < lo || value > hi)
    throw BadOption(option + ": '" + text + "' is not a whole number in " + std::to_string(lo) + ".." +
                    std::to_string(hi));
  return value;
}

}  // namespace

std::string_view mode_name(Mode mode) {
  switch (mode) {
    case Mode::Packet: return "packet";
    case Mode::Single: return "single";
    case Mode::Embree: return "embree";
  }
  return "unknown";
}

std::optional<Mode> parse_mode(std::string_view name) {
  for (Mode m : {Mode::Packet, Mode::Single, Mode::Embree})
    if (mode_name(m) == name) return m;
  return std::nullopt;
}

std::optional<BenchOptions> parse_bench_options(int argc, const char* const* argv,
                                                const std::filesystem::path& default_models, std::ostream& out,
                                                std::ostream& err, int& exit_code) {
  CLI::App app{
      "lancer-bench: Lancer's kd-tree traversal (packet and single-ray kernels) beside Embree 3 on the same "
      "triangles and rays. Prints a markdown table on stdout (Mrays/s: median of --reps runs, with min and max), "
      "progress and checks on stderr. Before timing each scene and ray set, Lancer's packet answers must equal its "
      "single-ray answers bit for bit, and Lancer must agree with Embree (same triangle, same t) except at ties; "
      "a set that fails is reported and not timed, and the exit code is then 1. `lancer bench --render` measures "
      "whole path-traced renders instead (beside Blender's Cycles when installed; --render --help).",
      "lancer-bench"};
  std::vector<std::string> scenes, sets, modes, isas, threads;
  std::string size, reps, models;
  BenchOptions opt;
  app.add_option("--scenes", scenes,
                 "Comma-separated scene names (see --list); an SPD scene of any valid size may be named, e.g. "
                 "gears-2")
      ->delimiter(',')
      ->type_name("A,B,...");
  app.add_option("--sets", sets, "Ray sets: primary, diffuse, shadow (default: all)")
      ->delimiter(',')
      ->type_name("SETS");
  app.add_option("--modes", modes,
                 "packet (Lancer, 64-ray packets), single (Lancer, one ray at a time), embree (Embree 3's best call); "
                 "default: all that this build has")
      ->delimiter(',')
      ->type_name("MODES");
  app.add_option("--isa", isas,
                 "Lancer ISAs: scalar, sse4, avx2, avx512 (default: the best this CPU runs); Embree is capped at the "
                 "same ISA (scalar: SSE2)")
      ->delimiter(',')
      ->type_name("ISAS");
  bool all_isas = false;
  app.add_flag("--all-isas", all_isas, "Every ISA this CPU runs");
  app.add_option("--threads", threads, "Thread counts, 0 = every hardware thread (default 1,0)")
      ->delimiter(',')
      ->type_name("N,...");
  app.add_option("--size", size, "Image side in pixels, a multiple of 8 (default 512; --quick 256)")->type_name("N");
  app.add_option("--reps", reps, "Timed runs per figure; the median is reported (default 5; --quick 3)")
      ->type_name("N");
  app.add_option("--models", models,
                 "Folder of OBJ/glTF meshes to add to the suite (default: " +
                     (default_models.empty() ? std::string("none") : default_models.string()) + ", when it exists)")
      ->type_name("DIR");
  app.add_option("--json", opt.json, "Write every raw number (each repetition too) to this JSON file")
      ->type_name("FILE");
  app.add_option("--plot", opt.plot,
                 "Write an SVG bar chart of Mrays/s by scene and mode (first set, first ISA, "
                 "last thread count)")
      ->type_name("FILE.svg");
  app.add_flag("--quick", opt.quick,
               "A small subset: cornell-box and balls-3, primary and shadow rays, 3 reps, 256x256 (explicit options "
               "still win)");
  app.add_flag("--list", opt.list, "Print the scene names of the suite and exit");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    exit_code = 0;
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    err << "lancer-bench: " << e.what() << "\nRun 'lancer-bench --help' for the options.\n";
    exit_code = 2;
    return std::nullopt;
  }

  try {
    const auto given = [&](const char* name) { return app.count(name) > 0; };
    if (opt.quick) {
      opt.scenes = kQuickScenes;
      opt.sets = {RaySet::Primary, RaySet::Shadow};
      opt.size = kQuickSize;
      opt.reps = kQuickReps;
    }
    if (given("--scenes")) {
      opt.scenes = scenes;
      if (opt.scenes.empty()) throw BadOption("--scenes: empty list");
    }
    if (given("--sets")) opt.sets = parse_names<RaySet>(sets, "--sets", "primary, diffuse, shadow", parse_ray_set);
    if (given("--modes")) {
      opt.modes = parse_names<Mode>(modes, "--modes", "packet, single, embree", parse_mode);
      opt.embree_requested = std::find(opt.modes.begin(), opt.modes.end(), Mode::Embree) != opt.modes.end();
      if (opt.embree_requested && !embree_available())
        throw BadOption(
            "--modes embree: this lancer-bench was built without Embree 3 (install libembree-dev and "
            "reconfigure)");
    } else {
      opt.modes = {Mode::Packet, Mode::Single};
      if (embree_available()) opt.modes.push_back(Mode::Embree);
    }
    if (given("--isa") && given("--all-isas")) throw BadOption("--isa and --all-isas exclude each other");
    if (given("--all-isas")) {
      opt.isas = supported_isas();
    } else if (given("--isa")) {
      opt.isas = parse_names<Isa>(isas, "--isa", "scalar, sse4, avx2, avx512", parse_isa);
      for (Isa isa : opt.isas)
        if (!cpu_supports(isa))
          throw BadOption("--isa " + std::string(isa_name(isa)) +
                          ": this CPU (or its operating system) does not "
                          "support it");
    } else {
      opt.isas = {best_supported_isa()};
    }
    if (given("--threads")) {
      opt.threads.clear();
      for (const std::string& t : threads) {
        const int n = parse_int(t, "--threads", 0, kMaxThreads);
        if (std::find(opt.threads.begin(), opt.threads.end(), n) == opt.threads.end()) opt.threads.push_back(n);
      }
      if (opt.threads.empty()) throw BadOption("--threads: empty list");
    }
    if (given("--size")) {
      opt.size = parse_int(size, "--size", kRayTileSide, kMaxSize);
      if (opt.size % kRayTileSide != 0)
        throw BadOption("--size: " + size + " is not a multiple of " + std::to_string(kRayTileSide));
    }
    if (given("--reps")) opt.reps = parse_int(reps, "--reps", 1, kMaxReps);
    if (given("--models")) {
      opt.models = models;
      opt.models_given = true;
      if (!std::filesystem::is_directory(opt.models))
        throw BadOption("--models: " + models + " is not a folder (it does not exist or is a file)");
    } else if (!default_models.empty() && std::filesystem::is_directory(default_models)) {
      opt.models = default_models;
    }
    if (!opt.plot.empty() && opt.plot == opt.json) throw BadOption("--plot and --json name the same file");
  } catch (const BadOption& e) {
    err << "lancer-bench: " << e.what() << "\nRun 'lancer-bench --help' for the options.\n";
    exit_code = 2;
    return std::nullopt;
  }
  exit_code = 0;
  return opt;
}

}  // namespace lancer::bench
