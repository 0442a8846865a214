// A mesh obstacle's shape over time: posed by scale and offset at load, a sequence interpolated
// linearly between frames and held outside their times, boxes that hold the mesh at a time and
// over a step, and bad settings refused naming their key.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fnopt/contact/mesh_shape.hpp>
#include <fnopt/io/obj_mesh.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

// The unit tetrahedron, wound outward, its vertices moved by `shift` and then vertex 3 by `lift`
// along z (so that frames of a sequence differ by more than a translation).
TriangleMesh tetrahedron(const Vec3& shift = Vec3::Zero(), double lift = 0.0) {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0) + shift, Vec3(1, 0, 0) + shift, Vec3(0, 1, 0) + shift, Vec3(0, 0, 1 + lift) + shift};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return mesh;
}

// Three frames at 10 frames per second: t = 0, 0.1, 0.2.
MeshShape three_frames(double scale = 1.0, const Vec3& offset = Vec3::Zero()) {
  return MeshShape::sequence({tetrahedron(), tetrahedron(Vec3(1, 0, 0), 0.5), tetrahedron(Vec3(1, 2, 0), -0.5)}, 10.0,
                             scale, offset);
}

void expect_vertices(const std::vector<Vec3>& actual, const std::vector<Vec3>& expected, double tolerance) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t k = 0; k < actual.size(); ++k) EXPECT_LE((actual[k] - expected[k]).norm(), tolerance) << k;
}

std::vector<Vec3> mix(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double w) {
  std::vector<Vec3> result(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) result[k] = (1.0 - w) * a[k] + w * b[k];
  return result;
}

TEST(MeshShape, ASingleMeshIsPosedByScaleAndOffsetAtEveryTime) {
  const Vec3 offset(0.5, -1.0, 2.0);
  const MeshShape shape = MeshShape::single(tetrahedron(), 2.0, offset);
  EXPECT_FALSE(shape.animated());
  EXPECT_EQ(shape.vertex_count(), 4);
  EXPECT_EQ(shape.triangle_count(), 4);
  EXPECT_EQ(shape.edges().size(), 6u);
  EXPECT_EQ(shape.edges().front(), (std::array<int, 2>{0, 1}));
  std::vector<Vec3> posed;
  for (const Vec3& v : tetrahedron().vertices) posed.push_back(2.0 * v + offset);
  for (double t : {-1.0, 0.0, 0.37, 100.0}) expect_vertices(shape.vertices_at(t), posed, 0.0);
  Vec3 lower, upper;
  shape.bounds_at(3.0, lower, upper);
  EXPECT_EQ(lower, offset);
  EXPECT_EQ(upper, offset + Vec3(2, 2, 2));
}

TEST(MeshShape, ASequenceMovesLinearlyBetweenFramesAndHoldsOutsideThem) {
  const Vec3 offset(0, 0, -1);
  const MeshShape shape = three_frames(0.5, offset);
  ASSERT_TRUE(shape.animated());
  EXPECT_EQ(shape.frame_count(), 3);
  std::vector<Vec3> frames[3];
  const TriangleMesh meshes[3] = {tetrahedron(), tetrahedron(Vec3(1, 0, 0), 0.5), tetrahedron(Vec3(1, 2, 0), -0.5)};
  for (int k = 0; k < 3; ++k) {
    for (const Vec3& v : meshes[k].vertices) frames[k].push_back(0.5 * v + offset);  // posed at load
    expect_vertices(shape.frame(k), frames[k], 0.0);
  }
  expect_vertices(shape.vertices_at(-0.5), frames[0], 0.0);  // frame 0 before t = 0
  expect_vertices(shape.vertices_at(0.0), frames[0], 0.0);
  expect_vertices(shape.vertices_at(0.05), mix(frames[0], frames[1], 0.5), 1e-15);
  expect_vertices(shape.vertices_at(0.1), frames[1], 1e-15);
  expect_vertices(shape.vertices_at(0.175), mix(frames[1], frames[2], 0.75), 1e-15);
  expect_vertices(shape.vertices_at(0.2), frames[2], 0.0);  // the last frame, then held
  expect_vertices(shape.vertices_at(7.0), frames[2], 0.0);
}

TEST(MeshShape, VerticesAtFillsABufferWithoutReallocating) {
  const MeshShape shape = three_frames();
  std::vector<Vec3> buffer;
  shape.vertices_at(0.0, buffer);
  const Vec3* storage = buffer.data();
  for (double t : {0.03, 0.11, 0.19, 0.5}) {
    shape.vertices_at(t, buffer);
    EXPECT_EQ(buffer.data(), storage);
    expect_vertices(buffer, shape.vertices_at(t), 0.0);
  }
}

bool holds(const Vec3& lower, const Vec3& upper, const std::vector<Vec3>& points, double slack) {
  for (const Vec3& p : points)
    if ((p.array() < lower.array() - slack).any() || (p.array() > upper.array() + slack).any()) return false;
  return true;
}

TEST(MeshShape, BoundsHoldTheMeshAtATimeAndOverAStep) {
  const MeshShape shape = three_frames(1.5, Vec3(0.1, 0.2, 0.3));
  Vec3 lower, upper, exact_lower, exact_upper;
  for (int k = 0; k < 3; ++k) {  // exact at the frames' times
    shape.bounds_at(0.1 * k, lower, upper);
    bounding_box(shape.frame(k), exact_lower, exact_upper);
    EXPECT_LT((lower - exact_lower).norm(), 1e-15);
    EXPECT_LT((upper - exact_upper).norm(), 1e-15);
  }
  for (double t = -0.05; t < 0.3; t += 0.0125) {
    shape.bounds_at(t, lower, upper);
    EXPECT_TRUE(holds(lower, upper, shape.vertices_at(t), 1e-14)) << t;
  }
  // Over steps across zero, one or two frame times, the swept box holds every pose in between.
  for (const auto& [t0, t1] : {std::pair{0.02, 0.04}, std::pair{0.05, 0.15}, std::pair{-0.1, 0.25}}) {
    shape.swept_bounds(t0, t1, lower, upper);
    for (int s = 0; s <= 40; ++s)
      EXPECT_TRUE(holds(lower, upper, shape.vertices_at(t0 + (t1 - t0) * s / 40.0), 1e-14)) << t0 << " " << t1;
  }
  // Over (0.05, 0.15) the swept box reaches frame 1's top, above both ends' boxes.
  shape.swept_bounds(0.05, 0.15, lower, upper);
  bounding_box(shape.frame(1), exact_lower, exact_upper);
  EXPECT_DOUBLE_EQ(upper.z(), exact_upper.z());
}

// The field of the Error that `call` throws, or "(no error)".
template <class Call>
std::string error_field(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.field();
  }
  return "(no error)";
}

TEST(MeshShape, BadSettingsAreRefusedNamingTheirKey) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<TriangleMesh> frames{tetrahedron(), tetrahedron(Vec3(1, 0, 0))};
  for (double fps : {0.0, -24.0, nan, inf})
    EXPECT_EQ(error_field([&] { MeshShape::sequence(frames, fps); }), "fps") << fps;
  for (double scale : {0.0, -1.0, nan, inf})
    EXPECT_EQ(error_field([&] { MeshShape::single(tetrahedron(), scale); }), "scale") << scale;
  EXPECT_EQ(error_field([&] { MeshShape::single(tetrahedron(), 1.0, Vec3(0, nan, 0)); }), "offset");
  EXPECT_EQ(error_field([&] { MeshShape::sequence({}, 30.0); }), "sequence");
  EXPECT_TRUE(
      testing::throws_error([&] { MeshShape::sequence(frames, 0.0); }, "fps: must be a positive finite number, got 0"));

  TriangleMesh changed = tetrahedron();
  changed.triangles[1] = {0, 3, 1};
  EXPECT_EQ(error_field([&] { MeshShape::sequence({tetrahedron(), changed}, 30.0); }), "sequence");
  TriangleMesh extra = tetrahedron();
  extra.vertices.push_back(Vec3(2, 2, 2));
  EXPECT_EQ(error_field([&] { MeshShape::sequence({tetrahedron(), extra}, 30.0); }), "sequence");
  TriangleMesh non_finite = tetrahedron();
  non_finite.vertices[2].x() = inf;
  EXPECT_EQ(error_field([&] { MeshShape::sequence({tetrahedron(), non_finite}, 30.0); }), "sequence");

  TriangleMesh bad = tetrahedron();
  bad.triangles[0] = {0, 2, 4};
  EXPECT_EQ(error_field([&] { MeshShape::single(bad); }), "mesh");
  bad.triangles[0] = {0, 2, 2};
  EXPECT_EQ(error_field([&] { MeshShape::single(bad); }), "mesh");
  EXPECT_EQ(error_field([&] { MeshShape::single(TriangleMesh{}); }), "mesh");
}

TEST(MeshShape, ASequenceOfFilesLoadsAndMoves) {
  const testing::TempDir tmp;
  tmp.write("box0000.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  tmp.write("box0001.obj", "v 0 0 2\nv 1 0 2\nv 0 1 2\nv 0 0 3\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  const MeshShape shape =
      MeshShape::sequence(read_obj_sequence((tmp.path() / "box").string()), 4.0, 1.0, Vec3(1, 0, 0));
  EXPECT_EQ(shape.fps(), 4.0);
  expect_vertices(shape.vertices_at(0.125), {Vec3(1, 0, 1), Vec3(2, 0, 1), Vec3(1, 1, 1), Vec3(1, 0, 2)}, 1e-15);
  expect_vertices(shape.vertices_at(1.0), {Vec3(1, 0, 2), Vec3(2, 0, 2), Vec3(1, 1, 2), Vec3(1, 0, 3)}, 0.0);
}

}  // namespace
}  // namespace fnopt
