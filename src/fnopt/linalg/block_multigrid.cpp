#include <fnopt/linalg/block_multigrid.hpp>

#include <algorithm>

#include <fnopt/linalg/block_pattern.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

namespace {

// Coarse points of a line of n grid points: every other one and the last, coarse k at
// min(2k, n - 1).
int coarse_count(int n) { return n % 2 == 0 ? n / 2 + 1 : (n + 1) / 2; }

// Linear interpolation along the line: point i from one or two coarse points; returns how many.
int line_weights(int i, int n, int* k, double* w) {
  if (i % 2 == 0 || i == n - 1) {
    k[0] = i % 2 == 0 ? i / 2 : n / 2;
    w[0] = 1.0;
    return 1;
  }
  k[0] = (i - 1) / 2;
  k[1] = (i + 1) / 2;
  w[0] = w[1] = 0.5;
  return 2;
}

// The smoother's kernels work on four float lanes, the fourth ignored: a 3x3 block stored column by
// column is three overlapping 4-float columns (the last reads one float past the block: the next
// block's first, or the padding at the end of the array), so that B y is three broadcasts, products
// and sums instead of nine scalar ones. B^T y is the same kernel on B stored row by row.
using Lanes = Eigen::Array4f;

inline Lanes block_times(const float* B, const float* y) {
  return Eigen::Map<const Lanes>(B) * y[0] + Eigen::Map<const Lanes>(B + 3) * y[1] +
         Eigen::Map<const Lanes>(B + 6) * y[2];
}

// target[0..2] += B^T y, B stored row by row; target[3] is a slot of padding (Level::upper).
inline void add_transpose_times(const float* B_rows, const float* y, float* target) {
  Eigen::Map<Lanes>(target) += block_times(B_rows, y);
}

// sum_k A_ik x_k over the blocks [begin, end) of a row (block k at values + 9k, in column column[k]).
// Two partial sums, so that consecutive blocks' products do not wait on each other's additions.
inline Lanes row_product(const int* column, const float* values, int begin, int end, const float* x) {
  Lanes a = Lanes::Zero(), c = Lanes::Zero();
  int k = begin;
  for (; k + 1 < end; k += 2) {
    a += block_times(values + 9 * k, x + 3 * column[k]);
    c += block_times(values + 9 * (k + 1), x + 3 * column[k + 1]);
  }
  if (k < end) a += block_times(values + 9 * k, x + 3 * column[k]);
  return a + c;
}

}  // namespace

void BlockMultigridParams::validate() const {
  require(smoothing_sweeps > 0, "multigrid.smoothing_sweeps", "must be positive");
  require(coarsest_dofs >= 3, "multigrid.coarsest_dofs", "must be at least 3");
}

BlockMultigrid::BlockMultigrid(BlockMultigridParams params) : params_(params) { params_.validate(); }

void BlockMultigrid::build_hierarchy(const Eigen::SparseMatrix<double>& A, const Grid& grid,
                                     const std::vector<int>& free_index) {
  levels_.clear();
  Level fine;
  fine.grid_rows = grid.rows;
  fine.grid_cols = grid.cols;
  fine.unknown = free_index;
  require(static_cast<int>(free_index.size()) == grid.vertex_count(), "multigrid",
          "free index does not match the grid");
  fine.unknowns = static_cast<int>(std::count_if(free_index.begin(), free_index.end(), [](int f) { return f >= 0; }));
  require(A.rows() == 3 * fine.unknowns && A.cols() == A.rows() && A.isCompressed(), "multigrid",
          "the matrix is not 3 dofs per free vertex");
  BlockPattern pattern = read_block_pattern(A, "multigrid");
  fine.row_start = std::move(pattern.row_start);
  fine.column = std::move(pattern.column);
  levels_.push_back(std::move(fine));
  for (;;) {
    Level& last = levels_.back();
    const bool shrinks = coarse_count(last.grid_rows) < last.grid_rows || coarse_count(last.grid_cols) < last.grid_cols;
    if (3 * last.unknowns <= params_.coarsest_dofs || !shrinks) break;
    Level coarse = coarsen(last);
    levels_.push_back(std::move(coarse));
  }
  for (Level& level : levels_) {
    const int n = level.unknowns;
    level.diagonal.assign(n, -1);
    for (int i = 0; i < n; ++i)
      for (int k = level.row_start[i]; k < level.row_start[i + 1]; ++k)
        if (level.column[k] == i) level.diagonal[i] = k;
    require(std::all_of(level.diagonal.begin(), level.diagonal.end(), [](int k) { return k >= 0; }), "multigrid",
            "a free vertex has no diagonal block");
    level.values.resize(9 * level.column.size());
    level.lower_start.assign(1, 0);
    level.lower_column.clear();
    for (int i = 0; i < n; ++i) {
      level.lower_column.insert(level.lower_column.end(), level.column.begin() + level.row_start[i],
                                level.column.begin() + level.diagonal[i]);
      level.lower_start.push_back(static_cast<int>(level.lower_column.size()));
    }
    // + the padding the kernels' last column reads.
    level.lower_values.assign(9 * level.lower_column.size() + 1, 0.0f);
    level.lower_rows.assign(9 * level.lower_column.size() + 1, 0.0f);
    level.diagonal_inverse.assign(9 * static_cast<std::size_t>(n) + 1, 0.0f);
    level.x.resize(3 * n);
    level.b.resize(3 * n);
    level.upper.resize(4 * static_cast<std::size_t>(n));
  }
}

BlockMultigrid::Level BlockMultigrid::coarsen(Level& fine) const {
  Level coarse;
  coarse.grid_rows = coarse_count(fine.grid_rows);
  coarse.grid_cols = coarse_count(fine.grid_cols);
  // Each fine unknown's bilinear weights on coarse grid vertices.
  std::vector<int> start(1, 0), vertex;
  std::vector<double> weight;
  start.reserve(fine.unknowns + 1);
  for (int v = 0; v < fine.grid_rows * fine.grid_cols; ++v) {
    if (fine.unknown[v] < 0) continue;
    require(fine.unknown[v] == static_cast<int>(start.size()) - 1, "multigrid",
            "free vertices not numbered in grid order");
    int ki[2], kj[2];
    double wi[2], wj[2];
    const int ni = line_weights(v / fine.grid_cols, fine.grid_rows, ki, wi);
    const int nj = line_weights(v % fine.grid_cols, fine.grid_cols, kj, wj);
    for (int a = 0; a < ni; ++a)
      for (int b = 0; b < nj; ++b) {
        vertex.push_back(ki[a] * coarse.grid_cols + kj[b]);
        weight.push_back(wi[a] * wj[b]);
      }
    start.push_back(static_cast<int>(vertex.size()));
  }
  // The coarse vertices some fine unknown interpolates from are the coarse unknowns, in grid order.
  std::vector<char> used(static_cast<std::size_t>(coarse.grid_rows) * coarse.grid_cols, 0);
  for (int c : vertex) used[c] = 1;
  coarse.unknown.resize(used.size());
  for (std::size_t c = 0; c < used.size(); ++c) coarse.unknown[c] = used[c] ? coarse.unknowns++ : -1;
  fine.prolong_start = start;
  fine.prolong_index.resize(vertex.size());
  fine.prolong_weight.resize(vertex.size());
  for (std::size_t e = 0; e < vertex.size(); ++e) {
    fine.prolong_index[e] = coarse.unknown[vertex[e]];
    fine.prolong_weight[e] = static_cast<float>(weight[e]);
  }
  // The coarse pattern: block (p, q) wherever some fine block (i, j) has p in i's and q in j's
  // interpolation.
  std::vector<std::vector<int>> rows(coarse.unknowns);
  for (int i = 0; i < fine.unknowns; ++i)
    for (int k = fine.row_start[i]; k < fine.row_start[i + 1]; ++k) {
      const int j = fine.column[k];
      for (int a = start[i]; a < start[i + 1]; ++a)
        for (int b = start[j]; b < start[j + 1]; ++b) rows[fine.prolong_index[a]].push_back(fine.prolong_index[b]);
    }
  coarse.row_start.assign(1, 0);
  for (std::vector<int>& row : rows) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    coarse.column.insert(coarse.column.end(), row.begin(), row.end());
    coarse.row_start.push_back(static_cast<int>(coarse.column.size()));
  }
  // The slot table of the Galerkin sum.
  fine.galerkin_start.assign(1, 0);
  fine.galerkin_slot.clear();
  fine.galerkin_weight.clear();
  for (int i = 0; i < fine.unknowns; ++i)
    for (int k = fine.row_start[i]; k < fine.row_start[i + 1]; ++k) {
      const int j = fine.column[k];
      for (int a = start[i]; a < start[i + 1]; ++a) {
        const int p = fine.prolong_index[a];
        const auto first = coarse.column.begin() + coarse.row_start[p],
                   last = coarse.column.begin() + coarse.row_start[p + 1];
        for (int b = start[j]; b < start[j + 1]; ++b) {
          fine.galerkin_slot.push_back(
              static_cast<int>(std::lower_bound(first, last, fine.prolong_index[b]) - coarse.column.begin()));
          fine.galerkin_weight.push_back(weight[a] * weight[b]);
        }
      }
      fine.galerkin_start.push_back(static_cast<int>(fine.galerkin_slot.size()));
    }
  return coarse;
}

void BlockMultigrid::copy_fine_values(const Eigen::SparseMatrix<double>& A) {
  Level& fine = levels_.front();
  const double* a = A.valuePtr();
  for (int i = 0; i < fine.unknowns; ++i)
    for (int k = fine.row_start[i]; k < fine.row_start[i + 1]; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) fine.values[9 * k + 3 * r + c] = a[block_entry(A, i, k - fine.row_start[i], r, c)];
}

bool BlockMultigrid::prepare_smoother(Level& level) {
  // The blocks left of the diagonal, column by column and row by row (values holds each block row by row).
  float* lower = level.lower_values.data();
  float* rows = level.lower_rows.data();
  for (int i = 0; i < level.unknowns; ++i)
    for (int k = level.row_start[i]; k < level.diagonal[i]; ++k, lower += 9, rows += 9)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          lower[3 * c + r] = static_cast<float>(level.values[9 * k + 3 * r + c]);
          rows[3 * r + c] = lower[3 * c + r];
        }
  for (int i = 0; i < level.unknowns; ++i) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> block(&level.values[9 * level.diagonal[i]]);
    const Eigen::LLT<Mat3> llt(block);
    if (llt.info() != Eigen::Success) return false;
    Eigen::Map<Eigen::Matrix3f>(&level.diagonal_inverse[9 * i]) = llt.solve(Mat3::Identity()).cast<float>();
  }
  return true;
}

bool BlockMultigrid::assign(const Eigen::SparseMatrix<double>& A, const Grid& grid, const std::vector<int>& free_index,
                            long pattern) {
  if (levels_.empty() || pattern < 0 || pattern != pattern_) {
    pattern_ = -1;
    build_hierarchy(A, grid, free_index);
    pattern_ = pattern;
  }
  copy_fine_values(A);
  for (std::size_t l = 0; l + 1 < levels_.size(); ++l) {
    const Level& fine = levels_[l];
    Level& coarse = levels_[l + 1];
    std::fill(coarse.values.begin(), coarse.values.end(), 0.0);
    for (std::size_t k = 0; k < fine.column.size(); ++k) {
      const double* block = &fine.values[9 * k];
      for (int e = fine.galerkin_start[k]; e < fine.galerkin_start[k + 1]; ++e) {
        double* target = &coarse.values[9 * static_cast<std::size_t>(fine.galerkin_slot[e])];
        const double w = fine.galerkin_weight[e];
        for (int c = 0; c < 9; ++c) target[c] += w * block[c];
      }
    }
  }
  for (Level& level : levels_)
    if (!prepare_smoother(level)) return false;
  const Level& last = levels_.back();
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * last.unknowns, 3 * last.unknowns);
  for (int i = 0; i < last.unknowns; ++i)
    for (int k = last.row_start[i]; k < last.row_start[i + 1]; ++k)
      dense.block<3, 3>(3 * i, 3 * last.column[k]) =
          Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&last.values[9 * k]);
  coarsest_.compute(dense);
  coarsest_rhs_.resize(dense.rows());
  return coarsest_.info() == Eigen::Success;
}

void BlockMultigrid::forward_sweep(Level& level, bool from_zero) {
  // x_i <- D_i^-1 (b_i - sum_{j < i} A_ij x_j - upper_i), upper = U x before the sweep (0 from x = 0).
  // From x = 0 the residual after the sweep is -U x (cycle()): scattered from each row as soon as its
  // x_i is known, so that the one read of row i serves both (as in backward_sweep).
  const int* column = level.lower_column.data();
  const float* lower = level.lower_values.data();
  const float* rows = level.lower_rows.data();
  float* x = level.x.data();
  float* upper = level.upper.data();
  if (from_zero) std::fill(level.upper.begin(), level.upper.end(), 0.0f);
  for (int i = 0; i < level.unknowns; ++i) {
    const int begin = level.lower_start[i], end = level.lower_start[i + 1];
    const float* b = &level.b[3 * i];
    Lanes s = Lanes(b[0], b[1], b[2], 0.0f) - row_product(column, lower, begin, end, x);
    if (!from_zero) s -= Lanes(upper[4 * i], upper[4 * i + 1], upper[4 * i + 2], 0.0f);
    const Lanes next = block_times(&level.diagonal_inverse[9 * i], s.data());
    std::copy_n(next.data(), 3, x + 3 * i);
    if (from_zero) {
      const float minus_next[3] = {-next[0], -next[1], -next[2]};
      for (int k = begin; k < end; ++k) add_transpose_times(rows + 9 * k, minus_next, upper + 4 * column[k]);
    }
  }
}

void BlockMultigrid::add_upper_product(const Level& level, const float* y, float* out, float sign) {
  // (U y)_j = sum_{i > j} A_ji y_i = sum_{i > j} A_ij^T y_i: row i of the lower triangle, scattered.
  const int* column = level.lower_column.data();
  const float* rows = level.lower_rows.data();
  for (int i = 0; i < level.unknowns; ++i) {
    const float signed_y[3] = {sign * y[3 * i], sign * y[3 * i + 1], sign * y[3 * i + 2]};
    for (int k = level.lower_start[i]; k < level.lower_start[i + 1]; ++k)
      add_transpose_times(rows + 9 * k, signed_y, out + 4 * column[k]);
  }
}

void BlockMultigrid::backward_sweep(Level& level) {
  // In reverse order, x_i <- D_i^-1 (b_i - sum_{j < i} A_ij x_j - upper_i), upper_i = sum_{j > i} A_ij x_j
  // of the x_j this sweep has already updated: scattered from each row as soon as its x_i is new, so
  // that the one read of row i serves both sums.
  const int* column = level.lower_column.data();
  const float* lower = level.lower_values.data();
  const float* rows = level.lower_rows.data();
  float* x = level.x.data();
  float* upper = level.upper.data();
  std::fill(level.upper.begin(), level.upper.end(), 0.0f);
  for (int i = level.unknowns - 1; i >= 0; --i) {
    const int begin = level.lower_start[i], end = level.lower_start[i + 1];
    const float* b = &level.b[3 * i];
    const Lanes s = Lanes(b[0] - upper[4 * i], b[1] - upper[4 * i + 1], b[2] - upper[4 * i + 2], 0.0f) -
                    row_product(column, lower, begin, end, x);
    const Lanes next = block_times(&level.diagonal_inverse[9 * i], s.data());
    std::copy_n(next.data(), 3, x + 3 * i);
    for (int k = begin; k < end; ++k) add_transpose_times(rows + 9 * k, next.data(), upper + 4 * column[k]);
  }
}

void BlockMultigrid::cycle(std::size_t l) {
  Level& level = levels_[l];
  if (l + 1 == levels_.size()) {
    for (int e = 0; e < 3 * level.unknowns; ++e) coarsest_rhs_[e] = level.b[e];
    coarsest_.solveInPlace(coarsest_rhs_);
    for (int e = 0; e < 3 * level.unknowns; ++e) level.x[e] = static_cast<float>(coarsest_rhs_[e]);
    return;
  }
  // The smoother reads only the blocks left of the diagonal (A is symmetric): a forward sweep gathers
  // them row by row; the blocks right of the diagonal, U, are their transposes, scattered. The first
  // sweep starts from x = 0, where U x = 0. Each forward sweep leaves row i's equation exact for the
  // x_j (j > i) before it, x_j - dx_j with dx_j its change, so the residual is b - A x = -U dx: after
  // the first sweep -U x, scattered by the sweep itself. With one sweep each way a cycle reads the
  // blocks left of the diagonal twice where it read all of A three times, and it scatters from their
  // copy stored row by row, so that each transpose's product is one four-lane kernel like the gather's
  // instead of three dot products (docs/results.md, "The reference's kernels", "The smoother's scatter
  // in four lanes").
  float* x = level.x.data();
  forward_sweep(level, true);  // and upper = -U x, the residual
  for (int s = 1; s < params_.smoothing_sweeps; ++s) {
    level.change.assign(level.x.begin(), level.x.end());
    std::fill(level.upper.begin(), level.upper.end(), 0.0f);
    add_upper_product(level, x, level.upper.data(), 1.0f);
    forward_sweep(level, false);
  }
  if (params_.smoothing_sweeps > 1) {
    for (int e = 0; e < 3 * level.unknowns; ++e) level.change[e] = level.x[e] - level.change[e];
    std::fill(level.upper.begin(), level.upper.end(), 0.0f);
    add_upper_product(level, level.change.data(), level.upper.data(), -1.0f);
  }
  // b_c = R^T r.
  Level& coarse = levels_[l + 1];
  std::fill(coarse.b.begin(), coarse.b.end(), 0.0f);
  for (int i = 0; i < level.unknowns; ++i) {
    const float* r = &level.upper[4 * i];
    for (int e = level.prolong_start[i]; e < level.prolong_start[i + 1]; ++e) {
      float* target = &coarse.b[3 * level.prolong_index[e]];
      const float w = level.prolong_weight[e];
      target[0] += w * r[0];
      target[1] += w * r[1];
      target[2] += w * r[2];
    }
  }
  cycle(l + 1);
  for (int i = 0; i < level.unknowns; ++i)
    for (int e = level.prolong_start[i]; e < level.prolong_start[i + 1]; ++e) {
      const float* source = &coarse.x[3 * level.prolong_index[e]];
      const float w = level.prolong_weight[e];
      for (int c = 0; c < 3; ++c) x[3 * i + c] += w * source[c];
    }
  for (int s = 0; s < params_.smoothing_sweeps; ++s) backward_sweep(level);
}

void BlockMultigrid::solve_in_place(VecX& r) {
  Level& fine = levels_.front();
  for (int e = 0; e < 3 * fine.unknowns; ++e) fine.b[e] = static_cast<float>(r[e]);
  cycle(0);
  for (int e = 0; e < 3 * fine.unknowns; ++e) r[e] = fine.x[e];
}

}  // namespace fnopt
