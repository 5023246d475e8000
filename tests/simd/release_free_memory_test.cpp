// release_free_memory hands freed heap blocks back: a test, because for months it compiled
// to nothing (the __GLIBC__ test came before any header that defines it).
#include "simd/release_free_memory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <cstring>
#include <vector>

#include "simd/process_memory.h"
#include "test_sanitizer.h"

namespace lancer {
namespace {

TEST(ReleaseFreeMemory, HandsAHoleInTheHeapBack) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "only glibc's malloc has a way to hand freed blocks back (malloc_trim)";
#else
  if (test::kAddressSanitized) GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's malloc, which malloc_trim trims";
  if (resident_bytes() < 0) GTEST_SKIP() << "no /proc/self/status here";
  // 32 MiB in 64 KiB blocks (under malloc's mmap threshold, so from the heap), touched and
  // freed while free() is told never to trim (a trim threshold above the heap): whatever
  // the heap looked like before, only release_free_memory can then hand them back.
  constexpr std::size_t kBlock = std::size_t(64) << 10, kBlocks = 512;
  std::vector<void*> blocks;
  blocks.reserve(kBlocks);
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(std::malloc(kBlock));
    ASSERT_NE(blocks.back(), nullptr);
    std::memset(blocks.back(), 1, kBlock);
  }
  release_free_memory();  // whatever earlier tests left, so that only these blocks count below
  ASSERT_EQ(mallopt(M_TRIM_THRESHOLD, 1 << 30), 1);
  for (void* b : blocks) std::free(b);
  const std::int64_t with_blocks_freed = resident_bytes();
  const bool released = release_free_memory();
  const std::int64_t after = resident_bytes();
  mallopt(M_TRIM_THRESHOLD, 128 << 10);  // glibc's default
  EXPECT_TRUE(released) << "malloc_trim reported nothing handed back";
  EXPECT_LE(after, with_blocks_freed - std::int64_t(kBlocks * kBlock / 2))
      << "resident " << with_blocks_freed << " bytes with the blocks freed, " << after << " after";
#endif
}

}  // namespace
}  // namespace lancer
