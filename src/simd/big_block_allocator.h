// An allocator for big working arrays that come and go, such as the kd-tree build's
// event and reference lists. Blocks of at least kBigBlockBytes are mapped straight from
// the system and unmapped when freed, so that a freed block never stays in the process
// (malloc keeps freed blocks below its mmap threshold, up to 32 MiB, for reuse, and the
// build's peak resident memory grew by a quarter with them), and they are marked for
// transparent huge pages, which spares most of the page faults of fresh memory. Smaller
// blocks use operator new. A failure throws OutOfMemory with the size asked for.
//
// Elements are left uninitialised by value-less construction (resize()), as the build
// sizes lists to a bound and writes each element once.
#pragma once

#include <cstddef>
#include <new>
#include <utility>
#include <vector>

#include "simd/out_of_memory.h"

namespace lancer {

inline constexpr std::size_t kBigBlockBytes = std::size_t(2) << 20;
inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

// Maps `bytes` (>= kBigBlockBytes), or throws OutOfMemory.
void* map_big_block(std::size_t bytes);
void unmap_big_block(void* p, std::size_t bytes) noexcept;

template <typename T>
struct BigBlockAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = BigBlockAllocator<U>;
  };
  BigBlockAllocator() noexcept = default;
  template <typename U>
  BigBlockAllocator(const BigBlockAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw OutOfMemory(std::size_t(-1));
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kBigBlockBytes) return static_cast<T*>(map_big_block(bytes));
    return static_cast<T*>(::operator new(bytes));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kBigBlockBytes) {
      unmap_big_block(p, bytes);
    } else {
      ::operator delete(p);
    }
  }

  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const BigBlockAllocator<U>&) const noexcept {
    return true;
  }
};

template <typename T>
using BigBlockVector = std::vector<T, BigBlockAllocator<T>>;

}  // namespace lancer
