// What `lancer-bench` is asked to measure: its command line, parsed and checked.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "render/ray_sets.h"
#include "simd/isa.h"

namespace lancer::bench {

// How rays are traced in a row: Lancer's packet and single-ray kernels, and Embree's best call.
enum class Mode { Packet, Single, Embree };

std::string_view mode_name(Mode mode);
std::optional<Mode> parse_mode(std::string_view name);

struct BenchOptions {
  std::vector<std::string> scenes;  // names to keep; empty: every scene of the suite
  std::vector<RaySet> sets{RaySet::Primary, RaySet::Diffuse, RaySet::Shadow};
  std::vector<Mode> modes;         // default: packet, single and (when built with it) embree
  bool embree_requested = false;   // --modes named embree explicitly
  std::vector<Isa> isas;           // default: the best this CPU runs
  std::vector<int> threads{1, 0};  // 0: every hardware thread
  int size = 512;                  // image side in pixels, a multiple of 8
  int reps = 5;
  std::filesystem::path models;  // empty: no models
  bool models_given = false;     // --models given: a missing folder is an error
  std::string json;              // output files; empty: none
  std::string plot;
  bool quick = false;
  bool list = false;  // --list: print the scene names and exit
};

// Parses argv. Returns the options, or std::nullopt with `exit_code` set: 0 after --help
// (help on `out`), 2 for a bad command line (message on `err`). Checks names (scenes are
// checked later, against the suite), numbers and --models; `default_models` is used when
// --models is not given and the folder exists.
std::optional<BenchOptions> parse_bench_options(int argc, const char* const* argv,
                                                const std::filesystem::path& default_models, std::ostream& out,
                                                std::ostream& err, int& exit_code);

}  // namespace lancer::bench
