// The process's own memory use, as the operating system counts it.
#ifndef VOXGI_CORE_MEMORY_H
#define VOXGI_CORE_MEMORY_H

#include <sys/resource.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif

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

// Transparent huge pages (docs/gl.md, huge pages) paused (true) or allowed again.
// While the process starts they cost more than they buy: at the first touch of
// memory that asked for them (madvise, glibc.malloc.hugetlb) the kernel must find,
// or compact, 2 MiB of free memory, and the start-up writes hundreds of MiB once
// (the scene, its BVH, the octree). The 2.44 M-triangle hall's start-up took
// 4.1-4.8 s with them and 2.2-2.4 s without, its frames the same; the points view's
// frames, 1.6x faster with them, keep that with the pause (264 ms against 262 with
// huge pages throughout and 424 without: measurements.md, huge-pages-paused). So
// they are paused from the process's start until its first frame is drawn (Linux:
// prctl PR_SET_THP_DISABLE, which overrides madvise; elsewhere nothing).
inline void pauseHugePages(bool paused) {
#if defined(__linux__)
  prctl(PR_SET_THP_DISABLE, paused ? 1 : 0, 0, 0, 0);
#else
  (void)paused;
#endif
}

}  // namespace voxgi

#endif  // VOXGI_CORE_MEMORY_H
