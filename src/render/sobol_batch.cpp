#include "render/sobol_batch.h"


namespace lancer {

// The per-ISA draws (sobol_batch_<isa>.cpp); nothing here is built with ISA flags.
#if defined(__x86_64__) || defined(_M_X64)
namespace sse4 {
void draw_sobol_lanes(const sobol_batch::Lanes& lanes, int count, sobol_batch::Out& out);
}
namespace avx2 {
void draw_sobol_lanes(const sobol_batch::Lanes& lanes, int count, sobol_batch::Out& out);
}
namespace avx512 {
void draw_sobol_lanes(const sobol_batch::Lanes& lanes, int count, sobol_batch::Out& out);
}
#endif

namespace {

using namespace sobol_batch;

DrawLanesFn drawer_for(Isa isa) {
#if defined(__x86_64__) || defined(_M_X64)
  return isa_version<DrawLanesFn>(isa, "draw_ahead", &sse4::draw_sobol_lanes, &avx2::draw_sobol_lanes,
                                  &avx512::draw_sobol_lanes);
#else
  return isa_version<DrawLanesFn>(isa, "draw_ahead", nullptr, nullptr, nullptr);
#endif
}

constexpr int kPadLanes = 8;  // the widest draw's vector

}  // namespace

void draw_ahead(const AheadRequest* requests, int count) {
  static const Isa best = best_supported_isa();  // probed once, not per bounce
  draw_ahead(requests, count, best);
}

void draw_ahead(const AheadRequest* requests, int count, Isa isa) {
  const DrawLanesFn draw = drawer_for(isa);
  if (!draw) return;  // scalar: get1 and get2 compute each value when it is asked for
  alignas(64) Lanes lanes;
  alignas(64) Out out;
  for (int k = 0; k < 4; ++k) lanes.table[k] = sobol::reversed_second_dimension_table(k);
  for (int first = 0; first < count; first += kMaxLanes) {
    const int n = count - first < kMaxLanes ? count - first : kMaxLanes;
    int l = 0;
    for (; l < n; ++l) {
      const AheadRequest& r = requests[first + l];
      const SobolSampler::Keys keys = r.sampler->keys();
      lanes.shuffle_key[l] = keys.shuffle;
      lanes.scramble_key[l] = keys.scramble;
      lanes.reversed_index[l] = keys.reversed_index;
      for (int k = 0; k < 2; ++k) {
        lanes.dim1[k][l] = r.dim1[k];
        lanes.dim2[k][l] = r.dim2[k];
      }
    }
    for (; l % kPadLanes != 0; ++l) {  // the last vector's unused lanes repeat lane 0
      lanes.shuffle_key[l] = lanes.shuffle_key[0];
      lanes.scramble_key[l] = lanes.scramble_key[0];
      lanes.reversed_index[l] = lanes.reversed_index[0];
      for (int k = 0; k < 2; ++k) {
        lanes.dim1[k][l] = lanes.dim1[k][0];
        lanes.dim2[k][l] = lanes.dim2[k][0];
      }
    }
    draw(lanes, l, out);
    for (int i = 0; i < n; ++i) {
      const AheadRequest& r = requests[first + i];
      const float v1[2] = {out.v1[0][i], out.v1[1][i]};
      const glm::vec2 v2[2] = {glm::vec2(out.v2x[0][i], out.v2y[0][i]), glm::vec2(out.v2x[1][i], out.v2y[1][i])};
      r.sampler->take_ahead(r.dim1, v1, r.dim2, v2);
    }
  }
}

}  // namespace lancer
