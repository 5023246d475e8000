// The lancer programs' operator new: the standard one, except that a failure throws
// OutOfMemory, which names the size asked for ("could not allocate 1.21 GiB ..."), where
// std::bad_alloc says only "std::bad_alloc". Linked into the executables only (not into
// the libraries, which tests and other programs link with their own operator new), and
// left out under AddressSanitizer, which brings its own.
#include <cstdlib>
#include <new>

#include "simd/out_of_memory.h"

#if defined(__SANITIZE_ADDRESS__)
#define LANCER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LANCER_ASAN 1
#endif
#endif

#if !defined(LANCER_ASAN)

namespace {

void* allocate(std::size_t bytes, std::size_t alignment) {
  if (bytes == 0) bytes = 1;
  for (;;) {
    void* p = nullptr;
    if (alignment <= alignof(std::max_align_t)) {
      p = std::malloc(bytes);
    } else if (posix_memalign(&p, alignment, bytes) != 0) {
      p = nullptr;
    }
    if (p) return p;
    // The standard's loop: a new-handler may free memory and let the next try succeed.
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw lancer::OutOfMemory(bytes);
    handler();
  }
}

void* allocate_nothrow(std::size_t bytes, std::size_t alignment) noexcept {
  try {
    return allocate(bytes, alignment);
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

void* operator new(std::size_t n) { return allocate(n, 0); }
void* operator new[](std::size_t n) { return allocate(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) { return allocate(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return allocate(n, static_cast<std::size_t>(a)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n, 0); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate_nothrow(n, 0); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate_nothrow(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate_nothrow(n, static_cast<std::size_t>(a));
}

// Every form frees with free(), which takes malloc's and posix_memalign's blocks alike.
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

#endif  // !LANCER_ASAN
