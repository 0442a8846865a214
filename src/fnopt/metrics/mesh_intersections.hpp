#pragma once
// Exact intersection counts of cloth frames: the independent referee of self-repulsion (§2) and of
// the obstacle contact's barrier and CCD (docs/design.md §14), sharing no code with them. Every
// decision is exact (exact_predicates.hpp): a pair touching at one point counts, no tolerance in
// either direction.
//
// The cloth is a grid of rows x cols vertices, vertex (i, j) = i cols + j, triangulated as
// Grid::triangles() does (each quad split along (i,j)-(i+1,j+1)); its edges are the unique edges
// of those triangles (horizontal, vertical and one diagonal per quad). A mesh's edges likewise.
//  * self-intersections: the (cloth edge, cloth triangle) pairs that meet, over the pairs that
//    share no vertex. A flat cloth has none. Two triangles that cross meet in a segment whose
//    ends are points where an edge of one meets the other, so a cloth through itself counts.
//  * mesh intersections: cloth edges meeting mesh triangles plus mesh edges meeting cloth
//    triangles (the second catches a mesh's sharp edge through a cloth triangle).
//
// Broad phase: a uniform grid of cells (side: the mean edge length; for two meshes the larger
// of the two means) hashed into buckets, holding each triangle in every cell its bounding box
// overlaps. An edge is tested against the triangles of the cells its box overlaps, a pair only
// in the lowest cell both boxes overlap (so once), and only if the boxes overlap (compared with
// <=, so touching boxes are candidates). The cell of a coordinate is floor((x - origin) / side),
// monotone in x, so boxes that overlap always share a cell. A box over more than 64 cells (a
// stretched or diverged frame) is tested against everything instead, so no frame can blow up the
// grid. OpenMP over the edges; the count does not depend on the thread count.
//
// Non-finite coordinates throw Error: a frame with a NaN has no shape to check, and counting
// nothing would report a diverged frame as free of intersections.
#include <vector>

#include <Eigen/Core>

#include <fnopt/io/trajectory_frames.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class Obstacle;
struct Scene;

// Whether the closed segment pq and the closed triangle abc share a point, exactly. A segment
// that reaches the triangle's plane at one point X meets it where X lies on no edge's outer side
// (the signs of the volumes of pq with each edge, orient3d). A segment in the plane is compared
// with the triangle in 2D after dropping the axis of the triangle normal's largest component
// (checked exactly to be non-zero), with orient2d. A degenerate triangle (collinear or
// coincident vertices) is the segment or point they span: it meets pq where one of its edges
// ab, bc, ca does. A zero-length segment p = q is the point p.
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// Self-intersections of one frame: positions holds 3 floats per vertex (as rollout frames are
// stored), converted to double exactly. Throws Error when rows or cols < 1, positions' size is
// not 3 rows cols, or a coordinate is not finite.
long count_self_intersections(const Eigen::VectorXf& positions, int rows, int cols);

// Cloth-mesh intersections of one frame (the mesh posed for it). Throws Error as above, and when
// a mesh vertex is not finite or a triangle's index is outside the mesh's vertices. A mesh
// triangle with a repeated index contributes its distinct edges only.
long count_mesh_intersections(const Eigen::VectorXf& cloth_positions, int rows, int cols,
                              const std::vector<Vec3>& mesh_vertices,
                              const std::vector<Eigen::Vector3i>& mesh_triangles);

// Self-intersections over every frame of a trajectory (fnopt evaluate's `self-intersections`).
struct TrajectoryIntersections {
  long crossings = 0;       // summed over the frames
  int frames_with_any = 0;  // frames with at least one
};
TrajectoryIntersections count_trajectory_self_intersections(const TrajectoryFrames& frames);

// Mesh intersections over every frame of a trajectory and every mesh obstacle among `obstacles`,
// frame f's meshes posed at time f dt by Obstacle::mesh_vertices (the obstacle's shape and
// motion, not its contact code); fnopt evaluate's `mesh intersections`. None without a mesh.
TrajectoryIntersections count_trajectory_mesh_intersections(const TrajectoryFrames& frames,
                                                            const std::vector<Obstacle>& obstacles, double dt);

// The crossings compare and the stability suite report for a rollout of `scene`: on a scene with
// contact (obstacles or self-contact), the self-intersections summed over the frames and, with a
// mesh obstacle, the mesh intersections; -1 where not measured (a scene without contact, which
// costs nothing).
struct SceneCrossings {
  long self = -1, mesh = -1;
};
SceneCrossings count_scene_crossings(const Scene& scene, const TrajectoryFrames& frames);

}  // namespace fnopt
