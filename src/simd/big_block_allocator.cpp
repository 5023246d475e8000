#include "simd/big_block_allocator.h"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace lancer {

void* map_big_block(std::size_t bytes) {
#if defined(__linux__)
  void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw OutOfMemory(bytes);
#if defined(MADV_HUGEPAGE)
  // A hint (without huge pages it still works), for blocks that can hold one.
  if (bytes >= kHugePageBytes) (void)madvise(p, bytes, MADV_HUGEPAGE);
#endif
  return p;
#else
  void* p = std::malloc(bytes);
  if (!p) throw OutOfMemory(bytes);
  return p;
#endif
}

void unmap_big_block(void* p, std::size_t bytes) noexcept {
#if defined(__linux__)
  munmap(p, bytes);
#else
  (void)bytes;
  std::free(p);
#endif
}

}  // namespace lancer
