#include "simd/release_free_memory.h"

// Any C library header defines __GLIBC__ (through <features.h>); without one included
// first, the test below is false and the function does nothing.
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace lancer {

bool release_free_memory() noexcept {
#if defined(__GLIBC__)
  return malloc_trim(0) != 0;
#else
  return false;
#endif
}

}  // namespace lancer
