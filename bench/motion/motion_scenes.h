// What lancer-motion-bench traces: a synthetic scene of moving bunnies, the still version of
// a moving scene, shutter times for camera rays, and an exact reference for checking hits.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "accel/accelerator.h"
#include "scene/scene.h"

namespace lancer::bench {

// `n` copies of `bunny` (one mesh, drawn through instances), each moving over the shutter
// along its own straight line while it turns about the vertical by up to 1.5 radians,
// with kShutterSteps keys made by motion_key from the matrices (rotation and translation
// are interpolated exactly as Lancer does, so the keys describe the motion exactly).
Scene moving_bunnies(const Scene& bunny, int n);

// `scene` with every instance still where it is at shutter open.
Scene still_copy(Scene scene);

// Shutter time in [0, 1) of pixel (x, y), stratified per 8x8 tile (kRayTileSide): the 64
// pixels of a tile take the 64 strata [k/64, (k+1)/64) once each, k the bit-reversed
// row-major index in the tile (so neighbouring pixels lie far apart in time) XOR a hash of
// the tile (another permutation per tile), jittered inside the stratum by a hash of the
// pixel. Any tile, and so any 64-ray packet, covers the whole shutter evenly.
float stratified_time(int x, int y);

// Closest hits under motion with nothing shared with the two-level accelerator but the
// interpolation routine: every instance moved by instance_at to the ray's time, the ray
// taken into it by ray_to_object and traced in the mesh's own kd-tree; ties in t go to the
// lowest instance. Slow (every instance per ray): for a sample of rays.
class MotionReference {
 public:
  explicit MotionReference(const Scene& scene);  // `scene` must outlive this
  Hit intersect(const Ray& ray) const;

 private:
  const Scene& scene_;
  std::vector<std::unique_ptr<TriangleSoA>> meshes_;  // per mesh, its triangles
  std::vector<std::unique_ptr<Accelerator>> trees_;   // per mesh (one, of all triangles, when not instanced)
};

}  // namespace lancer::bench
