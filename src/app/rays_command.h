// `lancer rays`: write one of the standard ray sets (render/ray_sets.h) of a scene to a
// ray file, for `lancer trace` or any other tracer to answer.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>

#include "render/ray_sets.h"

namespace lancer {

struct RaysOptions {
  std::string scene;
  RaySet set = RaySet::Primary;
  std::string output;
  int width = 512;   // multiples of kRayTileSide
  int height = 512;
  std::uint64_t seed = 0;
};

// Returns the process exit code (0, or 1 with the message on `err`); the summary line
// goes to `out`.
int run_rays(const RaysOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
