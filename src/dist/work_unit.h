// The unit of work of a distributed render: some consecutive passes (sample indices) over
// one tile. The tile's per-pixel sums and counts travel with it and come back with the new
// samples added in pass order, exactly as one process adds them (sum += double(sample),
// sample s only onto a pixel that has s), so the image stays bit-identical. What travels is
// 28 bytes a pixel each way, however many passes the unit holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace lancer {

// A unit holds at most this many passes, and its samples, which the worker keeps until it
// adds them, at most this many bytes (12 a sample); a unit beyond either is refused.
inline constexpr int kMaxUnitPasses = 256;
inline constexpr std::size_t kMaxUnitBytes = std::size_t{64} << 20;
// Passes a render may have (lancer render's most --spp).
inline constexpr int kMaxUnitSpp = 1 << 20;

struct WorkUnit {
  std::uint32_t id = 0;    // unique within a render
  std::uint32_t tile = 0;  // index into the render's tiles
  std::int32_t first_pass = 0;
  std::int32_t passes = 0;  // at least 1
};

// A tile's part of a RenderState: per pixel, row-major in the tile.
struct TileSums {
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> count;
};

// Rank 0 -> a worker.
struct UnitTask {
  WorkUnit unit;
  TileSums sums;
};

// A worker -> rank 0.
struct UnitResult {
  WorkUnit unit;
  // Passes added, from first_pass on: fewer than unit.passes when the worker was told to
  // stop (a pass left unfinished is not added).
  std::int32_t passes_done = 0;
  TileSums sums;
  std::uint64_t rays = 0;          // every ray traced for the unit
  std::uint64_t primary_rays = 0;  // its camera rays
  double primary_seconds = 0.0;    // thread-seconds inside the camera-ray tracing calls
  double seconds = 0.0;            // wall time the worker spent on the unit
  std::int32_t threads = 1;        // threads the worker rendered it with
};

// Byte images for the transport (the same binary on every rank: native byte order).
std::vector<std::byte> pack(const UnitTask& task);
std::vector<std::byte> pack(const UnitResult& result);
// Throw std::runtime_error when the bytes are not what pack wrote (size, counts) or hold a
// unit beyond the limits above.
UnitTask unpack_task(const std::vector<std::byte>& bytes);
UnitResult unpack_result(const std::vector<std::byte>& bytes);

}  // namespace lancer
