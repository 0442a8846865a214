#pragma once
// Sparse Hessian assembly with a fixed pattern. Every energy term registers its stencils once;
// the pattern (3x3 blocks between free vertices that share a stencil, plus every free vertex's
// diagonal block) and, for each stencil, the position of each of its blocks in the CSC value
// array are computed once. Each Newton iteration then only zeroes the values and scatters the
// per-stencil matrices: no triplets, no sorting, no allocation.
// Rows and columns are the free (non-handle) dofs: free vertex f owns rows 3f, 3f+1, 3f+2.
// The values go to one of two targets: the whole CSC matrix (matrix()), or only its lower triangle
// of 3x3 blocks (lower_blocks(), for products: a stencil block above the diagonal is skipped,
// since its transpose below it is added too), the same sums in the same order; or to both at once,
// a stencil's exact matrix to the blocks and its projection to the matrix (the Newton reference's
// iterations that rebuild its preconditioner: one evaluation of each stencil for the two).
#include <Eigen/Sparse>
#include <vector>

#include <fnopt/cloth/symmetric_block_matrix.hpp>

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

  // ExactAndProjected: the lower blocks take scatter_pair()'s exact matrices, the matrix its
  // projected ones.
  enum class Target { Matrix, LowerBlocks, ExactAndProjected };
  // Zeroes the target (both for ExactAndProjected) and sends the following calls there.
  void set_zero(Target target = Target::Matrix);
  // Sends the following calls to the target without zeroing it.
  void select(Target target) { target_ = target; }
  // Adds the 3n x 3n matrix of stencil s of the stencil set `handle` to the target (Matrix or
  // LowerBlocks); blocks of fixed vertices are skipped (Dirichlet elimination).
  template <int N>
  void scatter(int handle, std::size_t s, const Eigen::Matrix<double, 3 * N, 3 * N>& local) {
    const bool matrix = target_ == Target::Matrix;
    add_stencil<N>(matrix ? slots_ : lower_slots_, matrix ? matrix_.valuePtr() : lower_.values(), handle, s, local);
  }
  // With the target ExactAndProjected: stencil s's exact matrix to the lower blocks, its
  // projection to the matrix.
  template <int N>
  void scatter_pair(int handle, std::size_t s, const Eigen::Matrix<double, 3 * N, 3 * N>& exact,
                    const Eigen::Matrix<double, 3 * N, 3 * N>& projected) {
    add_stencil<N>(lower_slots_, lower_.values(), handle, s, exact);
    add_stencil<N>(slots_, matrix_.valuePtr(), handle, s, projected);
  }
  // Adds value * I_3 to the diagonal block of vertex v (no-op for a fixed vertex).
  void add_vertex_diagonal(int v, double value);
  // Multiplies every value of the target by `factor`.
  void scale(double factor);

  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  const SymmetricBlockMatrix& lower_blocks() const { return lower_; }

 private:
  // Position of a 3x3 block in a target's value array: entry (r, c) is at base + c*stride + r.
  struct Slot {
    int base = -1;
    int stride = 0;
  };
  struct StencilSet {
    const int* vertices;
    std::size_t count;
    int n;
  };

  template <int N>
  void add_stencil(const std::vector<Slot>& slots, double* values, int handle, std::size_t s,
                   const Eigen::Matrix<double, 3 * N, 3 * N>& local) const {
    const Slot* slot = &slots[set_offset_[handle] + s * N * N];
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b, ++slot) {
        if (slot->base < 0) continue;
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) values[slot->base + c * slot->stride + r] += local(3 * a + r, 3 * b + c);
      }
  }
  // Every block (a, b) of every stencil between free vertices, grouped by its column's free
  // vertex: column f's blocks are start[f]..start[f+1]-1, each with its row's free vertex, its
  // index among all `blocks` (set_offset_ + s n^2 + a n + b) and its transpose's (b, a).
  struct ColumnBlocks {
    std::size_t blocks = 0;
    std::vector<int> start, row;
    std::vector<std::size_t> index, transposed;
  };
  ColumnBlocks group_blocks_by_column();                // also sets set_offset_
  void build_patterns(const ColumnBlocks& columns);  // column_rows_, matrix_'s and lower_'s patterns
  void fill_slots(const ColumnBlocks& columns);      // slots_ and lower_slots_
  Slot block_slot(int row_vertex, int col_vertex) const;
  // Its place in lower_ (block k at 9k, stride 3); none above the diagonal.
  Slot lower_block_slot(int row_vertex, int col_vertex) const;
  bool to_matrix() const { return target_ != Target::LowerBlocks; }
  bool to_lower_blocks() const { return target_ != Target::Matrix; }

  std::vector<int> free_index_;
  int free_count_ = 0;
  std::vector<StencilSet> sets_;
  std::vector<std::size_t> set_offset_;
  std::vector<Slot> slots_;
  std::vector<std::vector<int>> column_rows_;  // per free vertex: sorted free row vertices
  std::vector<Slot> diagonal_;
  Eigen::SparseMatrix<double> matrix_;
  std::vector<Slot> lower_slots_, lower_diagonal_;
  SymmetricBlockMatrix lower_;
  Target target_ = Target::Matrix;
};

}  // namespace fnopt
