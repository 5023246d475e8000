// SPD "mount": a fractal mountain by midpoint displacement (Fournier, Fussell &
// Carpenter, "Computer Rendering of Stochastic Models", CACM 1982) on a square grid,
// with a pyramid of four glass spheres in front of it. One light, far away.
//
// The terrain covers [-1, 1]^2 with a 2^n x 2^n grid whose four outer corners are at
// height 0. Coarse to fine, each square of the current grid gets its edge midpoints
// (the mean of the edge's two ends) and its centre (the mean of its four corners),
// each pushed up or down by a Gaussian times h * roughness (times sqrt(2) for the
// centre), h the half side of the square. The roughness follows from the fractal
// dimension D = 2.2 as sqrt(q^2 - 1) with q = 2 / 2^(1 / (D - 1)). Every point draws its
// Gaussian from a hash of its position on the finest (size 12) grid, so the mountain of
// size n is exactly the mountain of size n + 1 sampled at every other point: all sizes
// show the same mountain. The terrain is an open surface facing up (+z in the SPD,
// +y in the scene), with its boundary on the square's border.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "scene/spd_common.h"
#include "simd/splitmix64.h"

namespace lancer::spd {

namespace {

constexpr int kMaxDepth = 12;
constexpr double kFractalDimension = 2.2;
constexpr std::uint64_t kMountainSeed = 21;

std::uint64_t mount_triangles(int size, const SpdOptions& options) {
  return (2ull << (2 * size)) + 4 * sphere_triangles(options);
}

// A standard normal deviate for grid point (gi, gj) of the finest grid: the sum of four
// uniforms (Irwin-Hall), centred and scaled to unit variance. Only integer and exact
// float arithmetic, so the terrain does not depend on the platform's libm.
double gaussian_at(std::uint64_t gi, std::uint64_t gj) {
  SplitMix64 rng(splitmix64_mix((gi << 32 | gj) ^ (kMountainSeed * 0x9E3779B97F4A7C15ull)));
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) sum += double(rng.next() >> 11) * 0x1p-53;
  return (sum - 2.0) * std::sqrt(3.0);
}

class Terrain {
 public:
  explicit Terrain(int size)
      : cells_(1 << size), shift_(kMaxDepth - size), height_(std::size_t(cells_ + 1) * (cells_ + 1), 0.0) {
    const double q = 2.0 / std::pow(2.0, 1.0 / (kFractalDimension - 1.0));
    const double roughness = std::sqrt(q * q - 1.0);
    for (int step = cells_; step > 1; step /= 2) {
      const int half = step / 2;
      const double amplitude = (double(half) * 2.0 / cells_) * roughness;
      // Centres first: they use the square's corners only, like the edge midpoints.
      for (int j = 0; j < cells_; j += step)
        for (int i = 0; i < cells_; i += step) {
          const double mean = (h(i, j) + h(i + step, j) + h(i, j + step) + h(i + step, j + step)) / 4.0;
          h(i + half, j + half) = mean + std::sqrt(2.0) * amplitude * noise(i + half, j + half);
        }
      for (int j = 0; j <= cells_; j += step)  // horizontal edges
        for (int i = 0; i < cells_; i += step)
          h(i + half, j) = (h(i, j) + h(i + step, j)) / 2.0 + amplitude * noise(i + half, j);
      for (int j = 0; j < cells_; j += step)  // vertical edges
        for (int i = 0; i <= cells_; i += step)
          h(i, j + half) = (h(i, j) + h(i, j + step)) / 2.0 + amplitude * noise(i, j + half);
    }
  }

  int cells() const { return cells_; }
  // Grid point (i, j) in SPD coordinates (x, y across, z up). 2 i / cells is exact.
  glm::dvec3 point(int i, int j) const { return {-1.0 + 2.0 * i / cells_, -1.0 + 2.0 * j / cells_, h(i, j)}; }

 private:
  double& h(int i, int j) { return height_[std::size_t(j) * std::size_t(cells_ + 1) + std::size_t(i)]; }
  double h(int i, int j) const { return height_[std::size_t(j) * std::size_t(cells_ + 1) + std::size_t(i)]; }
  double noise(int i, int j) const { return gaussian_at(std::uint64_t(i) << shift_, std::uint64_t(j) << shift_); }

  int cells_;
  int shift_;  // grid point (i, j) is point (i << shift, j << shift) of the finest grid
  std::vector<double> height_;
};

void build_mount(SpdEmitter& out, int size) {
  out.set_view({{-1.6, 1.6, 1.7}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0});
  out.add_lights({{-100.0, -100.0, 100.0}}, {0.0, 0.0, 0.0});

  const std::uint32_t rock = out.add_material(diffuse_material("mountain", {0.5f, 0.45f, 0.35f}));
  const Terrain terrain(size);
  for (int j = 0; j < terrain.cells(); ++j)
    for (int i = 0; i < terrain.cells(); ++i)
      out.quad(terrain.point(i, j), terrain.point(i + 1, j), terrain.point(i + 1, j + 1), terrain.point(i, j + 1),
               rock);

  // Four touching spheres of radius r stacked as a tetrahedron around (-0.8, 0.8, 1):
  // their centres are the corners of a regular tetrahedron of edge 2r, at distance
  // r sqrt(3/2) from its centre; one straight up, three below at z = -1/3 of that.
  const std::uint32_t glass = out.add_material(glass_material("crystal", {1.0f, 1.0f, 1.0f}, 0.9f, 1.5f));
  const glm::dvec3 centre(-0.8, 0.8, 1.0);
  const double radius = 0.17, reach = radius * std::sqrt(1.5);
  out.sphere(centre + glm::dvec3(0.0, 0.0, reach), radius, glass);
  const double horizontal = std::sqrt(8.0 / 9.0);
  for (int k = 0; k < 3; ++k) {
    const double azimuth = (-45.0 + 120.0 * k) * std::numbers::pi / 180.0;
    const glm::dvec3 dir(horizontal * std::cos(azimuth), horizontal * std::sin(azimuth), -1.0 / 3.0);
    out.sphere(centre + reach * dir, radius, glass);
  }
}

}  // namespace

const Generator kMount{"mount", {0, kMaxDepth}, mount_triangles, build_mount};

}  // namespace lancer::spd
