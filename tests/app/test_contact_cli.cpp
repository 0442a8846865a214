// Obstacles from the command line as a user gives them (docs/design.md §14): a released cloth
// dropped on a sphere and a table keeps every vertex outside, simulate and evaluate print the
// smallest distance, and bad obstacle input is one line and exit 2 before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

// The number after "min obstacle distance = " in a command's output; NaN where it is missing.
double min_distance(const std::string& output) {
  const std::string key = "min obstacle distance = ";
  const auto at = output.find(key);
  return at == std::string::npos ? NAN : std::stod(output.substr(at + key.size()));
}

TEST(ContactCli, AReleasedClothOnASphereStaysOutsideForEveryMethod) {
  const fnopt::testing::TempDir tmp;
  const std::string scene =
      "--res 12 --frames 40 --handles none --placement horizontal --threads 1 "
      "--obstacle 'sphere center=0,0,-0.25 radius=0.2 friction=0.3' --obstacle 'plane point=0,0,-0.5 normal=0,0,1' ";
  for (const std::string method : {"newton", "pqn", "lbfgs", "adam", "gd", "fnopt"}) {
    SCOPED_TRACE(method);
    const fs::path out = tmp.path() / (method + ".h5");
    const CommandResult r = run_fnopt("simulate " + scene + "--optimizer " + method + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("obstacle 1: sphere"), std::string::npos) << r.output;
    const double simulated = min_distance(r.output);
    EXPECT_GE(simulated, 0.0) << r.output;
    EXPECT_LT(simulated, 0.05) << "the cloth must reach the sphere within 40 frames: " << r.output;
    const CommandResult e = run_fnopt("evaluate --reference " + out.string() + " " + out.string() + " --threads 1");
    ASSERT_EQ(e.status, 0) << e.output;
    // The same frames, read back as floats from the file.
    EXPECT_NEAR(min_distance(e.output), simulated, 1e-6) << e.output;
  }
}

// compare reports each run's smallest obstacle and cloth-cloth distances and its self-intersections
// in compare.csv; mesh intersections only with a mesh obstacle.
TEST(ContactCli, CompareReportsEveryRunsSmallestDistancesAndCrossings) {
  const fnopt::testing::TempDir tmp;
  const fs::path dir = tmp.path() / "cmp";
  const CommandResult r = run_fnopt(
      "compare --res 10 --frames 30 --handles none --placement horizontal --obstacle 'sphere center=0,0,-0.25 "
      "radius=0.2' --optimizers newton,pqn,gd --iters 10 --threads 1 --step-samples 1 --cd-samples 100 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  std::string header;
  const auto rows = csv_rows(dir / "compare.csv", header);
  std::vector<std::string> columns;
  std::istringstream names(header);
  for (std::string name; std::getline(names, name, ',');) columns.push_back(name);
  auto at = [&](const std::string& name) {
    const auto column = std::find(columns.begin(), columns.end(), name) - columns.begin();
    EXPECT_LT(column, static_cast<long>(columns.size())) << name << " not in " << header;
    return static_cast<std::size_t>(column);
  };
  const std::size_t obstacle = at("min_obstacle_distance_m"), cloth = at("min_cloth_distance_m"),
                    self = at("self_intersections"), mesh = at("mesh_intersections");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    ASSERT_GT(row.size(), std::max({obstacle, cloth, self, mesh})) << row[0];
    EXPECT_GE(std::stod(row[obstacle]), 0.0) << row[0];
    EXPECT_GE(std::stod(row[cloth]), 1e-3) << row[0];  // self-contact is on for a released cloth
    EXPECT_EQ(row[self], "0") << row[0];
    EXPECT_EQ(row[mesh], "") << row[0];
  }
}

// bench contact: a row per resolution, case and method; far obstacles and a far mesh leave the
// rollout as it is, self-contact has no such claim.
TEST(ContactCli, BenchContactTimesEveryCaseAndFarObstaclesLeaveTheRolloutAsItIs) {
  const CommandResult r = run_fnopt("bench contact --res 8,10 --frames 4 --repeat 2 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const std::string grid : {"8^2", "10^2"})
    for (const std::string method : {"pqn", "newton"})
      for (const std::string c : {"far-obstacles", "far-mesh", "self-contact"}) {
        std::istringstream lines(r.output);
        bool found = false;
        for (std::string line; std::getline(lines, line);) {
          std::istringstream cells(line);
          std::string g, m, name, without, with, ratio, same;
          if (!(cells >> g >> m >> name >> without >> with >> ratio >> same) || g != grid || m != method || name != c)
            continue;
          found = true;
          EXPECT_GT(std::stod(without), 0.0) << line;
          EXPECT_GT(std::stod(with), 0.0) << line;
          EXPECT_EQ(same, c == "self-contact" ? "-" : "yes") << line;
        }
        EXPECT_TRUE(found) << grid << " " << method << " " << c << "\n" << r.output;
      }
}

TEST(ContactCli, ARolloutWithoutObstaclesPrintsNoDistance) {
  const fnopt::testing::TempDir tmp;
  const fs::path out = tmp.path() / "free.h5";
  const CommandResult r = run_fnopt("simulate --res 8 --frames 3 --threads 1 --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("min obstacle distance"), std::string::npos) << r.output;
}

// An obstacle spec simulate must refuse before any work: exit 2, one line naming the problem
// (`says`), no output file.
struct RefusedObstacle {
  std::string obstacle, says;
};

void expect_refused_before_any_work(const fs::path& dir, const std::vector<RefusedObstacle>& cases) {
  const fs::path out = dir / "never.h5";
  const std::string simulate = "simulate --res 8 --frames 3 --threads 1 --out " + out.string() + " --obstacle ";
  for (const RefusedObstacle& c : cases) {
    SCOPED_TRACE(c.obstacle);
    const CommandResult r = run_fnopt(simulate + c.obstacle);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output.rfind("fnopt: error: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(ContactCli, BadMeshesAreOneLineNamingTheFileAndExitTwoBeforeAnyWork) {
  const fnopt::testing::TempDir tmp;
  const std::string dir = tmp.path().string() + "/";
  std::ofstream(dir + "nan.obj") << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir + "malformed.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  std::ofstream(dir + "empty.obj") << "# nothing\n";
  std::ofstream(dir + "seq0000.obj") << "v 0 -1 0\nv 1 -1 0\nv 0 -1 1\nf 1 2 3\n";
  std::ofstream(dir + "seq0001.obj") << "v 0 -1 0\nv 1 -1 0\nv 0 -1 1\nv 1 -1 1\nf 1 2 3\nf 2 4 3\n";
  std::ofstream(dir + "through.obj") << "v 0.4 -0.1 -0.6\nv 0.6 -0.1 -0.6\nv 0.5 0.1 -0.6\nv 0.5 0 -0.4\n"
                                        "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  expect_refused_before_any_work(tmp.path(), {{"'mesh file=" + dir + "missing.obj'", dir + "missing.obj"},
                                              {"'mesh file=" + dir + "nan.obj'", dir + "nan.obj: line 2"},
                                              {"'mesh file=" + dir + "malformed.obj'", dir + "malformed.obj"},
                                              {"'mesh file=" + dir + "empty.obj'", dir + "empty.obj"},
                                              {"'mesh sequence=" + dir + "seq fps=10'", dir + "seq0001.obj"},
                                              {"'mesh file=" + dir + "through.obj'", "the cloth starts through it"}});
}

TEST(ContactCli, BadObstacleInputIsOneLineAndExitTwoBeforeAnyWork) {
  const fnopt::testing::TempDir tmp;
  std::ofstream(tmp.path() / "nan.csv") << "t,x,y,z\n0,0,0,-1\n1,nan,0,-1\n";
  expect_refused_before_any_work(
      tmp.path(), {{"'sphere center=0,0,-2 radius=-1'", "radius"},
                   {"'cone center=0,0,-2 radius=1'", "unknown shape 'cone'"},
                   {"'sphere center=0.5,0,-0.5 radius=0.3'", "the cloth starts inside it"},
                   {"'sphere center=0,0,-2 radius=0.1 path=" + (tmp.path() / "nan.csv").string() + "'", "not finite"}});
}

}  // namespace
