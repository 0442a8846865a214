#include <fnopt/cloth/spatial_hash.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

std::size_t SpatialHash::bucket_of(const Cell& c) const {
  // Teschner et al. 2003 primes; the mask keeps the low bits of the mixed key.
  const std::uint64_t key = static_cast<std::uint64_t>(c[0]) * 73856093ULL ^
                            static_cast<std::uint64_t>(c[1]) * 19349663ULL ^
                            static_cast<std::uint64_t>(c[2]) * 83492791ULL;
  return static_cast<std::size_t>((key ^ (key >> 29)) & mask_);
}

void SpatialHash::build(const VecX& x, double cell) {
  require(std::isfinite(cell) && cell > 0.0, "spatial hash", "cell size must be positive");
  cell_ = cell;
  const int n = static_cast<int>(x.size() / 3);
  std::size_t table = 16;
  while (table < 2 * static_cast<std::size_t>(n)) table *= 2;
  mask_ = table - 1;
  cells_.resize(n);
  bucket_start_.assign(table + 1, 0);
  sorted_.resize(n);
  const double inverse = 1.0 / cell;
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) cells_[k][c] = static_cast<std::int64_t>(std::floor(x[3 * k + c] * inverse));
    ++bucket_start_[bucket_of(cells_[k]) + 1];
  }
  for (std::size_t b = 0; b < table; ++b) bucket_start_[b + 1] += bucket_start_[b];
  // Fill each bucket in increasing point order (stable counting sort), using bucket_start_ as
  // the cursor and shifting it back afterwards.
  for (int k = 0; k < n; ++k) sorted_[bucket_start_[bucket_of(cells_[k])]++] = k;
  for (std::size_t b = table; b > 0; --b) bucket_start_[b] = bucket_start_[b - 1];
  bucket_start_[0] = 0;
}

void SpatialHash::pairs_within(const VecX& x, double radius, std::vector<Pair>& out) const {
  require(radius <= cell_ * (1.0 + 1e-12), "spatial hash", "query radius exceeds the cell size");
  const int n = static_cast<int>(cells_.size());
  const double r2 = radius * radius;
  for (int i = 0; i < n; ++i) {
    const std::size_t first = out.size();
    const Cell& ci = cells_[i];
    const Vec3 xi = x.segment<3>(3 * i);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Cell c{ci[0] + dx, ci[1] + dy, ci[2] + dz};
          const std::size_t b = bucket_of(c);
          for (int p = bucket_start_[b]; p < bucket_start_[b + 1]; ++p) {
            const int j = sorted_[p];
            if (j <= i || cells_[j] != c) continue;
            const double d2 = (x.segment<3>(3 * j) - xi).squaredNorm();
            if (d2 < r2) out.push_back({i, j, std::sqrt(d2)});
          }
        }
    // The 27 cells are visited in a fixed order, not by j: sort this point's pairs.
    std::sort(out.begin() + first, out.end(),
              [](const Pair& a, const Pair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  }
}

}  // namespace fnopt
