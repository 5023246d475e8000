// Photons left on surfaces, and a uniform hash grid that finds those within a radius of a
// point: the density estimate of photon mapping (Jensen 1996) as progressive photon mapping
// gathers it at its visible points (Hachisuka & Jensen 2009).
//
// Cells are cubes of one size, hashed into a table of 2^k buckets with the hash of Teschner
// et al. 2003 ("Optimized Spatial Hashing for Collision Detection of Deformable Objects").
// The table is filled by a stable counting sort, so a bucket holds its photons in the order
// they were given: a gather adds them up in an order that no thread schedule changes.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace lancer {

struct Photon {
  glm::vec3 p{0.0f};      // where it landed
  glm::vec3 wi{0.0f};     // unit, back towards where it came from
  glm::vec3 power{0.0f};  // the flux it carries (W, per channel)
  std::uint32_t bounces = 0;  // the scattering events it went through before landing
};

class PhotonGrid {
 public:
  // Hashes `photons` (copied, reordered by bucket) into cells of `cell_size` (> 0, finite).
  // Reuses its memory from build to build: once it has held the largest set, a build
  // allocates nothing.
  void build(const std::vector<Photon>& photons, float cell_size);

  // Calls f(photon) for every photon within `radius` of p (|photon.p - p| <= radius), in an
  // order that depends only on the photons given to build(). radius must be at most the
  // cell size, so that the query box spans at most 3 cells per axis.
  template <class F>
  void for_each_within(const glm::vec3& p, float radius, F&& f) const;

  std::size_t size() const { return sorted_.size(); }

 private:
  std::uint32_t bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const auto h = (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
                   (static_cast<std::uint64_t>(z) * 83492791u);
    return static_cast<std::uint32_t>(h & mask_);
  }
  // The cell coordinate of x, clamped far inside int64's range (a stray coordinate far
  // from the scene stays a valid, if crowded, cell).
  std::int64_t cell(float x) const {
    const double c = std::floor(static_cast<double>(x) * inv_cell_);
    return static_cast<std::int64_t>(c < -1e15 ? -1e15 : (c > 1e15 ? 1e15 : c));
  }

  double inv_cell_ = 1.0;
  std::uint64_t mask_ = 0;
  std::vector<Photon> sorted_;
  std::vector<std::uint32_t> start_;      // bucket b holds sorted_[start_[b], start_[b + 1])
  std::vector<std::uint32_t> bucket_of_;  // scratch of build(): each photon's bucket
};

template <class F>
void PhotonGrid::for_each_within(const glm::vec3& p, float radius, F&& f) const {
  if (sorted_.empty()) return;
  const std::int64_t x0 = cell(p.x - radius), x1 = cell(p.x + radius);
  const std::int64_t y0 = cell(p.y - radius), y1 = cell(p.y + radius);
  const std::int64_t z0 = cell(p.z - radius), z1 = cell(p.z + radius);
  // Distinct cells may share a bucket: each bucket is read once.
  std::uint32_t seen[27];
  int n = 0;
  const float r2 = radius * radius;
  for (std::int64_t z = z0; z <= z1 && z <= z0 + 2; ++z)
    for (std::int64_t y = y0; y <= y1 && y <= y0 + 2; ++y)
      for (std::int64_t x = x0; x <= x1 && x <= x0 + 2; ++x) {
        const std::uint32_t b = bucket(x, y, z);
        bool repeat = false;
        for (int i = 0; i < n; ++i) repeat |= seen[i] == b;
        if (repeat) continue;
        seen[n++] = b;
        for (std::uint32_t i = start_[b]; i < start_[b + 1]; ++i) {
          const Photon& ph = sorted_[i];
          const glm::vec3 d = ph.p - p;
          if (glm::dot(d, d) <= r2) f(ph);
        }
      }
}

}  // namespace lancer
