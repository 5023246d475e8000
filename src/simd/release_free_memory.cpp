#include "simd/release_free_memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace lancer {

void release_free_memory() noexcept {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace lancer
