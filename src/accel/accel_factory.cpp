#include "accel/accel_factory.h"

#include <stdexcept>
#include <string>

#include "accel/brute_force.h"

namespace lancer {

std::vector<std::string_view> accelerator_names() { return {"brute"}; }

std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris) {
  if (name == "brute") return std::make_unique<BruteForce>(tris);
  throw std::invalid_argument("unknown accelerator '" + std::string(name) + "'");
}

}  // namespace lancer
