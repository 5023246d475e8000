// How a progressive render may end early or report on the way, so a long render is never
// lost: a stop flag (set by the program's SIGINT/SIGTERM handler), a time budget, and
// periodic checkpoints of the image so far.
#pragma once

#include <atomic>
#include <functional>

#include "render/image.h"
#include "render/render_state.h"

namespace lancer {

struct RenderControl {
  // Non-zero: stop within a few milliseconds (checked before each wavefront of at most four
  // 8x8 pixel blocks). The
  // image then averages, per pixel, the samples finished so far.
  const std::atomic<int>* stop = nullptr;
  // > 0: stop starting new work once this many seconds have passed since the start.
  double time_limit_s = 0.0;
  // > 0: after a pass over the image that ends at least this long after the previous
  // checkpoint (or the start), call on_checkpoint with the image so far, on the calling
  // thread, while no worker runs.
  double checkpoint_s = 0.0;
  std::function<void(const ImageRGB& image, int passes_done)> on_checkpoint;
  // Non-null: the render continues from *state (empty: starts afresh), which must come from a
  // render of the same scene with the same settings but perhaps a smaller spp (one process's
  // or a distributed one's: check_render_state), and leaves its
  // sums and counts there, so they can be saved and resumed (--resume); on_checkpoint may read
  // it. Not for IntegratorKind::Sppm, whose state is another (render_image throws).
  RenderState* state = nullptr;
};

}  // namespace lancer
