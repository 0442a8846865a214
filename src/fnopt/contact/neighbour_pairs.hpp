#pragma once
// The self-contact pairs between primitives one grid step apart (docs/design.md §14): a vertex and a
// triangle, or two edges, that share no vertex while a vertex of one is within one step of a vertex of
// the other, |i - k| <= 1 and |j - l| <= 1. A grid holds about 26 such point-triangle pairs per vertex
// and more edge pairs, all h/sqrt(2) or more apart at rest, and they come near each other only where the
// cloth creases within a cell. Each is kept with a separating plane it had at rest, through primitive
// features and moving with them:
//  * through an edge ab of a triangle abc, perpendicular to that triangle, facing away from c; or
//  * through a vertex b, perpendicular to an edge ab, facing away from a;
// chosen so that one primitive lies on its back side (in the plane or behind it) and the other's
// points lie in front, as far as possible at rest. The signed distance of the front primitive's
// vertices to the plane, at any state, is then a lower bound of the pair's distance (every point of
// the front primitive is a convex combination of them, every point of the back one has a signed
// distance of at most 0): a few flops that clear a flat or gently curved cloth's pairs without
// computing their distances.
#include <array>
#include <vector>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/self_contact_pair.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

// The planes' normals at a state, computed once for all pairs: per triangle abc the in-plane normals
// of its edges ab, bc, ca facing out (away from the third vertex), per edge ab its direction b - a,
// all of unit length (zero for a degenerate feature, which bounds nothing).
class PlaneNormals {
 public:
  void compute(const VecX& x, const std::vector<std::array<int, 3>>& triangles,
               const std::vector<std::array<int, 2>>& edges);
  const Vec3& triangle_edge(int t, int k) const { return triangle_edges_[3 * t + k]; }
  const Vec3& edge(int e) const { return edges_[e]; }

 private:
  std::vector<Vec3> triangle_edges_, edges_;
};

struct SeparatingPlane {
  enum class Kind : int {
    EdgeOfTriangle,  // through edge k of triangle `feature`, perpendicular to it, facing out
    AlongEdge,       // through `origin`, the second end of edge `feature`, facing along it
    AgainstEdge,     // through `origin`, its first end, facing against it
  };
  Kind kind;
  int feature;               // a triangle or an edge
  int slot;                  // the triangle's edge (EdgeOfTriangle)
  int origin;                // a vertex on the plane
  std::array<int, 2> front;  // the front primitive's vertices (front[1] = -1 for a point)

  // The smallest signed distance of the front vertices at x: at most the pair's distance
  // (-inf where the plane is degenerate). `normals` must be of the same x.
  double separation(const VecX& x, const PlaneNormals& normals) const;
};

struct NeighbourPair {
  SelfContactPair pair;
  SeparatingPlane plane;
};

// Every neighbour pair of the grid with its plane, sorted by pair. `triangles` and `edges` are the
// term's (Grid::triangles() in its order, and their unique edges sorted).
std::vector<NeighbourPair> neighbour_pairs(const Grid& grid, const std::vector<std::array<int, 3>>& triangles,
                                           const std::vector<std::array<int, 2>>& edges);

}  // namespace fnopt
