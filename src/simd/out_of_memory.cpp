#include "simd/out_of_memory.h"

#include <cstdio>

namespace lancer {

OutOfMemory::OutOfMemory(std::size_t bytes) noexcept : bytes_(bytes) {
  const double b = static_cast<double>(bytes);
  const char* unit = "KiB";
  double scaled = b / 1024.0;
  if (b >= 1024.0 * 1024.0 * 1024.0) {
    unit = "GiB";
    scaled = b / (1024.0 * 1024.0 * 1024.0);
  } else if (b >= 1024.0 * 1024.0) {
    unit = "MiB";
    scaled = b / (1024.0 * 1024.0);
  }
  std::snprintf(message_, sizeof message_, "could not allocate %.2f %s (%zu bytes)", scaled, unit, bytes);
}

std::string out_of_memory_message(const std::bad_alloc& e) {
  if (const auto* sized = dynamic_cast<const OutOfMemory*>(&e)) return std::string("out of memory: ") + sized->what();
  return "out of memory (in a library allocation that does not say how much it asked for)";
}

}  // namespace lancer
