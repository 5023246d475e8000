#include "render/photon_grid.h"

#include <algorithm>
#include <stdexcept>

namespace lancer {

void PhotonGrid::build(const std::vector<Photon>& photons, float cell_size) {
  if (!(cell_size > 0.0f) || !std::isfinite(cell_size)) throw std::invalid_argument("photon grid: bad cell size");
  if (photons.size() >= (std::size_t(1) << 31)) throw std::length_error("photon grid: more than 2^31 photons");
  inv_cell_ = 1.0 / static_cast<double>(cell_size);
  // About one bucket per photon: short chains, and a table no bigger than the photons.
  std::size_t buckets = 1;
  while (buckets < photons.size()) buckets <<= 1;
  mask_ = buckets - 1;
  start_.assign(buckets + 1, 0u);
  bucket_of_.resize(photons.size());
  for (std::size_t i = 0; i < photons.size(); ++i) {
    const glm::vec3& p = photons[i].p;
    const std::uint32_t b = bucket(cell(p.x), cell(p.y), cell(p.z));
    bucket_of_[i] = b;
    ++start_[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  // Stable: each bucket's photons in their given order. start_[b] runs up to start_[b + 1]
  // as the bucket fills, then start_ is shifted back by one bucket.
  sorted_.resize(photons.size());
  for (std::size_t i = 0; i < photons.size(); ++i) sorted_[start_[bucket_of_[i]]++] = photons[i];
  for (std::size_t b = buckets; b > 0; --b) start_[b] = start_[b - 1];
  start_[0] = 0;
}

}  // namespace lancer
