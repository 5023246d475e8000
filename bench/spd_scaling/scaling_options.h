// lancer-spd-scaling's command line, parsed and checked.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "scaling_measure.h"

namespace lancer::bench {

// The default cap: every generator reaches 10^6, and gears, mount, rings and tetra reach
// 4-10 million triangles, within the memory of a 24 GiB machine shared with others.
inline constexpr std::uint64_t kDefaultScalingMaxTriangles = 12'000'000;

struct ScalingOptions {
  std::vector<std::string> generators{"balls", "gears", "mount", "rings", "tetra"};
  int first_decade = 4, last_decade = 7;
  std::uint64_t max_triangles = kDefaultScalingMaxTriangles;
  ScalingSettings settings;
  std::string markdown, plot;  // output files; empty: none (the table always goes to stdout)
  bool list = false;           // print the chosen points and exit
};

// Parses argv[1..argc). Returns the options, or std::nullopt with `exit_code` set: 0
// after --help (help on `out`), 2 for a bad command line (one line naming the option
// and what is wrong on `err`).
std::optional<ScalingOptions> parse_scaling_options(int argc, const char* const* argv, std::ostream& out,
                                                    std::ostream& err, int& exit_code);

}  // namespace lancer::bench
