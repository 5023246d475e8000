// PhotonGrid: every photon within the radius is found exactly once, none outside it, in an
// order that depends only on the photons given, whatever the cell size and however many
// cells share a bucket.
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/photon_grid.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

float uniform(std::uint64_t& state) {
  state += 0x9E3779B97F4A7C15ull;
  return float(splitmix64_mix(state) >> 40) * 0x1p-24f;
}

std::vector<Photon> random_photons(std::size_t n, float extent, std::uint64_t seed) {
  std::vector<Photon> photons(n);
  for (std::size_t i = 0; i < n; ++i) {
    photons[i].p = glm::vec3(uniform(seed), uniform(seed), uniform(seed)) * extent - glm::vec3(0.5f * extent);
    photons[i].bounces = static_cast<std::uint32_t>(i);  // the photon's identity, for the test
  }
  // Duplicates and points exactly on cell borders.
  for (std::size_t i = 0; i + 1 < n / 10; ++i) photons[n - 1 - i].p = photons[i].p;
  photons[0].p = glm::vec3(0.0f);
  photons[1].p = glm::vec3(1.0f, 0.5f, -0.25f);
  return photons;
}

TEST(PhotonGrid, FindsExactlyThePhotonsWithinTheRadius) {
  const std::vector<Photon> photons = random_photons(20000, 4.0f, 7);
  for (float cell : {0.05f, 0.2f, 1.0f}) {
    PhotonGrid grid;
    grid.build(photons, cell);
    ASSERT_EQ(grid.size(), photons.size());
    std::uint64_t state = 99;
    for (int q = 0; q < 300; ++q) {
      const glm::vec3 p = glm::vec3(uniform(state), uniform(state), uniform(state)) * 4.4f - glm::vec3(2.2f);
      const float radius = cell * (q % 3 == 0 ? 1.0f : uniform(state));
      std::vector<int> seen(photons.size(), 0);
      std::vector<std::uint32_t> order;
      grid.for_each_within(p, radius, [&](const Photon& ph) {
        ++seen[ph.bounces];
        order.push_back(ph.bounces);
      });
      for (std::size_t i = 0; i < photons.size(); ++i) {
        const glm::vec3 d = photons[i].p - p;
        ASSERT_EQ(seen[i], glm::dot(d, d) <= radius * radius ? 1 : 0)
            << "photon " << i << ", cell " << cell << ", query " << q;
      }
      // The same photons in the same order after a rebuild.
      PhotonGrid again;
      again.build(photons, cell);
      std::vector<std::uint32_t> order2;
      again.for_each_within(p, radius, [&](const Photon& ph) { order2.push_back(ph.bounces); });
      ASSERT_EQ(order, order2);
    }
  }
}

TEST(PhotonGrid, EmptyAndFarAwayQueriesFindNothing) {
  PhotonGrid grid;
  grid.build({}, 1.0f);
  int found = 0;
  grid.for_each_within(glm::vec3(0.0f), 1.0f, [&](const Photon&) { ++found; });
  EXPECT_EQ(found, 0);
  grid.build(random_photons(100, 1.0f, 3), 0.1f);
  grid.for_each_within(glm::vec3(1e30f), 0.1f, [&](const Photon&) { ++found; });
  EXPECT_EQ(found, 0);
  EXPECT_THROW(grid.build({}, 0.0f), std::invalid_argument);
}

}  // namespace
}  // namespace lancer
