// libFuzzer target for the ray-file readers (src/render/ray_file.h): each input is
// written to a scratch file and read as a ray file, a hit file and an occlusion file.
// A RayFileError is the expected answer to bad input; anything else (a crash, a
// sanitizer report, another exception, a result that breaks the format's promises
// checked below) is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.h"
#include "render/ray_file.h"

namespace {

using lancer::fuzz::require;

// read_rays promises: one ray per 32 bytes, no NaN anywhere, and tfar either below
// kUnboundedTfar or +inf.
void check_rays(const std::vector<lancer::Ray>& rays, std::size_t size) {
  require(size % lancer::kRayRecordBytes == 0 && rays.size() == size / lancer::kRayRecordBytes,
          "read_rays accepted a size that is not a whole number of rays, or lost rays");
  for (const lancer::Ray& r : rays) {
    const float fields[8] = {r.org.x, r.org.y, r.org.z, r.tnear, r.dir.x, r.dir.y, r.dir.z, r.tfar};
    for (float f : fields) require(!std::isnan(f), "read_rays returned a NaN");
    require(r.tfar < lancer::kUnboundedTfar || r.tfar == lancer::kInfinity, "an unbounded tfar was not made +inf");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  lancer::fuzz::mute_std_cerr();
  (void)lancer::fuzz::scratch_dir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = lancer::fuzz::scratch_dir() / "input.rays";
  lancer::fuzz::write_file(path, std::string_view(reinterpret_cast<const char*>(data), size));
  try {
    check_rays(lancer::read_rays(path), size);
  } catch (const lancer::RayFileError&) {
  }
  try {
    const std::vector<lancer::HitRecord> hits = lancer::read_hits(path);
    require(size % lancer::kHitRecordBytes == 0 && hits.size() == size / lancer::kHitRecordBytes,
            "read_hits accepted a size that is not a whole number of records, or lost records");
  } catch (const lancer::RayFileError&) {
  }
  try {
    const std::vector<std::uint8_t> occluded = lancer::read_occlusion(path);
    require(occluded.size() == size, "read_occlusion returned a different number of rays than bytes");
  } catch (const lancer::RayFileError&) {
  }
  return 0;
}
