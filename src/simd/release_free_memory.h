// Hands memory that the allocator keeps after free() back to the system.
#pragma once

namespace lancer {

// After a phase that allocated and freed many mid-sized blocks (a scene load, a kd-tree
// build), malloc keeps the freed blocks for reuse, and they count as resident memory
// until the process ends: about 30 MB on a million-triangle build. Called once per phase
// (it costs about a millisecond), so that the next phase's peak does not stack on them.
// True when memory went back; always false where the C library offers no way (it is
// glibc's malloc_trim).
bool release_free_memory() noexcept;

}  // namespace lancer
