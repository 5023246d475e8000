#include "simd/process_memory.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <unistd.h>

namespace lancer {
namespace {

// The "Key:   123 kB" line of /proc/self/status, in bytes, or -1.
std::int64_t status_kib(const char* key) noexcept {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return -1;
  char line[256];
  std::int64_t bytes = -1;
  const std::size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, key, n) == 0) {
      bytes = 1024 * std::atoll(line + n);
      break;
    }
  std::fclose(f);
  return bytes;
}

}  // namespace

std::int64_t resident_bytes() noexcept { return status_kib("VmRSS:"); }
std::int64_t peak_resident_bytes() noexcept { return status_kib("VmHWM:"); }

std::int64_t physical_memory_bytes() noexcept {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? std::int64_t(pages) * std::int64_t(page) : -1;
}

}  // namespace lancer
