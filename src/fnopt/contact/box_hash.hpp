#pragma once
// Uniform-grid hash of axis-aligned boxes: the broad phase of self-contact (docs/design.md §14).
// Each box is binned into every cubic cell of side `cell` that it overlaps; a cell (cx, cy, cz)
// maps to one of T >= 2n buckets by a hash of its integer coordinates, stored CSR-style (counting
// sort, no per-cell allocation). A query visits the buckets of the cells its box overlaps and
// reports every stored box that overlaps it (closed boxes: touching counts), each once. A box over
// more than kMaxCells cells (a fast or stretched primitive) is kept apart and tested against every
// query instead, so that no box can blow up the table. Buffers are reused between builds.
#include <array>
#include <cstdint>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct Box {
  Vec3 lower = Vec3::Constant(1e300), upper = Vec3::Constant(-1e300);

  void add(const Vec3& p) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  void add(const Box& b) {
    lower = lower.cwiseMin(b.lower);
    upper = upper.cwiseMax(b.upper);
  }
  void grow(double r) {
    lower.array() -= r;
    upper.array() += r;
  }
  bool overlaps(const Box& b) const {
    return (lower.array() <= b.upper.array()).all() && (b.lower.array() <= upper.array()).all();
  }
  bool contains(const Vec3& p) const { return (lower.array() <= p.array()).all() && (p.array() <= upper.array()).all(); }
  // The squared distance between the closed boxes (0 where they overlap): a lower bound on the
  // squared distance between anything inside one and anything inside the other. A point is the
  // box of one point.
  double squared_distance(const Box& b) const {
    return (lower - b.upper).cwiseMax(b.lower - upper).cwiseMax(0.0).squaredNorm();
  }
};

class BoxHash {
 public:
  static constexpr long kMaxCells = 64;

  // Bins `boxes` (kept by reference until the next build) into cells of side `cell` (> 0).
  void build(const std::vector<Box>& boxes, double cell);

  // Calls visit(k) once for every built box k that overlaps `query`.
  template <class Visit>
  void for_each_overlap(const Box& query, Visit&& visit) const {
    for_each_overlap(query, [](int) { return false; }, visit);
  }
  // The same, skipping the boxes k for which skip(k) (a test cheaper than the overlap's, made first).
  template <class Skip, class Visit>
  void for_each_overlap(const Box& query, Skip&& skip, Visit&& visit) const {
    ++query_;
    auto consider = [&](int k) {
      if (stamp_[k] == query_) return;
      stamp_[k] = query_;
      if (!skip(k) && (*boxes_)[k].overlaps(query)) visit(k);
    };
    for (int k : oversized_) consider(k);
    CellRange range;
    if (!cell_range(query, range) || range.count() > kMaxCells) {
      for (int k = 0; k < static_cast<int>(boxes_->size()); ++k) consider(k);
      return;
    }
    for (std::int64_t x = range.low[0]; x <= range.high[0]; ++x)
      for (std::int64_t y = range.low[1]; y <= range.high[1]; ++y)
        for (std::int64_t z = range.low[2]; z <= range.high[2]; ++z) {
          const std::size_t b = bucket_of({x, y, z});
          for (int e = bucket_start_[b]; e < bucket_start_[b + 1]; ++e) consider(entries_[e]);
        }
  }

 private:
  using Cell = std::array<std::int64_t, 3>;
  struct CellRange {
    Cell low, high;
    long count() const {
      long n = 1;
      for (int d = 0; d < 3; ++d) n *= static_cast<long>(high[d] - low[d] + 1);
      return n;
    }
  };
  // The cells a box overlaps; false for a box with a non-finite or far-out coordinate.
  bool cell_range(const Box& box, CellRange& range) const;
  std::size_t bucket_of(const Cell& c) const;

  const std::vector<Box>* boxes_ = nullptr;
  double cell_ = 1.0;
  std::size_t mask_ = 0;
  std::vector<int> bucket_start_;  // T + 1
  std::vector<int> entries_;       // box indices by bucket
  std::vector<int> oversized_;
  std::vector<int> next_;  // build scratch: the next free place of each bucket
  mutable std::vector<std::uint32_t> stamp_;  // per box: the last query that considered it
  mutable std::uint32_t query_ = 0;
};

}  // namespace fnopt
