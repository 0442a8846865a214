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
  column_rows_.assign(free_count_, {});
  for (int v = 0; v < static_cast<int>(free_index_.size()); ++v)
    if (free_index_[v] >= 0) column_rows_[free_index_[v]].push_back(free_index_[v]);
  for (const StencilSet& set : sets_)
    for (std::size_t s = 0; s < set.count; ++s)
      for (int a = 0; a < set.n; ++a)
        for (int b = 0; b < set.n; ++b) {
          const int fa = free_index_[set.vertices[s * set.n + a]];
          const int fb = free_index_[set.vertices[s * set.n + b]];
          if (fa >= 0 && fb >= 0) column_rows_[fb].push_back(fa);
        }
  for (auto& rows : column_rows_) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
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

  set_offset_.clear();
  slots_.clear();
  lower_slots_.clear();
  for (const StencilSet& set : sets_) {
    set_offset_.push_back(slots_.size());
    for (std::size_t s = 0; s < set.count; ++s)
      for (int a = 0; a < set.n; ++a)
        for (int b = 0; b < set.n; ++b) {
          const int va = set.vertices[s * set.n + a], vb = set.vertices[s * set.n + b];
          slots_.push_back(block_slot(va, vb));
          lower_slots_.push_back(lower_block_slot(va, vb));
        }
  }
  diagonal_.resize(free_index_.size());
  lower_diagonal_.resize(free_index_.size());
  for (int v = 0; v < static_cast<int>(free_index_.size()); ++v) {
    diagonal_[v] = block_slot(v, v);
    lower_diagonal_[v] = lower_block_slot(v, v);
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
