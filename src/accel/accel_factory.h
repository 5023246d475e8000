// Builds an accelerator by name (`--accel`, `--kd-split`), so the program and the
// benchmarks pick one without knowing the concrete classes.
#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "accel/accelerator.h"
#include "accel/instances.h"
#include "accel/kd_build.h"
#include "simd/isa.h"

namespace lancer {

// Names accepted by make_accelerator, the default first.
std::vector<std::string_view> accelerator_names();

std::vector<std::string_view> kd_split_names();
std::string_view kd_split_name(KdSplit split);
std::optional<KdSplit> parse_kd_split(std::string_view name);

// Throws std::invalid_argument for an unknown name, or an ISA this CPU lacks. `tris` must
// outlive the result. `kd` and `isa` apply to the kd-tree (the oracle is scalar).
std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris,
                                              const KdBuildOptions& kd = {}, Isa isa = best_supported_isa());

// The same for a scene drawn through instances: with empty `geometry` exactly the overload
// above; otherwise a TwoLevelAccelerator whose meshes each get an accelerator called
// `name` ("kdtree" or "brute"). `tris` must outlive the result only in the empty case.
std::unique_ptr<Accelerator> make_accelerator(std::string_view name, const TriangleSoA& tris,
                                              const InstancedGeometry& geometry, const KdBuildOptions& kd = {},
                                              Isa isa = best_supported_isa());

}  // namespace lancer
