#include "accel/accel_factory.h"

#include <stdexcept>
#include <string>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "accel/two_level.h"

namespace lancer {

std::vector<std::string_view> accelerator_names() { return {"kdtree", "brute"}; }

std::vector<std::string_view> kd_split_names() { return {"sah", "middle", "median"}; }

std::string_view kd_split_name(KdSplit split) {
  switch (split) {
    case KdSplit::Sah: return "sah";
    case KdSplit::Middle: return "middle";
    case KdSplit::Median: return "median";
  }
  return "?";
}

std::optional<KdSplit> parse_kd_split(std::string_view name) {
  for (KdSplit s : {KdSplit::Sah, KdSplit::Middle, KdSplit::Median})
    if (kd_split_name(s) == name) return s;
  return std::nullopt;
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris,
                                              const KdBuildOptions& kd, Isa isa) {
  if (name == "kdtree") return std::make_unique<KdTree>(tris, kd, isa);
  if (name == "brute") return std::make_unique<BruteForce>(tris);
  throw std::invalid_argument("unknown accelerator '" + std::string(name) + "'");
}

std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris,
                                              const InstancedGeometry& geometry, const KdBuildOptions& kd, Isa isa) {
  if (geometry.empty()) return make_accelerator(name, tris, kd, isa);
  if (name != "kdtree" && name != "brute")
    throw std::invalid_argument("unknown accelerator '" + std::string(name) + "'");
  return std::make_unique<TwoLevelAccelerator>(tris, geometry, name, kd, isa);
}

}  // namespace lancer
