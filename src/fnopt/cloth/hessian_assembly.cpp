#include <fnopt/cloth/hessian_assembly.hpp>

#include <algorithm>
#include <cassert>

namespace fnopt {

HessianAssembly::HessianAssembly(std::vector<int> free_index) : free_index_(std::move(free_index)) {
  for (int f : free_index_) free_count_ += f >= 0;
}

int HessianAssembly::add_stencils(const int* vertices, std::size_t count, int n) {
  sets_.push_back({vertices, count, n});
  return static_cast<int>(sets_.size()) - 1;
}

void HessianAssembly::finalize() {
  const ColumnBlocks columns = group_blocks_by_column();
  build_patterns(columns);
  fill_slots(columns);
  diagonal_.resize(free_index_.size());
  lower_diagonal_.resize(free_index_.size());
  for (int v = 0; v < static_cast<int>(free_index_.size()); ++v) {
    diagonal_[v] = block_slot(v, v);
    lower_diagonal_[v] = lower_block_slot(v, v);
  }
}

// A pattern change (self-contact's candidates) rebuilds everything, so each column's rows are
// found once, by a counting sort of the blocks, not searched for block by block.
HessianAssembly::ColumnBlocks HessianAssembly::group_blocks_by_column() {
  set_offset_.clear();
  ColumnBlocks columns;
  for (const StencilSet& set : sets_) {
    set_offset_.push_back(columns.blocks);
    columns.blocks += set.count * set.n * set.n;
  }
  const auto for_each_free_block = [&](auto&& visit) {
    for (std::size_t k = 0; k < sets_.size(); ++k) {
      const StencilSet& set = sets_[k];
      for (std::size_t s = 0; s < set.count; ++s) {
        const int* v = set.vertices + s * set.n;
        const std::size_t first = set_offset_[k] + s * set.n * set.n;
        for (int a = 0; a < set.n; ++a)
          for (int b = 0; b < set.n; ++b) {
            const int fa = free_index_[v[a]], fb = free_index_[v[b]];
            if (fa >= 0 && fb >= 0) visit(fa, fb, first + a * set.n + b, first + b * set.n + a);
          }
      }
    }
  };
  columns.start.assign(free_count_ + 1, 0);
  for_each_free_block([&](int, int fb, std::size_t, std::size_t) { ++columns.start[fb + 1]; });
  for (int f = 0; f < free_count_; ++f) columns.start[f + 1] += columns.start[f];
  const std::size_t count = columns.start[free_count_];
  columns.row.resize(count);
  columns.index.resize(count);
  columns.transposed.resize(count);
  std::vector<int> fill(columns.start.begin(), columns.start.end() - 1);
  for_each_free_block([&](int fa, int fb, std::size_t index, std::size_t transposed) {
    const int at = fill[fb]++;
    columns.row[at] = fa;
    columns.index[at] = index;
    columns.transposed[at] = transposed;
  });
  return columns;
}

void HessianAssembly::build_patterns(const ColumnBlocks& columns) {
  // Each column's rows: its own diagonal and its blocks' rows, once each, sorted.
  column_rows_.assign(free_count_, {});
  std::vector<int> seen(free_count_, -1);
  for (int fb = 0; fb < free_count_; ++fb) {
    auto& rows = column_rows_[fb];
    rows.push_back(fb);
    seen[fb] = fb;
    for (int k = columns.start[fb]; k < columns.start[fb + 1]; ++k)
      if (seen[columns.row[k]] != fb) {
        seen[columns.row[k]] = fb;
        rows.push_back(columns.row[k]);
      }
    std::sort(rows.begin(), rows.end());
  }

  // CSC: column 3fb+c holds rows 3fa..3fa+2 of every row vertex fa, in increasing order.
  const int n = 3 * free_count_;
  std::vector<int> outer(n + 1, 0);
  for (int fb = 0; fb < free_count_; ++fb)
    for (int c = 0; c < 3; ++c) outer[3 * fb + c + 1] = 3 * static_cast<int>(column_rows_[fb].size());
  for (int k = 0; k < n; ++k) outer[k + 1] += outer[k];
  std::vector<int> inner(outer[n]);
  for (int fb = 0; fb < free_count_; ++fb)
    for (int c = 0; c < 3; ++c) {
      int p = outer[3 * fb + c];
      for (int fa : column_rows_[fb])
        for (int r = 0; r < 3; ++r) inner[p++] = 3 * fa + r;
    }
  std::vector<double> values(inner.size(), 0.0);
  matrix_ = Eigen::Map<const Eigen::SparseMatrix<double>>(n, n, outer[n], outer.data(), inner.data(), values.data());
  matrix_.makeCompressed();

  // Lower blocks: row fa holds the columns fb < fa of column_rows_[fa] (the pattern is symmetric),
  // then its diagonal.
  std::vector<int> row_start(1, 0), column;
  for (int fa = 0; fa < free_count_; ++fa) {
    for (int fb : column_rows_[fa])
      if (fb < fa) column.push_back(fb);
    column.push_back(fa);
    row_start.push_back(static_cast<int>(column.size()));
  }
  lower_.set_pattern(std::move(row_start), std::move(column));
}

void HessianAssembly::fill_slots(const ColumnBlocks& columns) {
  // Block (fa, fb) sits at row place k of column fb: its CSC slot. Its transpose (fb, fa) is a lower
  // block where fa <= fb, in row fb at the same rank k (as block_slot and lower_block_slot find by
  // search).
  slots_.assign(columns.blocks, Slot{});
  lower_slots_.assign(columns.blocks, Slot{});
  std::vector<int> place(free_count_);  // the row places of the column at hand
  for (int fb = 0; fb < free_count_; ++fb) {
    const auto& rows = column_rows_[fb];
    for (int k = 0; k < static_cast<int>(rows.size()); ++k) place[rows[k]] = k;
    const int base = matrix_.outerIndexPtr()[3 * fb], stride = 3 * static_cast<int>(rows.size());
    for (int k = columns.start[fb]; k < columns.start[fb + 1]; ++k) {
      const int fa = columns.row[k];
      slots_[columns.index[k]] = {base + 3 * place[fa], stride};
      if (fa <= fb) lower_slots_[columns.transposed[k]] = {9 * (lower_.row_begin(fb) + place[fa]), 3};
    }
  }
}

void HessianAssembly::set_zero(Target target) {
  target_ = target;
  if (to_matrix()) matrix_.coeffs().setZero();
  if (to_lower_blocks()) lower_.set_zero();
}

void HessianAssembly::scale(double factor) {
  if (to_matrix()) matrix_.coeffs() *= factor;
  if (to_lower_blocks()) lower_.scale(factor);
}

HessianAssembly::Slot HessianAssembly::block_slot(int row_vertex, int col_vertex) const {
  const int fa = free_index_[row_vertex], fb = free_index_[col_vertex];
  if (fa < 0 || fb < 0) return {};
  const auto& rows = column_rows_[fb];
  const auto it = std::lower_bound(rows.begin(), rows.end(), fa);
  assert(it != rows.end() && *it == fa);
  const int position = static_cast<int>(it - rows.begin());
  return {matrix_.outerIndexPtr()[3 * fb] + 3 * position, 3 * static_cast<int>(rows.size())};
}

HessianAssembly::Slot HessianAssembly::lower_block_slot(int row_vertex, int col_vertex) const {
  const int fa = free_index_[row_vertex], fb = free_index_[col_vertex];
  if (fa < 0 || fb < 0 || fb > fa) return {};
  const auto& columns = column_rows_[fa];  // those below fa first: their rank is the block's place
  const int rank = static_cast<int>(std::lower_bound(columns.begin(), columns.end(), fb) - columns.begin());
  return {9 * (lower_.row_begin(fa) + rank), 3};
}

void HessianAssembly::add_vertex_diagonal(int v, double value) {
  auto add = [&](const Slot& slot, double* values) {
    if (slot.base >= 0)
      for (int c = 0; c < 3; ++c) values[slot.base + c * slot.stride + c] += value;
  };
  if (to_matrix()) add(diagonal_[v], matrix_.valuePtr());
  if (to_lower_blocks()) add(lower_diagonal_[v], lower_.values());
}

}  // namespace fnopt
