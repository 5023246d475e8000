// Which SPD scenes lancer-spd-scaling measures: for each generator (default tessellation)
// and each decade of triangle counts, the size whose count lies nearest in log scale.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lancer::bench {

struct ScalingPoint {
  std::string spd;           // generator: balls, gears, mount, rings or tetra
  int size = 0;              // its size factor
  std::uint64_t triangles = 0;  // spd_triangle_count(spd, size)
  std::string name() const { return spd + "-" + std::to_string(size); }
};

// A generator's size for decade 10^d must be within half a decade of it (a factor of
// sqrt(10)), so that a generator whose sizes step coarsely (balls: 9x) skips a decade
// rather than standing in for it with a count from the next one.
inline constexpr double kMaxDecadeDistance = 0.5;

// For each generator of `generators` (in that order) and each decade 10^first..10^last:
// among the sizes whose triangle count is at most `max_triangles`, the one nearest the
// decade in |log10(count) - d|, when within kMaxDecadeDistance; a size nearest to two
// decades is listed once. Sorted by generator (given order), then triangle count. Throws
// std::invalid_argument for an unknown generator or first > last.
std::vector<ScalingPoint> choose_scaling_points(const std::vector<std::string>& generators, int first_decade,
                                                int last_decade, std::uint64_t max_triangles);

}  // namespace lancer::bench
