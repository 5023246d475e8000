// SPD "gears": an n x n x n block of meshing spur gears above a reflective square, some
// of them glass. Each gear face is a 144-corner concave polygon (36 teeth of 4 corners),
// which is what the SPD database stresses. Five lights, one just behind the eye.
//
// Gear radius R = 1 / (n - 0.05 (n - 1)); tips at 0.995 R and roots at 0.9 R, so
// neighbours 1.9 R apart mesh without touching (every other gear turned by half a
// tooth). A tooth spanning angle T = 10 degrees from angle a has its tip corners at
// a -+ 0.19 T and its root corners at a + 0.3 T and a + 0.7 T. Layers lie 1/n apart
// from z = 1 down; gears are min(0.1, 1/(2n)) thick. Each gear is a closed prism: its
// two faces fanned from the axis (the corners go round in angle order, so the outline
// is star-shaped around the axis and the fan covers it exactly) and 144 side quads.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

#include "scene/spd_common.h"

namespace lancer::spd {

namespace {

constexpr int kMaxGrid = 44;
constexpr int kTeeth = 36;
constexpr int kCorners = 4 * kTeeth;

std::uint64_t gears_triangles(int size, const SpdOptions&) {
  const auto n = std::uint64_t(size);
  return 4 * kCorners * n * n * n + 2;
}

struct Gear {
  glm::dvec3 centre;  // centre of the top face
  double turn;        // angle of the first tooth
  std::uint32_t material;
};

double fraction(double x) { return x - std::floor(x); }

// The SPD's pseudo-random gear colours: fractional parts of small integer combinations
// of the grid position, scaled so the largest channel is 1.
glm::vec3 gear_colour(int ix, int iy, int iz) {
  glm::dvec3 c(0.01 + fraction((ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0),
               0.01 + fraction((iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0),
               0.01 + fraction((iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0));
  return glm::vec3(c / std::max({c.x, c.y, c.z}));
}

void emit_gear(SpdEmitter& out, const Gear& g, double tip, double root, double thickness) {
  constexpr double kToothAngle = 2.0 * std::numbers::pi / kTeeth;
  constexpr std::array<double, 4> kAt = {-0.19, 0.19, 0.3, 0.7};  // in tooth angles
  std::array<glm::dvec3, kCorners + 1> top{}, bottom{};
  for (int t = 0; t < kTeeth; ++t)
    for (int k = 0; k < 4; ++k) {
      const double angle = g.turn + kToothAngle * (t + kAt[std::size_t(k)]);
      const double radius = k < 2 ? tip : root;
      const auto j = std::size_t(4 * t + k);
      top[j] = g.centre + glm::dvec3(radius * std::cos(angle), radius * std::sin(angle), 0.0);
      bottom[j] = top[j] - glm::dvec3(0.0, 0.0, thickness);
    }
  top[kCorners] = top[0];  // close the outline on identical corners
  bottom[kCorners] = bottom[0];
  const glm::dvec3 top_centre = g.centre, bottom_centre = g.centre - glm::dvec3(0.0, 0.0, thickness);
  for (std::size_t j = 0; j < kCorners; ++j) out.triangle(top_centre, top[j], top[j + 1], g.material);
  for (std::size_t j = 0; j < kCorners; ++j) out.triangle(bottom_centre, bottom[j + 1], bottom[j], g.material);
  for (std::size_t j = 0; j < kCorners; ++j) out.quad(top[j], bottom[j], bottom[j + 1], top[j + 1], g.material);
}

void build_gears(SpdEmitter& out, int size) {
  out.set_view({{-1.1, -2.1, 2.6}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0});
  out.add_lights({{2.0, 4.0, 4.0}, {-2.0, 4.0, 3.0}, {2.0, -2.5, 2.5}, {-1.0, -4.0, 2.0}, {-1.111, -2.121, 2.626}},
                 {0.0, 0.0, 0.0});

  // The ground is shiny in the SPD (Kd 0.3, Ks 0.6): a mirror here.
  const std::uint32_t ground = out.add_material(mirror_material("ground", {1.0f, 0.85f, 0.7f}));
  out.quad({2.0, 2.0, 0.0}, {-2.0, 2.0, 0.0}, {-2.0, -2.0, 0.0}, {2.0, -2.0, 0.0}, ground);

  const double n = size;
  const double radius = 1.0 / (n - 0.05 * (n - 1.0));
  const double thickness = std::min(0.1, 1.0 / (2.0 * n));
  // Gears with equal colour and kind share a material (there are at most 2 * 7^3
  // combinations); gears are emitted grouped by material, in grid order within each.
  std::map<std::tuple<float, float, float, bool>, std::uint32_t> materials;
  std::vector<Gear> gears;
  gears.reserve(std::size_t(size) * std::size_t(size) * std::size_t(size));
  for (int iz = 0; iz < size; ++iz)
    for (int iy = 0; iy < size; ++iy)
      for (int ix = 0; ix < size; ++ix) {
        const glm::vec3 colour = gear_colour(ix, iy, iz);
        const bool glass = (ix * 4 + iy * 2 + iz) % 5 == 0;  // SPD: Kd 0.2, T 0.8, ior 1.1
        const auto key = std::make_tuple(colour.r, colour.g, colour.b, glass);
        auto found = materials.find(key);
        if (found == materials.end()) {
          const std::string name = "gear " + std::to_string(materials.size());
          const Material m = glass ? glass_material(name, colour, 0.8f, 1.1f) : diffuse_material(name, colour);
          found = materials.emplace(key, out.add_material(m)).first;
        }
        const glm::dvec3 centre(-1.0 + radius + ix * 1.9 * radius, -1.0 + radius + iy * 1.9 * radius, 1.0 - iz / n);
        gears.push_back({centre, std::numbers::pi * ((ix + iy + iz) % 2) / kTeeth, found->second});
      }
  std::stable_sort(gears.begin(), gears.end(), [](const Gear& a, const Gear& b) { return a.material < b.material; });
  for (const Gear& g : gears) emit_gear(out, g, 0.995 * radius, 0.9 * radius, thickness);
}

}  // namespace

const Generator kGears{"gears", {1, kMaxGrid}, gears_triangles, build_gears};

}  // namespace lancer::spd
