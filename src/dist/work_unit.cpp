#include "dist/work_unit.h"

#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace lancer {

namespace {

struct TaskHeader {
  WorkUnit unit;
  std::uint64_t pixels;
};

struct ResultHeader {
  WorkUnit unit;
  std::int32_t passes_done;
  std::int32_t threads;
  std::uint64_t pixels;
  std::uint64_t rays;
  std::uint64_t primary_rays;
  double primary_seconds;
  double seconds;
};
static_assert(std::is_trivially_copyable_v<TaskHeader> && std::is_trivially_copyable_v<ResultHeader>);
static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));

constexpr std::size_t kPixelBytes = sizeof(glm::dvec3) + sizeof(std::uint32_t);

[[noreturn]] void damaged(const std::string& what) { throw std::runtime_error("distributed render: " + what); }

template <class Header>
std::vector<std::byte> pack_with(const Header& h, const TileSums& sums) {
  if (sums.sum.size() != sums.count.size()) damaged("a tile's sums and counts differ in length");
  const std::size_t n = sums.sum.size();
  std::vector<std::byte> bytes(sizeof h + n * kPixelBytes);
  std::byte* at = bytes.data();
  std::memcpy(at, &h, sizeof h);
  at += sizeof h;
  if (n > 0) {
    std::memcpy(at, sums.sum.data(), n * sizeof(glm::dvec3));
    std::memcpy(at + n * sizeof(glm::dvec3), sums.count.data(), n * sizeof(std::uint32_t));
  }
  return bytes;
}

template <class Header>
Header unpack_with(const std::vector<std::byte>& bytes, TileSums& sums) {
  Header h;
  if (bytes.size() < sizeof h) damaged("a message shorter than its header");
  std::memcpy(&h, bytes.data(), sizeof h);
  if (h.pixels == 0 || h.pixels > (bytes.size() - sizeof h) / kPixelBytes ||
      bytes.size() != sizeof h + h.pixels * kPixelBytes)
    damaged("a message of " + std::to_string(bytes.size()) + " bytes for " + std::to_string(h.pixels) + " pixels");
  if (h.unit.passes < 1 || h.unit.first_pass < 0 || h.unit.passes > kMaxUnitPasses ||
      h.unit.first_pass > kMaxUnitSpp - h.unit.passes ||
      static_cast<std::uint64_t>(h.unit.passes) * h.pixels * 3 * sizeof(float) > kMaxUnitBytes)
    damaged("a unit of " + std::to_string(h.unit.passes) + " passes from pass " + std::to_string(h.unit.first_pass) +
            " over " + std::to_string(h.pixels) + " pixels");
  const std::size_t n = h.pixels;
  sums.sum.resize(n);
  sums.count.resize(n);
  const std::byte* at = bytes.data() + sizeof h;
  std::memcpy(sums.sum.data(), at, n * sizeof(glm::dvec3));
  std::memcpy(sums.count.data(), at + n * sizeof(glm::dvec3), n * sizeof(std::uint32_t));
  return h;
}

}  // namespace

std::vector<std::byte> pack(const UnitTask& task) {
  return pack_with(TaskHeader{task.unit, task.sums.sum.size()}, task.sums);
}

UnitTask unpack_task(const std::vector<std::byte>& bytes) {
  UnitTask task;
  task.unit = unpack_with<TaskHeader>(bytes, task.sums).unit;
  return task;
}

std::vector<std::byte> pack(const UnitResult& r) {
  return pack_with(ResultHeader{r.unit, r.passes_done, r.threads, r.sums.sum.size(), r.rays, r.primary_rays,
                                r.primary_seconds, r.seconds},
                   r.sums);
}

UnitResult unpack_result(const std::vector<std::byte>& bytes) {
  UnitResult r;
  const ResultHeader h = unpack_with<ResultHeader>(bytes, r.sums);
  if (h.passes_done < 0 || h.passes_done > h.unit.passes || h.threads < 1)
    damaged("a result with " + std::to_string(h.passes_done) + " of " + std::to_string(h.unit.passes) +
            " passes done by " + std::to_string(h.threads) + " threads");
  r.unit = h.unit, r.passes_done = h.passes_done, r.threads = h.threads;
  r.rays = h.rays, r.primary_rays = h.primary_rays, r.primary_seconds = h.primary_seconds, r.seconds = h.seconds;
  return r;
}

}  // namespace lancer
