// Sobol' values for many samplers at once (SobolSampler's get1 and get2, bit for bit),
// several samplers per vector (sobol_batch-inl.h, one copy per ISA). The path tracer draws
// each live path's bounce values this way before shading the bounce (two single dimensions:
// the light's pick and the roulette; two pairs: the light point and the BSDF direction);
// one path at a time, their hashes and permutations were 6 % of a Cornell box render.
// The values are left in each sampler (SobolSampler::take_ahead), whose get1 and get2 then
// return them: the integrators keep asking the sampler, and get the same numbers.
#pragma once

#include <cstdint>

#include "render/sobol_sampler.h"
#include "simd/isa.h"

namespace lancer {

struct AheadRequest {
  SobolSampler* sampler = nullptr;
  std::uint32_t dim1[2] = {SobolSampler::kNoDimension, SobolSampler::kNoDimension};
  std::uint32_t dim2[2] = {SobolSampler::kNoDimension, SobolSampler::kNoDimension};
};

// For each request, the sampler's get1(dim1[k]) and get2(dim2[k]) drawn and left in it, with
// the drawer of `isa` (scalar: nothing is drawn ahead; get1 and get2 compute them later).
void draw_ahead(const AheadRequest* requests, int count, Isa isa);
// The same with the best ISA this CPU runs, chosen once.
void draw_ahead(const AheadRequest* requests, int count);

namespace sobol_batch {

inline constexpr int kMaxLanes = 64;

struct Lanes {
  alignas(64) std::uint64_t shuffle_key[kMaxLanes];
  alignas(64) std::uint64_t scramble_key[kMaxLanes];
  alignas(64) std::uint32_t reversed_index[kMaxLanes];
  alignas(64) std::uint32_t dim1[2][kMaxLanes];
  alignas(64) std::uint32_t dim2[2][kMaxLanes];
  const std::uint32_t* table[4];  // sobol::reversed_second_dimension_table(k)
};

struct Out {
  alignas(64) float v1[2][kMaxLanes];
  alignas(64) float v2x[2][kMaxLanes];
  alignas(64) float v2y[2][kMaxLanes];
};

// Lanes [0, count), padded by the caller to a multiple of 8.
using DrawLanesFn = void (*)(const Lanes& lanes, int count, Out& out);

}  // namespace sobol_batch
}  // namespace lancer
