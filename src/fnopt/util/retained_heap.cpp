#include <fnopt/util/retained_heap.hpp>

#include <cstdlib>  // defines __GLIBC__ on glibc systems

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace fnopt {

bool retain_freed_heap_memory() {
#if defined(__GLIBC__)
  // Setting either value also turns off glibc's dynamic adjustment of the mmap threshold.
  return mallopt(M_MMAP_THRESHOLD, kHeapBlockLimitBytes) == 1 && mallopt(M_TRIM_THRESHOLD, kHeapTrimBytes) == 1;
#else
  return false;
#endif
}

}  // namespace fnopt
