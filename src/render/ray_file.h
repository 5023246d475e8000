// Ray files and their answers, so anyone can measure Lancer on exactly the rays they care
// about (`lancer rays` writes them, `lancer trace` answers them; docs/ray-files.md).
//
// Little-endian, no header:
//   ray file        8 float32 per ray: ox oy oz tnear dx dy dz tfar. A tfar at or above
//                   kUnboundedTfar (3.4e38, +inf included) means unbounded.
//   hit file        per ray, float32 t (+inf when none), then uint32 triangle id
//                   (0xFFFFFFFF when none): 8 bytes.
//   occlusion file  per ray, one uint8: 1 when occluded, 0 when not.
// Every failure throws RayFileError naming the file; files are written atomically.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/ray.h"

namespace lancer {

// The one exception of ray-file I/O; what() is "<file>: <problem>".
class RayFileError : public std::runtime_error {
 public:
  RayFileError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + problem), file_(file), problem_(problem) {}

  const std::filesystem::path& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::filesystem::path file_;
  std::string problem_;
};

inline constexpr std::size_t kRayRecordBytes = 32;
inline constexpr std::size_t kHitRecordBytes = 8;
// tfar values at or above this (the largest float is about 3.40282e38) read as +inf.
inline constexpr float kUnboundedTfar = 3.4e38f;
// Ray files holding more rays than this are refused before any allocation.
inline constexpr std::uint64_t kMaxRayFileRays = std::uint64_t{1} << 31;

// One answer of the hit file: t and the triangle id, or +inf and kNoHit for a miss.
struct HitRecord {
  float t = kInfinity;
  std::uint32_t id = kNoHit;

  friend bool operator==(const HitRecord&, const HitRecord&) = default;
};

// The hit file's record for `hit`. `source_triangle_id` maps the accelerator's triangle
// index to the id written (Scene::source_triangle_id); a miss becomes {+inf, kNoHit}.
// Throws std::out_of_range for a hit on a triangle the map does not know.
HitRecord make_hit_record(const Hit& hit, std::span<const std::uint32_t> source_triangle_id);

// Reads every ray of `file`, with tfar >= kUnboundedTfar turned into +inf. Throws
// RayFileError for a missing or unreadable file, an empty file, a size that is not a
// multiple of 32 bytes, more than kMaxRayFileRays rays, or a NaN anywhere (naming the ray
// index, the field and its byte offset). Infinities and tnear > tfar are valid rays.
std::vector<Ray> read_rays(const std::filesystem::path& file);

// Writes `rays` to `file` ("<file>.tmp" first, flushed, then renamed over `file`, so an
// interrupted program never leaves a partial file under the final name). Unbounded rays
// (tfar = +inf) are written as +inf. Throws RayFileError with the OS reason on failure.
void write_rays(const std::filesystem::path& file, std::span<const Ray> rays);

// The hit file: 8 bytes per ray, written atomically like write_rays.
void write_hits(const std::filesystem::path& file, std::span<const HitRecord> hits);
// Reads a hit file back (for tests and tools). Throws RayFileError for a missing file or
// a size that is not a multiple of 8 bytes.
std::vector<HitRecord> read_hits(const std::filesystem::path& file);

// The occlusion file: one byte per ray, 1 when occluded (any non-zero input counts as 1).
void write_occlusion(const std::filesystem::path& file, std::span<const std::uint8_t> occluded);
std::vector<std::uint8_t> read_occlusion(const std::filesystem::path& file);

}  // namespace lancer
