#pragma once
// The process's peak resident memory so far, for the bench tables.
#include <sys/resource.h>

namespace fnopt {

// [MB], from getrusage's ru_maxrss (KiB on Linux).
inline double peak_resident_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

}  // namespace fnopt
