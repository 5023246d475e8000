// `lancer trace`: answer the rays of a ray file (render/ray_file.h) on a scene, write the
// hits (or occlusion answers) and print the rate, so a benchmark runs on exactly the rays
// someone cares about.
#pragma once

#include <iosfwd>
#include <string>

#include "render/render_settings.h"
#include "scene/scene.h"

namespace lancer {

struct TraceOptions {
  std::string scene;
  std::string rays;  // input ray file
  std::string hits;  // output: hit file, or occlusion file with `occlusion`
  TraceMode mode = TraceMode::Packet;
  std::string isa;  // empty: the best this CPU supports
  InstancingMode instancing = InstancingMode::Auto;  // --instancing
  int threads = 0;  // 0: all cores
  bool occlusion = false;
};

// Returns the process exit code (0, or 1 with the message on `err`); the summary line and
// a line with the kd-tree's single-ray work per ray (measure_kd_work) go to `out`. Packet mode traces each run of 64 consecutive rays with one
// Accelerator::intersect_packet call, single mode calls intersect per ray, occlusion
// calls occluded per ray in both modes. The answers never depend on mode or threads.
int run_trace(const TraceOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
