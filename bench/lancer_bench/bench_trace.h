// One timed pass of lancer-bench: every ray of a set traced once, on a task arena's
// threads, in the 64-ray chunks of render/ray_batch.h (an 8x8 pixel tile of the
// tile-ordered sets), by Lancer's kd-tree or by Embree.
#pragma once

#include <tbb/task_arena.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_options.h"
#include "embree_tracer.h"

namespace lancer::bench {

// The answers of one pass: closest hits, or occlusion bytes (1: blocked).
struct Answers {
  std::vector<Hit> hits;
  std::vector<std::uint8_t> occluded;
};

// What Lancer's `mode` (Packet or Single) calls for closest hits or occlusion, in words.
// Occlusion has no packet kernel: both modes call KdTree::occluded per ray.
std::string lancer_call_name(Mode mode, bool occlusion);

// Traces every ray with Lancer in `mode` and returns the wall time in seconds; `out` is
// resized as needed.
double trace_lancer(const KdTree& kd, Mode mode, bool occlusion, std::span<const Ray> rays, tbb::task_arena& arena,
                    Answers& out);

// The same with an Embree call (an Occluded* call answers occlusion); each 64-ray chunk
// goes to EmbreeScene::intersect/occluded, 16 rays per call for the 16-wide calls.
double trace_embree(const EmbreeScene& scene, EmbreeCall call, std::span<const Ray> rays, tbb::task_arena& arena,
                    Answers& out);

}  // namespace lancer::bench
