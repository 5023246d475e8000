// The SPD generator table: name lookup, argument checks and the triangle cap, shared
// by spd_triangle_count and make_spd so both refuse the same inputs the same way.
#include "scene/spd.h"

#include <array>
#include <stdexcept>
#include <string>

#include "scene/spd_common.h"

namespace lancer {

namespace {

const std::array<const spd::Generator*, 5>& generators() {
  static const std::array<const spd::Generator*, 5> table = {&spd::kBalls, &spd::kGears, &spd::kMount, &spd::kRings,
                                                             &spd::kTetra};
  return table;
}

const spd::Generator& find_generator(std::string_view name) {
  for (const spd::Generator* g : generators())
    if (name == g->name) return *g;
  throw std::invalid_argument("unknown SPD scene '" + std::string(name) +
                              "' (expected balls, gears, mount, rings or tetra)");
}

std::string range_text(int lo, int hi) { return std::to_string(lo) + ".." + std::to_string(hi); }

// Checks size and options; returns the generator.
const spd::Generator& checked(std::string_view name, int size, const SpdOptions& options) {
  const spd::Generator& g = find_generator(name);
  const std::string who = "spd " + std::string(g.name) + ": ";
  if (size < g.sizes.min || size > g.sizes.max)
    throw std::invalid_argument(who + "size " + std::to_string(size) +
                                " is out of range (valid sizes: " + range_text(g.sizes.min, g.sizes.max) + ")");
  if (options.sphere_subdivisions < kSpdMinSphereSubdivisions ||
      options.sphere_subdivisions > kSpdMaxSphereSubdivisions)
    throw std::invalid_argument(
        who + "sphere subdivisions " + std::to_string(options.sphere_subdivisions) +
        " out of range (valid: " + range_text(kSpdMinSphereSubdivisions, kSpdMaxSphereSubdivisions) + ")");
  if (options.cylinder_sides < kSpdMinCylinderSides || options.cylinder_sides > kSpdMaxCylinderSides)
    throw std::invalid_argument(who + "cylinder sides " + std::to_string(options.cylinder_sides) +
                                " out of range (valid: " + range_text(kSpdMinCylinderSides, kSpdMaxCylinderSides) +
                                ")");
  return g;
}

}  // namespace

const std::vector<std::string_view>& spd_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> out;
    for (const spd::Generator* g : generators()) out.emplace_back(g->name);
    return out;
  }();
  return names;
}

SpdSizeRange spd_size_range(std::string_view name) { return find_generator(name).sizes; }

std::uint64_t spd_triangle_count(std::string_view name, int size, const SpdOptions& options) {
  return checked(name, size, options).triangles(size, options);
}

Scene make_spd(std::string_view name, int size, const SpdOptions& options) {
  const spd::Generator& g = checked(name, size, options);
  const std::uint64_t count = g.triangles(size, options);
  if (count > kSpdMaxTriangles)
    throw std::invalid_argument("spd " + std::string(g.name) + ": size " + std::to_string(size) + " with " +
                                std::to_string(options.sphere_subdivisions) + " sphere subdivisions and " +
                                std::to_string(options.cylinder_sides) + " cylinder sides gives " +
                                std::to_string(count) + " triangles, more than the limit of " +
                                std::to_string(kSpdMaxTriangles) + " (lower the size or the tessellation)");
  Scene scene;
  spd::SpdEmitter emitter(scene, g.name, size, count, options);
  g.build(emitter, size);
  emitter.finish();
  return scene;
}

}  // namespace lancer
