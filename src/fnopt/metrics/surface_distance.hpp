#pragma once
// The unsigned distance between two triangle surfaces, or between the vertex-disjoint parts of one
// (docs/design.md §14): the smallest of the vertex–triangle distances both ways and the edge–edge
// distances of closed primitives. The closest-approach metrics build on it
// (obstacle_distance.hpp for a cloth and a mesh, cloth_distance.hpp for the cloth and itself).
//
// Each primitive of one side is a branch-and-bound search over a box tree of the other's
// (contact/box_tree.hpp), each search starting from the smallest distance found so far, so that
// two far surfaces cost about one box test per primitive.
#include <array>
#include <vector>

#include <fnopt/contact/box_tree.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

// One surface: its points, the triangles and edges on them and the points on some triangle (its
// vertices), with box trees over its triangles and edges.
struct DistanceSurface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> vertices;
  BoxTree triangle_tree, edge_tree;

  // The surface of these triangles: their distinct edges and the points on them.
  void set_triangles(std::vector<std::array<int, 3>> triangles);
  // The surface of a rows x cols cloth, triangulated as Grid::triangles() does (every vertex on it).
  void set_grid(int rows, int cols);
  // Places the trees on `points` as they are now: built the first time, refitted after (the
  // triangles stay the same, so a refitted tree keeps every search exact).
  void place();
};

// The distance between the surfaces a and b (both placed).
double surface_distance(const DistanceSurface& a, const DistanceSurface& b);
// The smallest distance between vertex-disjoint primitives of one surface (placed): a vertex and a
// triangle not holding it, two edges sharing no vertex. +inf for a surface without such a pair.
double disjoint_self_distance(const DistanceSurface& surface);

}  // namespace fnopt
