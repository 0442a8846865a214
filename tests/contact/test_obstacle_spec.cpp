// Obstacle specs: every shape parses, the canonical text parses back to the same obstacle, and
// each kind of bad input is one Error naming its problem.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

void expect_same(const Obstacle& a, const Obstacle& b) {
  EXPECT_EQ(a.shape(), b.shape());
  EXPECT_EQ(a.point(), b.point());
  EXPECT_EQ(a.axis(), b.axis());
  EXPECT_EQ(a.radius(), b.radius());
  EXPECT_EQ(a.friction(), b.friction());
  EXPECT_EQ(a.motion().kind(), b.motion().kind());
  EXPECT_EQ(a.motion().name(), b.motion().name());
  EXPECT_EQ(a.to_text(), b.to_text());
}

TEST(ObstacleSpec, ParsesEveryShape) {
  const Obstacle s = parse_obstacle("sphere center=0.5,0.2,-0.5 radius=0.2 friction=0.3 motion=xy_v2");
  EXPECT_EQ(s.shape(), ObstacleShape::Sphere);
  EXPECT_EQ(s.point(), Vec3(0.5, 0.2, -0.5));
  EXPECT_EQ(s.radius(), 0.2);
  EXPECT_EQ(s.friction(), 0.3);
  EXPECT_EQ(s.motion().kind(), ObstacleMotion::Kind::Named);
  const Obstacle p = parse_obstacle("  plane point=0,0,-1 normal=0,0,2 ");
  EXPECT_EQ(p.shape(), ObstacleShape::Plane);
  EXPECT_DOUBLE_EQ(p.distance(Vec3(3, 4, 0), Vec3::Zero()), 1.0);
  const Obstacle b = parse_obstacle("box center=0,0,0 size=1,2,3 rounding=0.1");
  EXPECT_EQ(b.axis(), Vec3(1, 2, 3));
  EXPECT_EQ(b.radius(), 0.1);
  const Obstacle c = parse_obstacle("capsule a=0,0,0 b=1,0,0 radius=0.25 friction=1");
  EXPECT_EQ(c.axis(), Vec3(1, 0, 0));
  EXPECT_EQ(parse_obstacles("sphere center=0,0,0 radius=1; plane point=0,0,0 normal=0,0,1;").size(), 2u);
}

TEST(ObstacleSpec, CanonicalTextParsesBackToTheSameObstacle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), positive(0.01, 1.0);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Obstacle> obstacles = {
        Obstacle::plane(point(), point()), Obstacle::sphere(point(), positive(rng)),
        Obstacle::box(point(), Vec3(1 + positive(rng), 1 + positive(rng), 1 + positive(rng)), 0.5 * positive(rng)),
        Obstacle::capsule(point(), point() + Vec3(2, 0, 0), positive(rng))};
    obstacles[1].with_friction(positive(rng)).with_motion(ObstacleMotion::named("yz_v2", obstacles[1].point()));
    for (const Obstacle& o : obstacles) expect_same(parse_obstacle(o.to_text()), o);
    std::string specs;
    for (const Obstacle& o : obstacles) specs += o.to_text() + "; ";
    const std::vector<Obstacle> back = parse_obstacles(specs);
    ASSERT_EQ(back.size(), obstacles.size());
    for (std::size_t k = 0; k < back.size(); ++k) expect_same(back[k], obstacles[k]);
  }
}

// The message of the error `spec` throws ("" when it parses).
std::string problem(const std::string& spec) {
  try {
    parse_obstacle(spec);
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "obstacle") << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    return e.what();
  }
  return "";
}

TEST(ObstacleSpec, BadInputIsOneLineNamingTheProblem) {
  EXPECT_NE(problem("cube center=0,0,0 size=1,1,1").find("unknown shape 'cube'"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0 radius=1 colour=red").find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0 radius=-1").find("sphere.radius"), std::string::npos);
  EXPECT_NE(problem("capsule a=0,0,0 b=1,0,0 radius=0").find("capsule.radius"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,nan,0 radius=1").find("not finite"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0 radius=inf").find("not finite"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0").find("needs radius="), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0 radius=1 radius=2").find("twice"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0 radius=1").find("three numbers"), std::string::npos);
  EXPECT_NE(problem("sphere center=0,0,0 radius=1 motion=spin").find("motion"), std::string::npos);
  EXPECT_NE(problem("").find("empty"), std::string::npos);
  const std::string file = ::testing::TempDir() + "obstacle_nan.csv";
  std::ofstream(file) << "0,0,0,0\n1,0,NaN,0\n";
  const std::string nan_path = problem("sphere center=0,0,0 radius=1 path=" + file);
  EXPECT_NE(nan_path.find(file + ":2:"), std::string::npos) << nan_path;
  EXPECT_NE(nan_path.find("not finite"), std::string::npos) << nan_path;
  std::remove(file.c_str());
}

// A mesh spec reads its file (relative paths as given, stored absolute), poses it by scale and
// offset, and writes a canonical text that parses back to the same mesh; a sequence likewise.
TEST(ObstacleSpec, MeshesParseAndWriteBack) {
  const std::string dir = ::testing::TempDir();
  const std::string file = dir + "spec_tetra.obj";
  std::ofstream(file) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  for (int k = 0; k < 2; ++k)
    std::ofstream(dir + "spec_seq" + (k ? "0001" : "0000") + ".obj")
        << "v 0 0 " << k << "\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const Obstacle m = parse_obstacle("mesh file=" + file + " scale=2 offset=1,0,0 friction=0.4 motion=xy_v2");
  ASSERT_TRUE(m.is_mesh());
  EXPECT_EQ(m.mesh()->triangle_count(), 4);
  EXPECT_EQ(m.mesh()->frame(0)[1], Vec3(3, 0, 0));
  EXPECT_EQ(m.point(), Vec3(1, 0, 0));  // the origin the motion moves
  EXPECT_EQ(m.friction(), 0.4);
  const Obstacle back = parse_obstacle(m.to_text());
  EXPECT_EQ(back.to_text(), m.to_text());
  EXPECT_EQ(back.mesh()->frame(0), m.mesh()->frame(0));
  const Obstacle s = parse_obstacle("mesh sequence=" + dir + "spec_seq fps=4");
  EXPECT_TRUE(s.mesh()->animated());
  EXPECT_TRUE(s.moves());
  std::vector<Vec3> at;
  s.mesh_vertices(0.125, at);  // half way between the frames
  EXPECT_EQ(at[0], Vec3(0, 0, 0.5));
  EXPECT_EQ(parse_obstacle(s.to_text()).to_text(), s.to_text());
  EXPECT_NE(s.to_text().find("sequence=" + dir + "spec_seq fps=4"), std::string::npos) << s.to_text();
}

TEST(ObstacleSpec, BadMeshSpecsAreOneLineNamingTheFile) {
  const std::string dir = ::testing::TempDir();
  EXPECT_NE(problem("mesh").find("file=PATH.obj or sequence=PREFIX"), std::string::npos);
  EXPECT_NE(problem("mesh file=" + dir + "no_such.obj").find(dir + "no_such.obj"), std::string::npos);
  const std::string bad = dir + "spec_bad.obj";
  std::ofstream(bad) << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
  const std::string message = problem("mesh file=" + bad);
  EXPECT_NE(message.find(bad + ": line 2"), std::string::npos) << message;
  const std::string empty = dir + "spec_empty.obj";
  std::ofstream(empty) << "v 0 0 0\n";
  EXPECT_NE(problem("mesh file=" + empty).find(empty), std::string::npos);
  EXPECT_NE(problem("mesh file=" + bad + " sequence=x").find("not both"), std::string::npos);
  EXPECT_NE(problem("mesh file=x.obj fps=3").find("fps= is for a sequence"), std::string::npos);
  EXPECT_NE(problem("mesh sequence=" + dir + "spec_none").find("spec_none0000.obj"), std::string::npos);
  const std::string tetra = dir + "spec_tetra2.obj";
  std::ofstream(tetra) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_NE(problem("mesh file=" + tetra + " scale=0").find("scale"), std::string::npos);
  EXPECT_NE(problem("mesh file=" + tetra + " radius=1").find("unknown key 'radius'"), std::string::npos);
}

}  // namespace
}  // namespace fnopt
