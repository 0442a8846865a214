// The training session: a run in an output folder writes its model, checkpoint and log; a run
// stopped early and resumed reads as one run (its log trimmed to the checkpoint, then continued);
// a folder holding a checkpoint is refused without resume, and resume without one is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fnopt/training/training_session.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TrainingSessionOptions tiny_session(const std::filesystem::path& out, int steps) {
  TrainingSessionOptions session;
  session.train.pool.resolutions = {8};
  session.train.pool.environments = 4;
  session.train.model =
      FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4);
  session.train.batch = 2;
  session.train.steps = steps;
  session.train.validate();
  session.out = out.string();
  session.checkpoint_every = 2;
  session.validate();
  return session;
}

std::vector<std::string> log_steps(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::string> steps;
  while (std::getline(in, line)) steps.push_back(line.substr(0, line.find(',')));
  return steps;
}

TEST(TrainingSession, AResumedRunReadsAsOneRun) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_training_session";
  std::filesystem::remove_all(dir);
  const TrainingSessionResult first = run_training_session(tiny_session(dir, 3), Communicator::self());
  EXPECT_EQ(first.steps, 3);
  EXPECT_FALSE(first.out_of_time);
  EXPECT_TRUE(std::filesystem::exists(first.model_path));
  EXPECT_TRUE(std::filesystem::exists(dir / "checkpoint.pt"));
  EXPECT_EQ(log_steps(first.log_path), (std::vector<std::string>{"1", "2", "3"}));

  // A log row past the checkpoint's step (a run killed between its log and its checkpoint).
  std::ofstream(first.log_path, std::ios::app) << "4,9.9,1,1,1,1,1,0,0,\n";
  TrainingSessionOptions more = tiny_session(dir, 5);
  more.resume = true;
  const TrainingSessionResult second = run_training_session(more, Communicator::self());
  EXPECT_EQ(second.steps, 5);
  EXPECT_EQ(log_steps(second.log_path), (std::vector<std::string>{"1", "2", "3", "4", "5"}));
  EXPECT_GE(second.seconds, first.seconds);

  try {  // a fresh run over the checkpoint
    run_training_session(tiny_session(dir, 5), Communicator::self());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "out");
  }
  std::filesystem::remove_all(dir);
  TrainingSessionOptions nothing = tiny_session(dir, 2);
  nothing.resume = true;
  try {
    run_training_session(nothing, Communicator::self());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "resume");
  }
  std::filesystem::remove_all(dir);
}

TEST(TrainingSession, RefusesSettingsThatCannotRunByTheirFlags) {
  TrainingSessionOptions session = tiny_session(std::filesystem::temp_directory_path(), 1);
  session.checkpoint_every = 0;
  try {
    session.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "checkpoint-every");
  }
  session.checkpoint_every = 1;
  session.minutes = -1;
  EXPECT_THROW(session.validate(), Error);
  session.minutes = 0;
  session.validation = ValidationOptions{};
  session.validation->frames = 0;
  try {
    session.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "validate-frames");
  }
}

}  // namespace
}  // namespace fnopt
