#pragma once
// Uniform-grid spatial hash for close vertex pairs (self-repulsion, self-contact metrics).
// Points are binned into cubic cells of side `cell`; a cell (cx, cy, cz) maps to one of
// T >= 2n buckets by a hash of its integer coordinates, and the buckets are stored CSR-style
// (counting sort, no per-cell allocation). A query visits, for every point, the 27 cells around
// its own and keeps the points of exactly those cells (a bucket shared by two cells is filtered
// by the stored cell coordinates, so no pair is reported twice): every pair closer than
// `radius` <= `cell` is found once, as (i, j) with i < j.
// Buffers are reused between builds; building allocates only when the point count grows.
#include <array>
#include <cstdint>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class SpatialHash {
 public:
  struct Pair {
    int i, j;         // i < j
    double distance;  // |x_i - x_j|
  };

  // Bins the points x (3 coordinates each) into cells of side `cell` (> 0).
  void build(const VecX& x, double cell);
  // Appends to `out` every pair of the built points with |x_i - x_j| < radius (radius <= cell),
  // in increasing (i, j) order. `x` must be the positions given to build().
  void pairs_within(const VecX& x, double radius, std::vector<Pair>& out) const;

  double cell() const { return cell_; }

 private:
  using Cell = std::array<std::int64_t, 3>;
  std::size_t bucket_of(const Cell& c) const;

  double cell_ = 0.0;
  std::size_t mask_ = 0;
  std::vector<Cell> cells_;        // per point
  std::vector<int> bucket_start_;  // T + 1
  std::vector<int> sorted_;        // point indices by bucket
};

}  // namespace fnopt
