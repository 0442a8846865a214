#pragma once
// Bilinear resampling of per-vertex fields (positions, velocities, accelerations) between two
// grids of the same cloth, of any sizes, square or not: restriction (fine -> coarse) and
// prolongation (coarse -> fine) are the same operation, sampling the source grid's bilinear
// interpolant at the target grid's vertices.
//
// Both grids are placed by their rest coordinates (cloth/grid.hpp): vertex (i, j) at
// (j h, -i h), so the top-left vertices coincide (where the `corner` handles are) and a grid
// covers (C-1)h x (R-1)h. Cells stay square, so two grids of one cloth can differ slightly in
// aspect ratio (17x23 covers 16/22 x 1, 32x45 covers 31/44 x 1): a target vertex beyond the
// source's extent gets the bilinear function of the nearest boundary cell, extended. Fields
// that are linear in the rest coordinates are therefore reproduced exactly everywhere, and the
// rest pose of one grid samples to the rest pose of the other.
#include <vector>

#include <fnopt/cloth/grid.hpp>

namespace fnopt {

class GridResampler {
 public:
  // Throws Error("grid resampling: ...") for a grid with fewer than 2 rows or columns or a
  // spacing that is not positive and finite.
  GridResampler(const Grid& from, const Grid& to);

  const Grid& from() const { return from_; }
  const Grid& to() const { return to_; }

  // `field` holds `components` values per vertex of from() (vertex-major, the VecX layout of
  // util/types.hpp); the result the same per vertex of to(). Throws Error naming the sizes if
  // the field does not fit from().
  VecX apply(const VecX& field, int components = 3) const;
  void apply(const VecX& field, VecX& out, int components = 3) const;

 private:
  struct Stencil {
    int corner = 0;             // source vertex (i0, j0), top-left of the cell used
    double fi = 0.0, fj = 0.0;  // offsets in cells from it (outside [0, 1]: extended)
  };
  Grid from_, to_;
  std::vector<Stencil> stencils_;  // one per target vertex
};

// One-shot forms of GridResampler(from, to).apply(field, components).
VecX restrict_field(const Grid& fine, const VecX& field, const Grid& coarse, int components = 3);
VecX prolong_field(const Grid& coarse, const VecX& field, const Grid& fine, int components = 3);

// The grid of the same cloth with `longer_edge` vertices along its longer edge and the other
// edge rounded to keep the aspect ratio (at least 3): 32 gives 32x32 for a square grid, 16x32
// for 32x64, 19x32 for 48x80. Throws Error if longer_edge < 3.
Grid grid_with_longer_edge(const Grid& grid, int longer_edge);

// The vertex of `grid` nearest to vertex `vertex` of `other` by rest position (clamped to the
// grid), e.g. where a handle of a fine grid lands on a coarse one.
int nearest_vertex(const Grid& grid, const Grid& other, int vertex);

}  // namespace fnopt
