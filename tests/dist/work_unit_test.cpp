// The byte images the ranks of a distributed render exchange (units with their tile's sums,
// results, a worker's Ready): every field survives the trip exactly, and bytes that pack did not write
// are refused rather than read past or turned into a unit no worker could render.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "dist/distributed_render.h"
#include "dist/work_unit.h"

namespace lancer {
namespace {

// Sums a text or rounded encoding would change: tiny, huge, negative zero, NaN, infinity.
TileSums sample_sums(std::size_t pixels) {
  TileSums sums;
  for (std::size_t i = 0; i < pixels; ++i) {
    sums.sum.emplace_back(std::ldexp(1.0 + 0.1 * double(i), int(i) * 40 - 200), -0.0, 1.0 / 3.0 + double(i));
    sums.count.push_back(static_cast<std::uint32_t>(7 * i + 1));
  }
  sums.sum[0].y = std::numeric_limits<double>::denorm_min();
  sums.sum[1].z = std::numeric_limits<double>::quiet_NaN();
  sums.sum[2].x = std::numeric_limits<double>::infinity();
  sums.count[3] = 0xffffffffu;
  return sums;
}

UnitTask sample_task() { return {WorkUnit{0xfedcba98u, 1234, 56, 200}, sample_sums(5)}; }

UnitResult sample_result() {
  UnitResult r;
  r.unit = {7, 3, 12, 4};
  r.passes_done = 3;
  r.sums = sample_sums(6);
  r.rays = 0x123456789abcull;
  r.primary_rays = 45;
  r.primary_seconds = 0.125;
  r.seconds = 1.0 / 3.0;
  r.threads = 6;
  return r;
}

void expect_same_bits(const TileSums& a, const TileSums& b) {
  ASSERT_EQ(a.sum.size(), b.sum.size());
  ASSERT_EQ(a.count, b.count);
  EXPECT_EQ(std::memcmp(a.sum.data(), b.sum.data(), a.sum.size() * sizeof(glm::dvec3)), 0)
      << "sums bit for bit (NaN and -0 included)";
}

// Overwrites the bytes at `offset` with `value` (the header's fields sit at the offsets of
// their struct; these tests find them by packing a changed copy, not by layout).
template <typename T>
std::vector<std::byte> with_field(std::vector<std::byte> bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof value);
  return bytes;
}

// Where two byte images differ first.
std::size_t first_difference(const std::vector<std::byte>& a, const std::vector<std::byte>& b) {
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] != b[i]) return i;
  return a.size();
}

TEST(WorkUnitBytes, TaskRoundTripKeepsEveryFieldAndEveryBit) {
  const UnitTask task = sample_task();
  const UnitTask back = unpack_task(pack(task));
  EXPECT_EQ(back.unit.id, task.unit.id);
  EXPECT_EQ(back.unit.tile, task.unit.tile);
  EXPECT_EQ(back.unit.first_pass, task.unit.first_pass);
  EXPECT_EQ(back.unit.passes, task.unit.passes);
  expect_same_bits(back.sums, task.sums);
}

TEST(WorkUnitBytes, TaskOfTheWrongSizeIsRefused) {
  const std::vector<std::byte> good = pack(sample_task());
  std::vector<std::byte> b = good;
  b.pop_back();
  EXPECT_THROW(unpack_task(b), std::runtime_error) << "a count cut short";
  b = good;
  b.resize(b.size() + sizeof(glm::dvec3) + sizeof(std::uint32_t));
  EXPECT_THROW(unpack_task(b), std::runtime_error) << "one pixel more than the header says";
  b = good;
  b.resize(sizeof(WorkUnit) + 3);
  EXPECT_THROW(unpack_task(b), std::runtime_error) << "the header cut short";
  EXPECT_THROW(unpack_task({}), std::runtime_error);
}

TEST(WorkUnitBytes, TaskWithoutPassesOrPixelsIsRefused) {
  for (const int passes : {0, -1, std::numeric_limits<int>::min()}) {
    UnitTask t = sample_task();
    t.unit.passes = passes;
    EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << passes << " passes";
  }
  UnitTask t = sample_task();
  t.unit.first_pass = -1;
  EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << "a negative first pass";
  t = sample_task();
  t.sums = {};
  EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << "no pixels";
  t = sample_task();
  t.unit.first_pass = 0, t.unit.passes = 1;
  EXPECT_NO_THROW(unpack_task(pack(t)));
}

// The pixel count in the header must match the bytes, however large it claims to be (no
// size computed from it may wrap around).
TEST(WorkUnitBytes, APixelCountThatDisagreesWithTheBytesIsRefused) {
  const UnitTask good = sample_task();
  UnitTask more = good;
  more.sums.sum.emplace_back(1.0);
  more.sums.count.push_back(1);
  const std::vector<std::byte> bytes = pack(good);
  const std::size_t at = first_difference(bytes, pack(more));
  ASSERT_LT(at + sizeof(std::uint64_t), bytes.size());
  EXPECT_EQ(unpack_task(with_field<std::uint64_t>(bytes, at, 5)).sums.sum.size(), 5u) << "found the field";
  for (const std::uint64_t pixels : {std::uint64_t{4}, std::uint64_t{6}, std::uint64_t{0}, ~std::uint64_t{0},
                                     std::uint64_t{1} << 62, (~std::uint64_t{0}) / 28 + 1})
    EXPECT_THROW(unpack_task(with_field<std::uint64_t>(bytes, at, pixels)), std::runtime_error) << pixels;
}

// A damaged unit must not make a worker allocate without bound: at most kMaxUnitPasses
// passes, kMaxUnitBytes of samples, and no pass beyond what a render may have.
TEST(WorkUnitBytes, UnitsBeyondTheLimitsAreRefused) {
  UnitTask t = sample_task();  // 5 pixels
  t.unit.first_pass = 0;
  t.unit.passes = kMaxUnitPasses;
  EXPECT_NO_THROW(unpack_task(pack(t)));
  t.unit.passes = kMaxUnitPasses + 1;
  EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << "too many passes";
  t.unit.passes = 4;
  t.unit.first_pass = kMaxUnitSpp - 4;
  EXPECT_NO_THROW(unpack_task(pack(t)));
  t.unit.first_pass = kMaxUnitSpp - 3;
  EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << "passes beyond the most a render has";
  t.unit.first_pass = std::numeric_limits<std::int32_t>::max();
  EXPECT_THROW(unpack_task(pack(t)), std::runtime_error) << "a first pass near the int limit";
  // 64 MiB of samples: kMaxUnitPasses passes of 21,846 pixels (12 bytes a sample) are too many.
  UnitTask big{WorkUnit{1, 0, 0, kMaxUnitPasses}, TileSums{std::vector<glm::dvec3>(21846), std::vector<std::uint32_t>(21846)}};
  EXPECT_THROW(unpack_task(pack(big)), std::runtime_error) << "samples beyond kMaxUnitBytes";
  big.unit.passes = 1;
  EXPECT_NO_THROW(unpack_task(pack(big)));
}

TEST(WorkUnitBytes, SumsAndCountsOfDifferentLengthsAreNotPacked) {
  UnitTask t = sample_task();
  t.sums.count.pop_back();
  EXPECT_THROW(pack(t), std::runtime_error);
}

TEST(WorkUnitBytes, ResultRoundTripKeepsEveryFieldAndEveryBit) {
  const UnitResult r = sample_result();
  const UnitResult back = unpack_result(pack(r));
  EXPECT_EQ(back.unit.id, r.unit.id);
  EXPECT_EQ(back.unit.tile, r.unit.tile);
  EXPECT_EQ(back.unit.first_pass, r.unit.first_pass);
  EXPECT_EQ(back.unit.passes, r.unit.passes);
  EXPECT_EQ(back.passes_done, r.passes_done);
  EXPECT_EQ(back.rays, r.rays);
  EXPECT_EQ(back.primary_rays, r.primary_rays);
  EXPECT_EQ(back.primary_seconds, r.primary_seconds);
  EXPECT_EQ(back.seconds, r.seconds);
  EXPECT_EQ(back.threads, r.threads);
  expect_same_bits(back.sums, r.sums);
  UnitResult none = r;
  none.passes_done = 0;
  EXPECT_EQ(unpack_result(pack(none)).passes_done, 0) << "a unit stopped before its first pass";
}

TEST(WorkUnitBytes, ResultOfTheWrongSizeIsRefused) {
  const std::vector<std::byte> good = pack(sample_result());
  std::vector<std::byte> b = good;
  b.pop_back();
  EXPECT_THROW(unpack_result(b), std::runtime_error) << "a count cut short";
  b = good;
  b.resize(b.size() - sizeof(glm::dvec3) - sizeof(std::uint32_t));
  EXPECT_THROW(unpack_result(b), std::runtime_error) << "one pixel missing";
  b = good;
  b.resize(40);
  EXPECT_THROW(unpack_result(b), std::runtime_error) << "the header cut short";
  EXPECT_THROW(unpack_result({}), std::runtime_error);
  EXPECT_THROW(unpack_result(pack(sample_task())), std::runtime_error) << "a task is not a result";
}

TEST(WorkUnitBytes, ResultWithImpossibleCountsIsRefused) {
  UnitResult r = sample_result();
  r.unit.passes = 2;  // 3 done
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "more passes done than asked";
  r = sample_result();
  r.unit.passes = 0;
  r.passes_done = 0;
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "a unit of no passes";
  r.unit.passes = -3;
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "a unit of negative passes";
  r = sample_result();
  r.unit.first_pass = -1;
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "a negative first pass";
  r = sample_result();
  r.passes_done = -1;
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "a negative count of passes done";
  r = sample_result();
  r.threads = 0;
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "no threads";
  r = sample_result();
  r.sums = {};
  EXPECT_THROW(unpack_result(pack(r)), std::runtime_error) << "no pixels";
}

TEST(WorkerReadyBytes, RoundTrip) {
  WorkerReady w;
  w.ok = false;
  w.threads = 12;
  w.load_s = 1.5;
  w.build_s = 0.25;
  w.host = "node-17.cluster";
  w.error = std::string("cannot read scene.gltf: ") + '\0' + "binary";
  w.facts = "0123456789abcdef";
  const WorkerReady back = unpack_ready(pack(w));
  EXPECT_EQ(back.facts, w.facts);
  EXPECT_EQ(back.ok, w.ok);
  EXPECT_EQ(back.threads, w.threads);
  EXPECT_EQ(back.load_s, w.load_s);
  EXPECT_EQ(back.build_s, w.build_s);
  EXPECT_EQ(back.host, w.host);
  EXPECT_EQ(back.error, w.error);
  w.ok = true;
  w.error.clear();
  EXPECT_TRUE(unpack_ready(pack(w)).ok);
}

TEST(WorkerReadyBytes, CutShortOrTooLongIsRefused) {
  WorkerReady w;
  w.host = "h";
  w.error = "e";
  w.facts = "f";
  const std::vector<std::byte> good = pack(w);
  std::vector<std::byte> longer = good;
  longer.push_back(std::byte{0});
  EXPECT_THROW(unpack_ready(longer), std::runtime_error);
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(unpack_ready(std::vector<std::byte>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n))),
                 std::runtime_error)
        << n << " of " << good.size() << " bytes";
}

}  // namespace
}  // namespace lancer
