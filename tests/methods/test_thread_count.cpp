// One thread count for OpenMP and LibTorch (methods/thread_count.hpp): an explicit count, and
// the default of 0 (OMP_NUM_THREADS where it is a positive count, else 1).
#include <gtest/gtest.h>

#include <ATen/Parallel.h>
#include <omp.h>

#include <cstdlib>
#include <optional>
#include <string>

#include <fnopt/methods/thread_count.hpp>

namespace fnopt {
namespace {

// Restores both thread counts and OMP_NUM_THREADS when a test ends, so that the tests after it
// run as before.
class ThreadCountTest : public ::testing::Test {
 protected:
  void SetUp() override {
    omp_threads_ = omp_get_max_threads();
    torch_threads_ = at::get_num_threads();
    if (const char* env = std::getenv("OMP_NUM_THREADS")) environment_ = env;
  }
  void TearDown() override {
    if (environment_)
      setenv("OMP_NUM_THREADS", environment_->c_str(), 1);
    else
      unsetenv("OMP_NUM_THREADS");
    at::set_num_threads(torch_threads_);
    omp_set_num_threads(omp_threads_);
  }

 private:
  int omp_threads_ = 1, torch_threads_ = 1;
  std::optional<std::string> environment_;
};

TEST_F(ThreadCountTest, SetsOpenMpAndLibTorchToAnExplicitCount) {
  EXPECT_EQ(set_thread_count(3), 3);
  EXPECT_EQ(omp_get_max_threads(), 3);
  EXPECT_EQ(at::get_num_threads(), 3);
  EXPECT_EQ(set_thread_count(1), 1);
  EXPECT_EQ(omp_get_max_threads(), 1);
  EXPECT_EQ(at::get_num_threads(), 1);
}

TEST_F(ThreadCountTest, ZeroTakesOmpNumThreadsOrOne) {
  setenv("OMP_NUM_THREADS", "2", 1);
  EXPECT_EQ(set_thread_count(0), 2);
  EXPECT_EQ(omp_get_max_threads(), 2);
  setenv("OMP_NUM_THREADS", "4,2", 1);  // a list: the outer level's count
  EXPECT_EQ(set_thread_count(0), 4);
  EXPECT_EQ(omp_get_max_threads(), 4);
  for (const char* unusable : {"0", "-3", "many", ""}) {
    setenv("OMP_NUM_THREADS", unusable, 1);
    EXPECT_EQ(set_thread_count(0), 1) << "OMP_NUM_THREADS='" << unusable << "'";
  }
  unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(set_thread_count(0), 1);
  EXPECT_EQ(omp_get_max_threads(), 1);
  EXPECT_EQ(at::get_num_threads(), 1);
  // A negative count is the default too.
  setenv("OMP_NUM_THREADS", "2", 1);
  EXPECT_EQ(set_thread_count(-1), 2);
}

}  // namespace
}  // namespace fnopt
