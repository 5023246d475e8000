// Builds an accelerator by name (`--accel`), so the program and the benchmarks pick one
// without knowing the concrete classes.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"

namespace lancer {

// Names accepted by make_accelerator, the default first.
std::vector<std::string_view> accelerator_names();

// Throws std::invalid_argument for an unknown name. `tris` must outlive the result.
std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris);

}  // namespace lancer
