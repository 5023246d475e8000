// How a progressive render may end early or report on the way, so a long render is never
// lost: a stop flag (set by the program's SIGINT/SIGTERM handler), a time budget, and
// periodic checkpoints of the image so far.
#pragma once

#include <atomic>
#include <functional>

#include "render/image.h"

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
};

}  // namespace lancer
