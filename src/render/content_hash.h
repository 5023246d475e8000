// A fast 64-bit hash of bytes, to notice that a file or a saved render state is not the one
// expected (an edited scene, a damaged checkpoint). Not cryptographic: it detects accidents,
// not tampering. The value depends on the order and the boundaries of the add() calls.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace lancer {

class ContentHash {
 public:
  void add(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (; size >= 8; p += 8, size -= 8) {
      std::uint64_t word;
      std::memcpy(&word, p, 8);
      mix(word);
    }
    std::uint64_t tail = 0;
    if (size > 0) std::memcpy(&tail, p, size);  // p may be null for an empty vector's data()
    mix(tail ^ (std::uint64_t{size} << 56));  // marks where each add() ended
  }
  // Length first, so that ("ab", "c") and ("a", "bc") differ.
  void add(std::string_view text) {
    add_u64(text.size());
    add(text.data(), text.size());
  }
  void add_u64(std::uint64_t value) { mix(value); }

  std::uint64_t value() const {
    // The murmur3 finaliser: every input bit reaches every output bit.
    std::uint64_t h = state_;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
  }
  // value() as 16 lower-case hex digits.
  std::string hex() const {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string out(16, '0');
    const std::uint64_t v = value();
    for (int i = 0; i < 16; ++i) out[static_cast<std::size_t>(i)] = kDigits[(v >> (60 - 4 * i)) & 0xF];
    return out;
  }

 private:
  void mix(std::uint64_t word) {
    state_ = std::rotl(state_ ^ (word * 0x87c37b91114253d5ULL), 31) * 0x4cf5ad432745937fULL + 0x52dce729ULL;
  }
  std::uint64_t state_ = 0x6a09e667f3bcc909ULL;
};

}  // namespace lancer
