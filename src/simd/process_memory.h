// This process's resident memory, as the kernel counts it.
#pragma once

#include <cstdint>

namespace lancer {

// Resident memory now (VmRSS) and its peak since the process started (VmHWM), in bytes;
// -1 where the system does not say (Linux's /proc/self/status is read).
std::int64_t resident_bytes() noexcept;
std::int64_t peak_resident_bytes() noexcept;

}  // namespace lancer
