// OBJ meshes: polygons and relative indices triangulated into a closed, outward mesh; every kind of
// bad input refused in one line naming the file (and the line); sequences of one topology; the
// example meshes of examples/meshes closed, outward and on the shapes they tessellate.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>

#include <fnopt/io/obj_mesh.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

// The unit cube [0,1]^3 as six quads wound outward, some written with relative indices and
// v/vt/vn triples, in two groups, with a material, a line and a point (ignored).
const char* const kCube =
    "# a cube\n"
    "mtllib cube.mtl\n"
    "o first\n"
    "usemtl wood\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvn 0 0 1\n"
    "f -1 -2 -3 -4\n"  // the bottom, z = 0, facing -z: vertices 4 3 2 1
    "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f -4/1/1 -3/1/1 -2/1/1 -1/1/1\n"  // the top, z = 1: 5 6 7 8
    "g sides\n"
    "f 1//1 2//1 6//1 5//1\n"
    "f 2 3 7 6\n"
    "f 3 4 8 7\n"
    "f 4 1 5 8\n"
    "l 1 7\np 3\n";

// Each undirected edge and how many triangles hold it; each directed edge at most once when the
// triangles are wound consistently.
bool closed_and_oriented(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

double signed_volume(const TriangleMesh& mesh) {
  double six_volume = 0.0;
  for (const auto& t : mesh.triangles)
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  return six_volume / 6.0;
}

double area(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles)
    sum += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
  return sum;
}

TEST(ObjMesh, QuadsAndRelativeIndicesTriangulateIntoAClosedOutwardCube) {
  const testing::TempDir tmp;
  const TriangleMesh cube = read_obj_mesh(tmp.write("cube.obj", kCube));
  ASSERT_EQ(cube.vertices.size(), 8u);
  EXPECT_EQ(cube.vertices[6], Vec3(1, 1, 1));
  ASSERT_EQ(cube.triangles.size(), 12u);
  EXPECT_TRUE(closed_and_oriented(cube));
  EXPECT_DOUBLE_EQ(signed_volume(cube), 1.0);  // outward: the quads' winding kept
  EXPECT_DOUBLE_EQ(area(cube), 6.0);
  EXPECT_EQ(unique_edges(cube.triangles).size(), 18u);  // 12 of the cube, a diagonal per face
  // The bottom, written -1 -2 -3 -4 after four vertices: vertices 4 3 2 1 (0-based 3 2 1 0).
  for (int k = 0; k < 2; ++k)
    for (int index : cube.triangles[k]) EXPECT_LT(index, 4);
}

TEST(ObjMesh, APolygonIsTriangulatedWholeAndCoordinatesAreReadExactly) {
  const testing::TempDir tmp;
  // A convex pentagon in the plane z = 0.3, counter-clockwise seen from +z, and CR LF line ends.
  const TriangleMesh pentagon = read_obj_mesh(
      tmp.write("pentagon.obj", "v 0 0 0.3\r\nv 2 0 0.3\r\nv 3 1 0.3\r\nv 1 2.5 0.3\r\nv -1 1 0.3\r\nf 1 2 3 4 5\r\n"));
  ASSERT_EQ(pentagon.triangles.size(), 3u);
  EXPECT_NEAR(area(pentagon), 6.0, 1e-12);  // the shoelace formula's
  for (const auto& t : pentagon.triangles) {
    const Vec3 normal =
        (pentagon.vertices[t[1]] - pentagon.vertices[t[0]]).cross(pentagon.vertices[t[2]] - pentagon.vertices[t[0]]);
    EXPECT_GT(normal.z(), 0.0);
  }
  EXPECT_EQ(pentagon.vertices[0].z(), 0.3);  // the double nearest 0.3, as from_chars reads it
}

TEST(ObjMesh, ATriangleWithARepeatedVertexIsDropped) {
  const testing::TempDir tmp;
  // A triangle written as a quad with its last vertex twice, beside a proper one.
  const TriangleMesh mesh =
      read_obj_mesh(tmp.write("repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 3\nf 1 2 4\n"));
  ASSERT_EQ(mesh.triangles.size(), 2u);
  for (const auto& t : mesh.triangles) EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
  EXPECT_NEAR(area(mesh), 1.0, 1e-15);
}

// read_obj_mesh of `text` throws one line naming the file and containing `expected`.
::testing::AssertionResult refused(const std::string& text, const std::string& expected) {
  const testing::TempDir tmp;
  const std::string path = tmp.write("bad.obj", text);
  const auto result = testing::throws_error([&] { read_obj_mesh(path); }, path + ": " + expected);
  return result;
}

TEST(ObjMesh, BadInputIsRefusedInOneLineNamingTheFileAndLine) {
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  // A zero index: tinyobjloader's own message, which names the line.
  EXPECT_TRUE(refused(triangle + "f 1 2 0\n", "malformed OBJ: "));
  const testing::TempDir tmp;
  const std::string zero_index = tmp.write("zero.obj", triangle + "f 1 2 0\n");
  EXPECT_TRUE(testing::throws_error([&] { read_obj_mesh(zero_index); }, "line 4"));
  EXPECT_TRUE(refused(triangle, "no triangle"));
  EXPECT_TRUE(refused("", "no triangle"));
  EXPECT_TRUE(refused(triangle + "f 1 1 2\nf 3 3 3 3\n", "no triangle with three distinct vertices"));
  EXPECT_TRUE(refused("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "line 2: vertex 2: coordinate 'nan' is not finite"));
  EXPECT_TRUE(refused("v 0 0 0\nv 1 0 0\n\nv 0 1e400 0\nf 1 2 3\n",
                      "line 4: vertex 3: coordinate '1e400' is out of a double's range"));
  EXPECT_TRUE(refused("v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n", "line 2: vertex 2: 'x' is not a number"));
  EXPECT_TRUE(refused("v 0 0 0\nv 1,5 0 0\nv 0 1 0\nf 1 2 3\n", "line 2: vertex 2: '1,5' is not a number"));
  EXPECT_TRUE(refused("v 0 0 0\r\nv 1 0\r\nv 0 1 0\r\nf 1 2 3\r\n", "line 2: vertex 2 has 2 coordinates, not three"));
  EXPECT_TRUE(refused(triangle + "f 1 2 3\nf 1 2 9\n", "line 5: the face refers to vertex 9, but the file has 3"));
  EXPECT_TRUE(refused(triangle + "f 1 2 3 4\n", "line 4: the face refers to vertex 4, but the file has 3"));
  EXPECT_TRUE(refused(triangle + "f -4 -2 -1\n", "line 4: a relative face index points before the first vertex"));
  EXPECT_TRUE(refused(triangle + "f 1 2\n", "line 4: a face needs three or more vertices, this one has 2"));
}

TEST(ObjMesh, AMissingFileOrADirectoryIsRefusedByName) {
  const testing::TempDir tmp;
  const std::string missing = (tmp.path() / "missing.obj").string();
  EXPECT_TRUE(testing::throws_error([&] { read_obj_mesh(missing); }, missing + ": no such file"));
  EXPECT_TRUE(testing::throws_error([&] { read_obj_mesh(tmp.path().string()); }, "is a directory"));
  try {
    read_obj_mesh(missing);
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), missing);  // the file is the field, so a caller can name it as it likes
  }
}

// Frame k of a sequence: the unit tetrahedron moved by k along x, or with `triangles` of its own.
std::string tetrahedron(int k, const std::string& triangles = "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n") {
  const std::string x = std::to_string(k), next = std::to_string(k + 1);
  return "v " + x + " 0 0\nv " + next + " 0 0\nv " + x + " 1 0\nv " + x + " 0 1\n" + triangles;
}

TEST(ObjSequence, ReadsConsecutiveFramesUpToTheFirstGap) {
  const testing::TempDir tmp;
  for (int k : {0, 1, 2, 4})
    tmp.write("walk" + std::string(k < 10 ? "000" : "00") + std::to_string(k) + ".obj", tetrahedron(k));
  const auto frames = read_obj_sequence((tmp.path() / "walk").string());
  ASSERT_EQ(frames.size(), 3u);  // 0003 is missing: 0004 is not a frame
  EXPECT_EQ(frames[2].vertices[0], Vec3(2, 0, 0));
  EXPECT_EQ(frames[1].triangles, frames[0].triangles);
  EXPECT_EQ(sequence_frame_path("dir/walk", 12), "dir/walk0012.obj");
  EXPECT_EQ(sequence_frame_path("dir/walk", 12345), "dir/walk12345.obj");
}

TEST(ObjSequence, NoFirstFrameOrAChangedTopologyIsRefusedNamingTheFile) {
  const testing::TempDir tmp;
  const std::string prefix = (tmp.path() / "walk").string();
  EXPECT_TRUE(testing::throws_error([&] { read_obj_sequence(prefix); }, prefix + "0000.obj: no such file"));
  tmp.write("walk0001.obj", tetrahedron(1));
  EXPECT_TRUE(testing::throws_error([&] { read_obj_sequence(prefix); }, prefix + "0000.obj: no such file"));

  tmp.write("walk0000.obj", tetrahedron(0));
  tmp.write("walk0002.obj", tetrahedron(2) + "v 5 5 5\n");
  EXPECT_TRUE(testing::throws_error([&] { read_obj_sequence(prefix); },
                                    prefix + "0002.obj: has 5 vertices where the first frame has 4"));
  tmp.write("walk0002.obj", tetrahedron(2, "f 1 3 2\nf 1 2 4\nf 2 3 4\n"));
  EXPECT_TRUE(testing::throws_error([&] { read_obj_sequence(prefix); },
                                    prefix + "0002.obj: has 3 triangles where the first frame has 4"));
  tmp.write("walk0002.obj", tetrahedron(2, "f 1 3 2\nf 1 2 4\nf 2 4 3\nf 1 4 3\n"));
  EXPECT_TRUE(
      testing::throws_error([&] { read_obj_sequence(prefix); },
                            prefix + "0002.obj: has triangle 3 on vertices 2,4,3 where the first frame has 2,3,4"));
  tmp.write("walk0002.obj", "v 0 0 0\n");
  EXPECT_TRUE(testing::throws_error([&] { read_obj_sequence(prefix); }, prefix + "0002.obj: no triangle"));
}

TEST(ObjMesh, UniqueEdgesAndBoundingBox) {
  const std::vector<std::array<int, 3>> triangles{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const std::vector<std::array<int, 2>> expected{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  EXPECT_EQ(unique_edges(triangles), expected);
  Vec3 lower, upper;
  bounding_box({Vec3(1, -2, 3), Vec3(-1, 4, 0)}, lower, upper);
  EXPECT_EQ(lower, Vec3(-1, -2, 0));
  EXPECT_EQ(upper, Vec3(1, 4, 3));
  bounding_box({}, lower, upper);
  EXPECT_TRUE(lower.x() > upper.x());
}

std::string example_mesh(const std::string& name) { return std::string(FNOPT_SOURCE_DIR) + "/examples/meshes/" + name; }

TEST(ExampleMeshes, AreClosedAndOutward) {
  for (const char* name : {"mannequin.obj", "sphere.obj", "table.obj"}) {
    const TriangleMesh mesh = read_obj_mesh(example_mesh(name));
    EXPECT_TRUE(closed_and_oriented(mesh)) << name;
    EXPECT_GT(signed_volume(mesh), 0.0) << name;
  }
}

TEST(ExampleMeshes, SphereAndTableVerticesLieOnTheirScenesShapes) {
  const TriangleMesh sphere = read_obj_mesh(example_mesh("sphere.obj"));
  for (const Vec3& v : sphere.vertices) EXPECT_NEAR((v - Vec3(0, 0, -0.3)).norm(), 0.25, 1e-8);
  // An inscribed polytope falls short of the ball by less than sagitta x area, 3 sagitta / radius
  // of its volume, and the sagitta is at most 1 mm.
  const double ball = 4.0 / 3.0 * M_PI * std::pow(0.25, 3);
  EXPECT_LT(signed_volume(sphere), ball);
  EXPECT_GT(signed_volume(sphere), (1.0 - 3.0 * 1e-3 / 0.25) * ball);
  // The table: at the rounding's distance from the inner box (half sizes size/2 - rounding).
  const TriangleMesh table = read_obj_mesh(example_mesh("table.obj"));
  const Vec3 inner_half = Vec3(1, 1.4, 0.2) / 2.0 - Vec3::Constant(0.02);
  for (const Vec3& v : table.vertices) {
    const Vec3 outside = ((v - Vec3(0.35, 0, -0.2)).cwiseAbs() - inner_half).cwiseMax(0.0);
    EXPECT_NEAR(outside.norm(), 0.02, 1e-8);
  }
}

TEST(ExampleMeshes, MannequinStandsUnderTheCloth) {
  const TriangleMesh mannequin = read_obj_mesh(example_mesh("mannequin.obj"));
  EXPECT_GE(mannequin.triangles.size(), 2000u);
  EXPECT_LE(mannequin.triangles.size(), 6000u);
  Vec3 lower, upper;
  bounding_box(mannequin.vertices, lower, upper);
  EXPECT_NEAR(lower.z(), -1.3, 0.01);
  EXPECT_NEAR(upper.z(), -0.6, 0.01);
  EXPECT_NEAR(upper.x() - lower.x(), 0.45, 0.01);
  EXPECT_NEAR(0.5 * (upper.x() + lower.x()), 0.0, 0.01);
  EXPECT_NEAR(0.5 * (upper.y() + lower.y()), 0.0, 0.01);
}

}  // namespace
}  // namespace fnopt
