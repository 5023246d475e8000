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
// was built in ascending ref order, that is exactly Event::operator<'s order.
inline void radix_sort_events(EventVector& events, EventVector& buffer) {
  constexpr int kShift[3] = {0, 12, 23};
  constexpr int kBits[3] = {12, 11, 11};
  buffer.resize(events.size());
  EventVector* src = &events;
  EventVector* dst = &buffer;
  std::uint32_t count[1u << 12];
  for (int pass = 0; pass < 3; ++pass) {
    const std::uint32_t mask = (1u << kBits[pass]) - 1;
    for (std::uint32_t d = 0; d <= mask; ++d) count[d] = 0;
    for (const Event& e : *src) ++count[(radix_key(e) >> kShift[pass]) & mask];
    std::uint32_t offset = 0;
    for (std::uint32_t d = 0; d <= mask; ++d) offset += std::exchange(count[d], offset);
    Event* out = dst->data();
    for (const Event& e : *src) out[count[(radix_key(e) >> kShift[pass]) & mask]++] = e;
    std::swap(src, dst);
  }
  events.swap(buffer);  // three passes: the sorted list is in `buffer`
}

}  // namespace lancer::kd
