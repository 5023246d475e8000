#include "bench_checks.h"

#include <bit>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace lancer::bench {

namespace {

void require_same_size(std::size_t a, std::size_t b) {
  if (a != b) throw std::invalid_argument("lancer-bench: comparing answer lists of different lengths");
}

// `absolute`: kSameTExtent of the scene in units of the ray's t.
bool same_t(float a, float b, float absolute) {
  return std::fabs(a - b) <= kSameTRelative * std::fmax(std::fabs(a), std::fabs(b)) + absolute;
}

}  // namespace

Agreement compare_closest(std::span<const Ray> rays, std::span<const Hit> lancer, std::span<const Hit> embree,
                          float scene_extent) {
  require_same_size(lancer.size(), embree.size());
  require_same_size(rays.size(), lancer.size());
  Agreement a;
  a.compared = lancer.size();
  for (std::size_t i = 0; i < lancer.size(); ++i) {
    const Hit &l = lancer[i], &e = embree[i];
    if (!l.valid() && !e.valid()) continue;
    const bool both = l.valid() && e.valid();
    float absolute = 0.0f;  // only for the same triangle (kSameTExtent)
    if (both && l.prim == e.prim && l.instance == e.instance) {
      const float dir_length = std::sqrt(glm::dot(rays[i].dir, rays[i].dir));
      if (dir_length > 0.0f) absolute = kSameTExtent * scene_extent / dir_length;
    }
    if (both && same_t(l.t, e.t, absolute)) {
      if (l.prim != e.prim) ++a.ties;
      continue;
    }
    if (a.disagreements++ == 0) a.first_disagreement = i;
  }
  return a;
}

Agreement compare_occlusion(std::span<const std::uint8_t> lancer, std::span<const std::uint8_t> embree) {
  require_same_size(lancer.size(), embree.size());
  Agreement a;
  a.compared = lancer.size();
  for (std::size_t i = 0; i < lancer.size(); ++i)
    if ((lancer[i] != 0) != (embree[i] != 0) && a.disagreements++ == 0) a.first_disagreement = i;
  return a;
}

bool same_hit_bits(const Hit& a, const Hit& b) {
  return a.prim == b.prim && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
         std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
         std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

std::size_t count_bit_differences(std::span<const Hit> a, std::span<const Hit> b, std::size_t& first) {
  require_same_size(a.size(), b.size());
  std::size_t n = 0;
  first = static_cast<std::size_t>(-1);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_hit_bits(a[i], b[i]) && n++ == 0) first = i;
  return n;
}

std::size_t count_bit_differences(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                                  std::size_t& first) {
  require_same_size(a.size(), b.size());
  std::size_t n = 0;
  first = static_cast<std::size_t>(-1);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i] && n++ == 0) first = i;
  return n;
}

}  // namespace lancer::bench
