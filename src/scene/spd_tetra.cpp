// SPD "tetra": a recursive tetrahedral pyramid (the Sierpinski tetrahedron, after
// Mandelbrot and Norton, as ray traced by Glassner and by Kay & Kajiya). The tetrahedron
// inscribed in the cube [-1, 1]^3 (the corners whose coordinate signs multiply to +1)
// is replaced by four tetrahedra of half its size at its corners, depth - 1 times. The
// small tetrahedra touch at single corners only, so each is a closed mesh of its own.
// One light; the background fills most of the view.
#include <array>
#include <cstdint>
#include <utility>

#include <glm/geometric.hpp>

#include "scene/spd_common.h"

namespace lancer::spd {

namespace {

constexpr int kMaxDepth = 12;

std::uint64_t tetra_triangles(int size, const SpdOptions&) { return 1ull << (2 * size); }

// The corners of the tetrahedron as signs of the cube's half size.
constexpr std::array<glm::dvec3, 4> kCorners = {glm::dvec3(1, 1, 1), glm::dvec3(1, -1, -1), glm::dvec3(-1, 1, -1),
                                                glm::dvec3(-1, -1, 1)};

// The four faces (each leaves out one corner), wound so the normal points away from
// the corner left out, i.e. outward.
std::array<std::array<int, 3>, 4> outward_faces() {
  std::array<std::array<int, 3>, 4> faces{};
  for (int skip = 0; skip < 4; ++skip) {
    std::array<int, 3> f{};
    for (int i = 0, n = 0; i < 4; ++i)
      if (i != skip) f[std::size_t(n++)] = i;
    const glm::dvec3 a = kCorners[std::size_t(f[0])], b = kCorners[std::size_t(f[1])], c = kCorners[std::size_t(f[2])];
    if (glm::dot(glm::cross(b - a, c - a), kCorners[std::size_t(skip)] - a) > 0.0) std::swap(f[1], f[2]);
    faces[std::size_t(skip)] = f;
  }
  return faces;
}

struct Pyramid {
  SpdEmitter& out;
  std::uint32_t material;
  std::array<std::array<int, 3>, 4> faces = outward_faces();

  // Halving is exact in binary, so every corner is a short dyadic number and corners
  // shared by neighbouring tetrahedra come out with the same bits.
  void grow(const glm::dvec3& centre, double half, int depth) {
    if (depth <= 1) {
      std::array<glm::dvec3, 4> p{};
      for (std::size_t i = 0; i < 4; ++i) p[i] = centre + half * kCorners[i];
      for (const auto& f : faces)
        out.triangle(p[std::size_t(f[0])], p[std::size_t(f[1])], p[std::size_t(f[2])], material);
      return;
    }
    for (const glm::dvec3& corner : kCorners) grow(centre + 0.5 * half * corner, 0.5 * half, depth - 1);
  }
};

void build_tetra(SpdEmitter& out, int size) {
  const glm::dvec3 at(-0.004103, -0.004103, 0.216539);
  out.set_view({{1.022846, -3.177154, -2.174512}, at, {-0.816497, -0.816497, 0.816497}, 45.0});
  out.add_lights({{2.0, -18.0, -5.0}}, at);
  Pyramid pyramid{out, out.add_material(diffuse_material("tetra", {1.0f, 0.2f, 0.2f}))};
  pyramid.grow({0.0, 0.0, 0.0}, 1.0, size);
}

}  // namespace

const Generator kTetra{"tetra", {1, kMaxDepth}, tetra_triangles, build_tetra};

}  // namespace lancer::spd
