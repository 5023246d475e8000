// An allocation failure that says how much was asked for: std::bad_alloc does not.
#pragma once

#include <cstddef>
#include <new>
#include <string>

namespace lancer {

class OutOfMemory : public std::bad_alloc {
 public:
  explicit OutOfMemory(std::size_t bytes) noexcept;
  // "could not allocate 1.21 GiB (1300000000 bytes)"; built without allocating.
  const char* what() const noexcept override { return message_; }
  std::size_t bytes() const noexcept { return bytes_; }

 private:
  std::size_t bytes_;
  char message_[80];
};

// The line a program prints for `e`: "out of memory: could not allocate ..." for an
// OutOfMemory; for any other std::bad_alloc (oneTBB's, the C++ library's own) it says
// that the size is not known.
std::string out_of_memory_message(const std::bad_alloc& e);

}  // namespace lancer
