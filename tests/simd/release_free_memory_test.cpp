// release_free_memory hands freed heap blocks back: a test, because for months it compiled
// to nothing (the __GLIBC__ test came before any header that defines it).
#include "simd/release_free_memory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "simd/process_memory.h"

namespace lancer {
namespace {

TEST(ReleaseFreeMemory, HandsAHoleInTheHeapBack) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "only glibc's malloc has a way to hand freed blocks back (malloc_trim)";
#elif defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's malloc, which malloc_trim trims";
#else
  if (resident_bytes() < 0) GTEST_SKIP() << "no /proc/self/status here";
  // 32 MiB in 64 KiB blocks (under malloc's mmap threshold, so from the heap), touched,
  // then a small block above them that stays: once the big ones are freed they are a hole
  // in the heap, which free() itself keeps (it trims only the heap's top).
  constexpr std::size_t kBlock = std::size_t(64) << 10, kBlocks = 512;
  std::vector<void*> blocks;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(std::malloc(kBlock));
    ASSERT_NE(blocks.back(), nullptr);
    std::memset(blocks.back(), 1, kBlock);
  }
  void* above = std::malloc(64);
  std::memset(above, 1, 64);
  release_free_memory();  // whatever earlier tests left, so that only the hole counts below
  for (void* b : blocks) std::free(b);
  const std::int64_t with_hole = resident_bytes();
  EXPECT_TRUE(release_free_memory()) << "malloc_trim reported nothing handed back";
  const std::int64_t after = resident_bytes();
  std::free(above);
  EXPECT_LE(after, with_hole - std::int64_t(kBlocks * kBlock / 2))
      << "resident " << with_hole << " bytes with the hole, " << after << " after";
#endif
}

}  // namespace
}  // namespace lancer
