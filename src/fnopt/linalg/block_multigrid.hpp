#pragma once
// A geometric multigrid V-cycle on a cloth grid, to precondition with (docs/design.md §6): an
// approximate inverse of a symmetric positive definite matrix A over the free vertices' dofs
// (3 per vertex, in free-index order, as HessianAssembly builds them), stored and smoothed in 3x3
// blocks of floats.
//
// Levels: each coarser grid keeps every other row and column of the finer one (and the last, so
// that a grid of any size coarsens), the prolongation is bilinear in grid indices (per dof,
// the same for x, y and z), and the coarse matrices are Galerkin products A_c = R^T A R, summed
// block by block through slot tables built once per sparsity pattern. A coarse vertex none of
// whose fine neighbours is free (all handles) is no unknown. One V-cycle: forward block
// Gauss–Seidel sweeps, the residual restricted by R^T, the coarser cycle, its correction
// prolonged, backward sweeps (the mirror of the first, so the cycle is a symmetric positive
// definite operator, as CG's preconditioner must be; Briggs, Henson & McCormick 2000, ch. 3–5),
// and a dense Cholesky solve on the coarsest grid.
//
// Why: the sparse Cholesky factor of A costs, at 100^2, 400–500 ms to compute and 7.8 ms per
// solve even in floats (5.5 million entries read twice); A itself has 1.3 x 10^5 blocks, of which
// the smoother keeps the half left of the diagonal (A is symmetric) and a cycle reads it and its
// coarse levels about three times, no factorisation to rebuild (docs/results.md, "A multigrid
// preconditioner on fine grids", "The reference's kernels").
#include <Eigen/Cholesky>
#include <Eigen/Sparse>
#include <vector>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

struct BlockMultigridParams {
  int smoothing_sweeps = 1;  // block Gauss–Seidel sweeps before the coarse correction, and as many after
  // Coarsening stops at a grid of at most this many unknown dofs, solved there by dense Cholesky
  // (at 400, 64^2 and 100^2 end at 9^2 and 8^2 vertices: a 0.03 ms solve).
  int coarsest_dofs = 400;

  void validate() const;  // throws Error naming the parameter
};

class BlockMultigrid {
 public:
  explicit BlockMultigrid(BlockMultigridParams params = {});

  // Builds the hierarchy for A (symmetric, both triangles stored, 3x3 blocks between free vertices
  // of `grid`, free_index[v] = v's index among them or -1). The prolongations, coarse patterns and
  // slot tables are rebuilt only when `pattern` differs from the last one (an id that changes with
  // A's sparsity pattern, as BackwardEulerObjective::hessian_pattern_id(); -1: always). False if a
  // diagonal block or the coarsest matrix is not positive definite. Throws Error if A is not made
  // of 3x3 blocks on that free set.
  bool assign(const Eigen::SparseMatrix<double>& A, const Grid& grid, const std::vector<int>& free_index,
              long pattern = -1);
  int rows() const { return levels_.empty() ? 0 : 3 * levels_.front().unknowns; }
  int level_count() const { return static_cast<int>(levels_.size()); }
  // r <- B r, B the V-cycle's approximation of A^-1; no allocation.
  void solve_in_place(VecX& r);

 private:
  struct Level {
    int grid_rows = 0, grid_cols = 0;
    std::vector<int> unknown;  // per grid vertex: its index among this level's unknowns, or -1
    int unknowns = 0;
    // The matrix in block-compressed rows: row i's blocks at [row_start[i], row_start[i + 1]),
    // block k in column column[k], its 3x3 values row-major at values[9k].
    std::vector<int> row_start, column, diagonal;  // diagonal[i]: row i's diagonal block
    std::vector<double> values;
    // The smoother's: the blocks left of the diagonal, row by row (lower_start, lower_column as row_start,
    // column), and D_i^-1, in floats, each block column by column, one float of padding. lower_rows holds
    // the same blocks row by row, for the products with their transposes (U = L^T).
    std::vector<int> lower_start, lower_column;
    std::vector<float> lower_values, lower_rows, diagonal_inverse;
    // Prolongation from the next coarser level: unknown i = sum of weight * coarse unknown over
    // [prolong_start[i], prolong_start[i + 1]).
    std::vector<int> prolong_start, prolong_index;
    std::vector<float> prolong_weight;
    // Galerkin slot table: block k of this level adds weight x its values to the coarser level's
    // block galerkin_slot over [galerkin_start[k], galerkin_start[k + 1]).
    std::vector<int> galerkin_start, galerkin_slot;
    std::vector<double> galerkin_weight;
    std::vector<float> x, b;  // the cycle's solution and right-hand side
    // Products with the blocks right of the diagonal (the smoother's), the residual: four floats per
    // unknown, the fourth unused, so that each block's product is added as four lanes.
    std::vector<float> upper;
    std::vector<float> change;  // the last forward sweep's change of x, with more than one sweep
  };

  void build_hierarchy(const Eigen::SparseMatrix<double>& A, const Grid& grid, const std::vector<int>& free_index);
  // The next coarser level's grid, unknowns, this level's prolongation and the coarser pattern.
  Level coarsen(Level& fine) const;
  void copy_fine_values(const Eigen::SparseMatrix<double>& A);
  bool prepare_smoother(Level& level);
  // Block Gauss–Seidel sweeps on level.x for level.b: forward, with level.upper = U x (U the blocks
  // right of the diagonal) unless from_zero (x = 0), where it leaves level.upper = -U x, the residual;
  // backward.
  static void forward_sweep(Level& level, bool from_zero);
  static void backward_sweep(Level& level);
  // out += sign x U y, scattered from the blocks left of the diagonal (U = L^T).
  static void add_upper_product(const Level& level, const float* y, float* out, float sign);
  void cycle(std::size_t l);

  BlockMultigridParams params_;
  long pattern_ = -1;
  std::vector<Level> levels_;
  Eigen::LLT<Eigen::MatrixXd> coarsest_;
  Eigen::VectorXd coarsest_rhs_;
};

}  // namespace fnopt
