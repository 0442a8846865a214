#pragma once
// Runs a block of library calls on the calling thread alone.
//
// Why: CHOLMOD 3 (SuiteSparse 5, Debian bookworm) opens the copy loops of its supernodal
// factorization with a fixed `num_threads(CHOLMOD_OMP_NUM_THREADS)` = 4, whatever
// omp_set_num_threads() says, and OpenBLAS (OpenMP build) splits each dense block over
// omp_get_max_threads(). The two oversubscribe the cores, and the factorization then spends its
// time in futex wake-ups (docs/design.md §9). Its supernodes are small at these sizes, so a
// serial factorization loses nothing; the assembly around it stays parallel.
//
// omp_set_num_threads(1) sends OpenBLAS down its serial path (it follows omp_get_max_threads()
// at each call); max-active-levels 0 makes CHOLMOD's explicit num_threads(4) regions inactive
// (OpenMP 5.0, 2.6.1: no region is active beyond max-active-levels). Both are per-thread
// settings, restored on exit.
#include <omp.h>

namespace fnopt {

class SerialOpenMpScope {
 public:
  SerialOpenMpScope() : threads_(omp_get_max_threads()), levels_(omp_get_max_active_levels()) {
    omp_set_num_threads(1);
    omp_set_max_active_levels(0);
  }
  ~SerialOpenMpScope() {
    omp_set_max_active_levels(levels_);
    omp_set_num_threads(threads_);
  }
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  int threads_;
  int levels_;
};

}  // namespace fnopt
