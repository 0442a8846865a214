#pragma once
// How close a rollout came to its obstacles (docs/design.md §8, §14), each frame's obstacles posed
// at its time (frame f at f dt), the smallest over every obstacle and frame of:
//  * an analytic obstacle: the signed distance d_k(x_i) over the cloth's vertices, negative
//    where a vertex is inside;
//  * a mesh obstacle (the mesh posed by Obstacle::mesh_vertices): the unsigned distance between
//    the cloth's surface and the mesh's, the smallest of the cloth-vertex/mesh-triangle,
//    mesh-vertex/cloth-triangle and cloth-edge/mesh-edge distances (closed primitives, the
//    cloth triangulated as Grid::triangles() does; a mesh vertex on no triangle is not on its
//    surface and is left out). A cloth through the mesh is not negative here: the mesh
//    intersection count (mesh_intersections.hpp) says that.
// The contact's guarantee is a value of at least the contact thickness (up to the float storage
// of the frames). `fnopt evaluate` prints it as "min obstacle distance = D m".
//
// The mesh's distance is metrics/surface_distance.hpp's.
#include <vector>

#include <Eigen/Core>

#include <fnopt/contact/obstacle.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// The smallest distance of one state of a rows x cols cloth at time t; +inf without obstacles.
// Throws Error where positions' size is not 3 rows cols and there is a mesh obstacle.
double min_obstacle_distance(const std::vector<Obstacle>& obstacles, const VecX& positions, int rows, int cols,
                             double time);
// Over the frames of a rollout of `scene` (positions as stored, frame f at time f scene.dt).
double min_obstacle_distance(const Scene& scene, const std::vector<Eigen::VectorXf>& frames);

}  // namespace fnopt
