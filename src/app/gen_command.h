// `lancer gen`: write a generated scene to a file (today: the SPD databases as .glb).
#pragma once

#include <iosfwd>
#include <string>

#include "scene/spd.h"

namespace lancer {

struct GenOptions {
  std::string kind = "spd";  // the generator family; only "spd" so far
  std::string name;          // balls, gears, mount, rings or tetra
  int size = 0;              // the SPD size factor (see scene/spd.h for each range)
  std::string output;        // a .glb file
  SpdOptions tessellation;   // sphere subdivisions and cylinder sides
};

// Builds the scene and writes it. On success prints
// "wrote FILE: N triangles (spd NAME, size S)" to `out` and returns 0; on any error
// prints "lancer: error: ..." to `err` and returns 1.
int run_gen(const GenOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
