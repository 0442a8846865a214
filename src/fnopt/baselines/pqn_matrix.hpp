#pragma once
// The fixed matrix of the prefactored quasi-Newton method (baselines/pqn.hpp; docs/design.md,
// "Prefactored quasi-Newton"), over the free vertices of a cloth step:
//   A = dt^2 M (1 + c dt) + dt^4 K,
// the inertia part of hess L exactly, and K built once from the elastic terms with fixed
// stencils (stretch, shear, bend; self-repulsion is left out: its pairs change every step):
//  - Isotropic (the default): K = the PSD-projected Hessian at the given positions with every
//    3x3 block B replaced by trace(B) I3. A spring's rank-one block k e e^T/|e|^2 becomes k I3,
//    the graph Laplacian of projective dynamics (Bouaziz et al. 2014) weighted by each term's
//    stiffness; a bending hinge gives its bi-Laplacian. trace(R B R^T) = trace(B), so A does not
//    depend on how the cloth is rotated, and it stays a fair model of the energy after the cloth
//    turns, where the anisotropic Hessian of the rest pose does not (docs/history/results-0.5-experiments.md).
//    A = S (x) I3 is stored as the scalar n_free x n_free matrix S: a factor 9x smaller, and the
//    three coordinates are solved together.
//  - RestHessian: K = the PSD-projected Hessian at the given positions, as it is (3 n_free rows).
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

enum class PqnMatrixKind { Isotropic, RestHessian };

const char* to_string(PqnMatrixKind kind);  // "isotropic", "rest-hessian"
// Throws Error("pqn.matrix", "...") for another name.
PqnMatrixKind parse_pqn_matrix_kind(const std::string& name);

struct PqnMatrix {
  PqnMatrixKind kind = PqnMatrixKind::Isotropic;
  // S (one row per free vertex, A = S (x) I3) for Isotropic; A (3 rows per free vertex) else.
  Eigen::SparseMatrix<double> matrix;
  std::vector<int> free_index;  // free_index[v]: vertex v's row (block) in the matrix, or -1

  int rows_per_vertex() const { return kind == PqnMatrixKind::Isotropic ? 1 : 3; }
  // The 3 n_free x 3 n_free matrix A itself (for tests and tools).
  Eigen::SparseMatrix<double> expanded() const;
};

// The matrix at positions x (pqn passes the grid's rest pose) over free_index's free vertices.
PqnMatrix build_pqn_matrix(const BackwardEulerObjective& objective, const std::vector<int>& free_index,
                           PqnMatrixKind kind, const VecX& x);

// The Cholesky factor of a PqnMatrix.
class PqnFactor {
 public:
  // Factorizes `matrix` (kept by value); false if it is not positive definite.
  bool factorize(const PqnMatrix& matrix);
  // q <- A^-1 q for q of 3 dofs per vertex; the fixed dofs of q are set to zero.
  void solve_in_place(VecX& q);
  // r <- A^-1 r for r of 3 dofs per free vertex (free vertex f at 3f, as the Hessian's rows).
  void solve_free_in_place(VecX& r);
  // q^T A q over the free dofs of q (3 dofs per vertex; the fixed dofs do not count): the
  // curvature that A predicts along q.
  double quadratic_form(const VecX& q);

 private:
  PqnMatrix matrix_;
  SparseCholesky cholesky_{SparseCholesky::Method::Simplicial};
  Eigen::VectorXd block_;  // the free dofs, in the factor's layout
  // Where coordinate c of free vertex f sits in block_.
  int block_position(int free_vertex, int coordinate) const;
  // block_ <- the free dofs of q (3 dofs per vertex), in the factor's layout.
  void gather_free(const VecX& q);
};

// The factor for the cloth step at hand, rebuilt only when what A depends on changes: the grid,
// dt, the material's stiffnesses, density or damping, or the set of handle vertices.
class PqnFactorCache {
 public:
  explicit PqnFactorCache(PqnMatrixKind kind) : kind_(kind) {}
  // The factor of A for this step (built at the grid's rest pose). Throws Error if A is not
  // positive definite (a non-finite material or dt).
  PqnFactor& prepare(const StepProblem& problem);
  long factorizations() const { return factorizations_; }

 private:
  struct Key {
    int rows = 0, cols = 0;
    double spacing = 0.0, dt = 0.0;
    double stretch = 0.0, shear = 0.0, bend = 0.0, density = 0.0, damping = 0.0;
    std::vector<int> free_index;
    bool operator==(const Key& other) const;
  };
  static Key key_of(const StepProblem& problem);

  PqnMatrixKind kind_;
  PqnFactor factor_;
  bool have_factor_ = false;
  Key key_;
  long factorizations_ = 0;
};

}  // namespace fnopt
