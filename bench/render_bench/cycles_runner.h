// Blender's Cycles as the reference path tracer of `lancer bench --render`: runs
// bench/cycles/cycles_render.py in `blender -b` and reads what it printed.
#pragma once

#include <filesystem>
#include <string>

namespace lancer::bench {

struct CyclesJob {
  std::filesystem::path scene, output;  // a .gltf/.glb file; the .exr to write
  int size = 256, spp = 64;
  int max_depth = 64;  // Lancer's --max-depth: Cycles is given max_bounces = max_depth - 1
  int threads = 2, seed = 0;
};

// Whether `blender` can be run (found on PATH or as a path).
bool blender_available(const std::string& blender);

// Renders `job`; returns the seconds of Cycles' render call (import and saving not
// included). Throws std::runtime_error with Blender's last output lines when it fails.
double run_cycles(const std::string& blender, const std::filesystem::path& script, const CyclesJob& job);

}  // namespace lancer::bench
