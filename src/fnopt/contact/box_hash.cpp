#include <fnopt/contact/box_hash.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

bool BoxHash::cell_range(const Box& box, CellRange& range) const {
  for (int d = 0; d < 3; ++d) {
    const double low = std::floor(box.lower[d] / cell_), high = std::floor(box.upper[d] / cell_);
    // Beyond 2^52 cells the cell of a coordinate is not exact (and a non-finite one has none).
    if (!(std::abs(low) < 4.5e15 && std::abs(high) < 4.5e15) || high < low) return false;
    range.low[d] = static_cast<std::int64_t>(low);
    range.high[d] = static_cast<std::int64_t>(high);
  }
  return true;
}

std::size_t BoxHash::bucket_of(const Cell& c) const {
  // Teschner et al. 2003's spatial hash of a cell's integer coordinates.
  const auto h = static_cast<std::uint64_t>(c[0]) * 73856093u ^ static_cast<std::uint64_t>(c[1]) * 19349663u ^
                 static_cast<std::uint64_t>(c[2]) * 83492791u;
  return static_cast<std::size_t>(h) & mask_;
}

void BoxHash::build(const std::vector<Box>& boxes, double cell) {
  require(std::isfinite(cell) && cell > 0.0, "box hash", "the cell must be a positive length");
  boxes_ = &boxes;
  cell_ = cell;
  std::size_t buckets = 2;
  while (buckets < 2 * boxes.size()) buckets *= 2;
  mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  oversized_.clear();
  stamp_.assign(boxes.size(), 0);
  query_ = 0;
  // Counting sort: the number of entries per bucket, then their places.
  auto for_each_cell = [&](int k, auto&& emit) {
    CellRange range;
    if (!cell_range(boxes[k], range) || range.count() > kMaxCells) return false;
    for (std::int64_t x = range.low[0]; x <= range.high[0]; ++x)
      for (std::int64_t y = range.low[1]; y <= range.high[1]; ++y)
        for (std::int64_t z = range.low[2]; z <= range.high[2]; ++z) emit(bucket_of({x, y, z}));
    return true;
  };
  for (int k = 0; k < static_cast<int>(boxes.size()); ++k)
    if (!for_each_cell(k, [&](std::size_t b) { ++bucket_start_[b + 1]; })) oversized_.push_back(k);
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  entries_.resize(bucket_start_[buckets]);
  next_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
  for (int k = 0; k < static_cast<int>(boxes.size()); ++k)
    for_each_cell(k, [&](std::size_t b) { entries_[next_[b]++] = k; });
}

}  // namespace fnopt
