// This process's resident memory, as the kernel counts it, and the machine's.
#pragma once

#include <cstdint>

namespace lancer {

// Resident memory now (VmRSS) and its peak since the process started (VmHWM), in bytes;
// -1 where the system does not say (Linux's /proc/self/status is read).
std::int64_t resident_bytes() noexcept;
std::int64_t peak_resident_bytes() noexcept;

// The machine's physical memory in bytes (sysconf), or -1 where the system does not say:
// what a single render's working set can never exceed without being killed.
std::int64_t physical_memory_bytes() noexcept;

}  // namespace lancer
