// The tests that need two processes, run by CTest as `mpiexec -n 2 test_mpi`: MPI is initialised
// as fnopt's own main does it, and only rank 0 prints gtest's report (a failure on rank 1 still
// fails the run: its exit status is non-zero, and mpiexec returns it).
#include <gtest/gtest.h>

#include <fnopt/parallel/communicator.hpp>

int main(int argc, char** argv) {
  const fnopt::MpiSession mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (!fnopt::Communicator::world().is_root()) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
