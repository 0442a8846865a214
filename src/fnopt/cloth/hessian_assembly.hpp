#pragma once
// Sparse Hessian assembly with a fixed pattern. Every energy term registers its stencils once;
// the pattern (3x3 blocks between free vertices that share a stencil, plus every free vertex's
// diagonal block) and, for each stencil, the position of each of its blocks in the CSC value
// array are computed once. Each Newton iteration then only zeroes the values and scatters the
// per-stencil matrices: no triplets, no sorting, no allocation.
// Rows and columns are the free (non-handle) dofs: free vertex f owns rows 3f, 3f+1, 3f+2.
#include <Eigen/Sparse>
#include <vector>

namespace fnopt {

class HessianAssembly {
 public:
  // free_index[v] = index of vertex v among the free vertices, or -1 for a fixed vertex.
  explicit HessianAssembly(std::vector<int> free_index);

  // Registers `count` stencils of n vertices each (vertices[s*n + i]); returns a handle for
  // scatter(). Only before finalize().
  int add_stencils(const int* vertices, std::size_t count, int n);
  // Builds the pattern and the slot tables.
  void finalize();

  void set_zero() { matrix_.coeffs().setZero(); }
  // Adds the 3n x 3n matrix of stencil s of the stencil set `handle`; blocks of fixed vertices
  // are skipped (Dirichlet elimination).
  template <int N>
  void scatter(int handle, std::size_t s, const Eigen::Matrix<double, 3 * N, 3 * N>& local) {
    const Slot* slot = &slots_[set_offset_[handle] + s * N * N];
    double* values = matrix_.valuePtr();
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b, ++slot) {
        if (slot->base < 0) continue;
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) values[slot->base + c * slot->stride + r] += local(3 * a + r, 3 * b + c);
      }
  }
  // Adds value * I_3 to the diagonal block of vertex v (no-op for a fixed vertex).
  void add_vertex_diagonal(int v, double value);
  // Multiplies every stored value by `factor`.
  void scale(double factor) { matrix_.coeffs() *= factor; }

  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }

 private:
  // Position of a 3x3 block in the value array: entry (r, c) is at base + c*stride + r.
  struct Slot {
    int base = -1;
    int stride = 0;
  };
  struct StencilSet {
    const int* vertices;
    std::size_t count;
    int n;
  };

  Slot block_slot(int row_vertex, int col_vertex) const;

  std::vector<int> free_index_;
  int free_count_ = 0;
  std::vector<StencilSet> sets_;
  std::vector<std::size_t> set_offset_;
  std::vector<Slot> slots_;
  std::vector<std::vector<int>> column_rows_;  // per free vertex: sorted free row vertices
  std::vector<Slot> diagonal_;
  Eigen::SparseMatrix<double> matrix_;
};

}  // namespace fnopt
