// OutOfMemory names the size of a failed allocation; the big-block allocator throws it.
#include "simd/out_of_memory.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "simd/big_block_allocator.h"

namespace lancer {
namespace {

TEST(OutOfMemory, NamesTheSizeInBytesAndInTheNearestUnit) {
  EXPECT_STREQ(OutOfMemory(1300000000).what(), "could not allocate 1.21 GiB (1300000000 bytes)");
  EXPECT_STREQ(OutOfMemory(3u << 20).what(), "could not allocate 3.00 MiB (3145728 bytes)");
  EXPECT_STREQ(OutOfMemory(512).what(), "could not allocate 0.50 KiB (512 bytes)");
  EXPECT_EQ(OutOfMemory(77).bytes(), 77u);
}

TEST(OutOfMemory, MessageForAnyBadAlloc) {
  EXPECT_EQ(out_of_memory_message(OutOfMemory(2048)), "out of memory: could not allocate 2.00 KiB (2048 bytes)");
  EXPECT_EQ(out_of_memory_message(std::bad_alloc()),
            "out of memory (in a library allocation that does not say how much it asked for)");
}

TEST(BigBlockAllocator, AFailedMappingThrowsItsSize) {
  BigBlockAllocator<std::uint64_t> alloc;
  const std::size_t n = std::size_t(1) << 58;  // 2^61 bytes: more than any address space
  try {
    (void)alloc.allocate(n);
    FAIL() << "a 2^61-byte block was mapped";
  } catch (const OutOfMemory& e) {
    EXPECT_EQ(e.bytes(), n * sizeof(std::uint64_t));
  }
}

TEST(BigBlockAllocator, BigAndSmallBlocksHoldTheirElements) {
  for (std::size_t n : {std::size_t(100), kBigBlockBytes / sizeof(int) + 3}) {
    BigBlockVector<int> v;
    v.resize(n);  // left uninitialised: written below
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<int>(i * 7);
    BigBlockVector<int> copy = v;
    v = {};
    for (std::size_t i = 0; i < n; i += 997) ASSERT_EQ(copy[i], static_cast<int>(i * 7)) << n;
  }
}

}  // namespace
}  // namespace lancer
