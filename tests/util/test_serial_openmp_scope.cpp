#include <fnopt/util/serial_openmp_scope.hpp>

#include <gtest/gtest.h>

namespace fnopt {
namespace {

int threads_in_region(int requested) {
  int threads = 0;
#pragma omp parallel num_threads(requested)
  {
#pragma omp single
    threads = omp_get_num_threads();
  }
  return threads;
}

// CHOLMOD asks for num_threads(4) explicitly; the scope must still keep it on one thread.
TEST(SerialOpenMpScope, ExplicitThreadCountsRunSeriallyInsideAndAreRestoredAfter) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(3);
  ASSERT_EQ(threads_in_region(2), 2) << "OpenMP must be able to run 2 threads for this test to mean anything";
  {
    SerialOpenMpScope serial;
    EXPECT_EQ(omp_get_max_threads(), 1);  // what OpenBLAS reads to pick its serial path
    EXPECT_EQ(threads_in_region(4), 1);
  }
  EXPECT_EQ(omp_get_max_threads(), 3);
  EXPECT_EQ(threads_in_region(2), 2);
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace fnopt
