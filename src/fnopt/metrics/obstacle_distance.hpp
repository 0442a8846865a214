#pragma once
// How close a rollout came to its obstacles (docs/design.md §8, §14): the smallest signed distance
// d_k(x_i) over every vertex i, obstacle k and frame, each frame's obstacles posed at its time
// (frame f at f dt). Negative where a vertex is inside an obstacle; the contact's guarantee is a
// value of at least the contact thickness (up to the float storage of the frames).
// `fnopt evaluate` prints it as "min obstacle distance = D m".
#include <vector>

#include <Eigen/Core>

#include <fnopt/contact/obstacle.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// The smallest d_k(x_i) of one state at time t; +inf without obstacles.
double min_obstacle_distance(const std::vector<Obstacle>& obstacles, const VecX& positions, double time);
// Over the frames of a rollout of `scene` (positions as stored, frame f at time f scene.dt).
double min_obstacle_distance(const Scene& scene, const std::vector<Eigen::VectorXf>& frames);

}  // namespace fnopt
