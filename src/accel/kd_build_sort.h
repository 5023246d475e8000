// Sorting sweep events: a stable least-significant-digit radix sort (three passes over a
// 34-bit key), used for long lists, where it beats a comparison sort several times over.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "accel/kd_build_types.h"

namespace lancer::kd {

// The order of (pos, type) as an unsigned integer: IEEE bits flipped so that integers
// compare like the floats (finite positions only), with -0 and +0 mapped to one key since
// they compare equal as floats.
inline std::uint64_t radix_key(const Event& e) {
  std::uint32_t b = std::bit_cast<std::uint32_t>(e.pos);
  if ((b & 0x7FFFFFFFu) == 0) b = 0;
  b = (b & 0x80000000u) ? ~b : (b | 0x80000000u);
  return (std::uint64_t(b) << 2) | e.type();
}

// Below this many events std::sort is faster (the radix sort clears 4096 counters a pass).
inline constexpr std::size_t kRadixSortMin = 1024;

// Sorts `events` by (pos, type), keeping the given order among equal keys. When the list
// was built in ascending ref order, that is exactly Event::operator<'s order. The three
// digit histograms are counted in one pass over the list, then three scatter passes.
inline void radix_sort_events(EventVector& events, EventVector& buffer) {
  constexpr int kShift[3] = {0, 12, 23};
  constexpr std::uint32_t kMask[3] = {(1u << 12) - 1, (1u << 11) - 1, (1u << 11) - 1};
  buffer.resize(events.size());
  static thread_local std::uint32_t count[3][1u << 12];
  for (int pass = 0; pass < 3; ++pass)
    for (std::uint32_t d = 0; d <= kMask[pass]; ++d) count[pass][d] = 0;
  for (const Event& e : events) {
    const std::uint64_t key = radix_key(e);
    for (int pass = 0; pass < 3; ++pass) ++count[pass][(key >> kShift[pass]) & kMask[pass]];
  }
  EventVector* src = &events;
  EventVector* dst = &buffer;
  for (int pass = 0; pass < 3; ++pass) {
    std::uint32_t* c = count[pass];
    std::uint32_t offset = 0;
    for (std::uint32_t d = 0; d <= kMask[pass]; ++d) offset += std::exchange(c[d], offset);
    Event* out = dst->data();
    for (const Event& e : *src) out[c[(radix_key(e) >> kShift[pass]) & kMask[pass]]++] = e;
    std::swap(src, dst);
  }
  events.swap(buffer);  // three passes: the sorted list is in `buffer`
}

}  // namespace lancer::kd
