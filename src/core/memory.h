// The process's own memory use, as the operating system counts it.
#ifndef VOXGI_CORE_MEMORY_H
#define VOXGI_CORE_MEMORY_H

#include <sys/resource.h>

#include <cstdint>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace voxgi {

// The most resident memory the process has held so far (Linux: ru_maxrss, in KiB),
// in bytes. On a software GL this includes what the "GPU" holds.
inline uint64_t peakResidentBytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<uint64_t>(u.ru_maxrss) * 1024u;
}

// Hands the heap's free pages back to the system after a large build has freed its
// working arrays (glibc keeps them otherwise, and they count as resident). Nothing
// elsewhere.
inline void releaseFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace voxgi

#endif  // VOXGI_CORE_MEMORY_H
