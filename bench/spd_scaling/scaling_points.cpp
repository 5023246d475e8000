#include "scaling_points.h"

#include <cmath>
#include <stdexcept>

#include "scene/spd.h"

namespace lancer::bench {

std::vector<ScalingPoint> choose_scaling_points(const std::vector<std::string>& generators, int first_decade,
                                                int last_decade, std::uint64_t max_triangles) {
  if (first_decade > last_decade)
    throw std::invalid_argument("scaling: first decade " + std::to_string(first_decade) + " is above the last " +
                                std::to_string(last_decade));
  std::vector<ScalingPoint> points;
  for (const std::string& spd : generators) {
    const SpdSizeRange range = spd_size_range(spd);  // throws for an unknown name
    std::vector<ScalingPoint> mine;
    for (int d = first_decade; d <= last_decade; ++d) {
      ScalingPoint best;
      double best_distance = kMaxDecadeDistance;
      for (int size = range.min; size <= range.max; ++size) {
        const std::uint64_t n = spd_triangle_count(spd, size);
        if (n > max_triangles) break;  // counts grow with the size
        const double distance = std::fabs(std::log10(static_cast<double>(n)) - d);
        if (distance <= best_distance) {
          best_distance = distance;
          best = ScalingPoint{spd, size, n};
        }
      }
      if (best.triangles == 0) continue;
      if (!mine.empty() && mine.back().size == best.size) continue;
      mine.push_back(best);
    }
    points.insert(points.end(), mine.begin(), mine.end());
  }
  return points;
}

}  // namespace lancer::bench
