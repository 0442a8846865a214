// A process started without an MPI launcher is a communicator of one: every collective is the
// identity, and nothing touches MPI (MPI is never initialised here). The two-rank behaviour is
// tested under mpirun (tests/mpi).
#include <gtest/gtest.h>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TEST(Communicator, WithoutALauncherTheWorldIsOneProcess) {
  EXPECT_FALSE(MpiSession::active());
  const Communicator& world = Communicator::world();
  EXPECT_EQ(world.size(), 1);
  EXPECT_EQ(world.rank(), 0);
  EXPECT_TRUE(world.is_root());
}

TEST(Communicator, OneProcessCollectivesAreTheIdentity) {
  const Communicator& self = Communicator::self();
  float f[2] = {1.5f, -2.0f};
  self.sum(f, 2);
  EXPECT_EQ(f[0], 1.5f);
  EXPECT_EQ(f[1], -2.0f);
  EXPECT_EQ(self.sum(2.5), 2.5);
  EXPECT_EQ(self.sum(3), 3);
  EXPECT_TRUE(self.any(true));
  EXPECT_FALSE(self.any(false));
  std::string text = "unchanged";
  self.broadcast(text);
  EXPECT_EQ(text, "unchanged");
  EXPECT_EQ(self.gather("mine"), std::vector<std::string>{"mine"});
  Communicator::Message message;
  EXPECT_FALSE(self.take_arrived(message));
  EXPECT_THROW(self.send_to_root("x"), Error);
}

}  // namespace
}  // namespace fnopt
