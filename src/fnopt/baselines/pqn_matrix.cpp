#include <fnopt/baselines/pqn_matrix.hpp>

#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

Eigen::SparseMatrix<double> PqnMatrix::expanded() const {
  std::vector<Eigen::Triplet<double>> entries;
  for (int col = 0; col < matrix.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, col); it; ++it)
      for (int c = 0; c < 3; ++c) entries.emplace_back(3 * it.row() + c, 3 * col + c, it.value());
  Eigen::SparseMatrix<double> A(3 * matrix.rows(), 3 * matrix.cols());
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

PqnMatrix build_pqn_matrix(const BackwardEulerObjective& objective, const std::vector<int>& free_index, const VecX& x) {
  HessianAssembly assembly(free_index);
  std::vector<std::pair<const EnergyTerm*, int>> terms;
  // The rest-state matrix holds the elastic terms only: the repulsion's, the obstacles' and
  // self-contact's (docs/design.md §14) depend on where the cloth is.
  for (const auto& term : objective.terms())
    if (term.get() != static_cast<const EnergyTerm*>(objective.repulsion()) &&
        term.get() != static_cast<const EnergyTerm*>(objective.contact()) &&
        term.get() != static_cast<const EnergyTerm*>(objective.mesh_contact()) &&
        term.get() != static_cast<const EnergyTerm*>(objective.self_contact()))
      terms.emplace_back(term.get(), term->register_hessian(assembly));
  assembly.finalize();
  assembly.set_zero();
  for (const auto& [term, handle] : terms)
    if (handle >= 0) term->accumulate_hessian(x, /*project=*/true, assembly, handle);
  const double dt2 = objective.dt() * objective.dt();
  assembly.scale(dt2 * dt2);
  const Eigen::SparseMatrix<double>& K = assembly.matrix();

  PqnMatrix result;
  result.free_index = free_index;
  std::vector<Eigen::Triplet<double>> entries;
  // S_ij = trace of K's block (i, j): the sum of its entries (3i + c, 3j + c).
  for (int col = 0; col < K.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, col); it; ++it)
      if (it.row() % 3 == col % 3) entries.emplace_back(it.row() / 3, col / 3, it.value());
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v)
    if (free_index[v] >= 0) entries.emplace_back(free_index[v], free_index[v], objective.inertia_weight(v));
  result.matrix.resize(K.rows() / 3, K.cols() / 3);
  result.matrix.setFromTriplets(entries.begin(), entries.end());  // sums the duplicates
  return result;
}

bool PqnFactor::factorize(const PqnMatrix& matrix) {
  matrix_ = matrix;
  return cholesky_.factorize_matrix(matrix_.matrix);
}

void PqnFactor::solve_free_in_place(VecX& r) {
  const int rows = static_cast<int>(matrix_.matrix.rows());
  block_.resize(3 * rows);
  for (int f = 0; f < rows; ++f)
    for (int c = 0; c < 3; ++c) block_[c * rows + f] = r[3 * f + c];
  cholesky_.solve_in_place(block_.data(), rows, 3);
  for (int f = 0; f < rows; ++f)
    for (int c = 0; c < 3; ++c) r[3 * f + c] = block_[c * rows + f];
}

int PqnFactor::block_position(int free_vertex, int coordinate) const {
  return coordinate * static_cast<int>(matrix_.matrix.rows()) + free_vertex;
}

void PqnFactor::gather_free(const VecX& q) {
  const std::vector<int>& free_index = matrix_.free_index;
  block_.resize(3 * matrix_.matrix.rows());
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v)
    if (const int f = free_index[v]; f >= 0)
      for (int c = 0; c < 3; ++c) block_[block_position(f, c)] = q[3 * v + c];
}

void PqnFactor::solve_in_place(VecX& q) {
  gather_free(q);
  const int rows = static_cast<int>(matrix_.matrix.rows());
  cholesky_.solve_in_place(block_.data(), rows, 3);
  const std::vector<int>& free_index = matrix_.free_index;
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v) {
    const int f = free_index[v];
    for (int c = 0; c < 3; ++c) q[3 * v + c] = f < 0 ? 0.0 : block_[block_position(f, c)];
  }
}

double PqnFactor::quadratic_form(const VecX& q) {
  gather_free(q);
  const auto A = matrix_.matrix.selfadjointView<Eigen::Lower>();
  const int rows = static_cast<int>(matrix_.matrix.rows());
  double sum = 0.0;  // A = S (x) I3: one scalar form per coordinate
  for (int c = 0; c < 3; ++c) {
    const auto column = block_.segment(c * rows, rows);
    sum += column.dot(A * column);
  }
  return sum;
}

bool PqnFactorCache::Key::operator==(const Key& o) const {
  return rows == o.rows && cols == o.cols && spacing == o.spacing && dt == o.dt && stretch == o.stretch &&
         shear == o.shear && bend == o.bend && density == o.density && damping == o.damping &&
         free_index == o.free_index;
}

PqnFactorCache::Key PqnFactorCache::key_of(const StepProblem& problem) {
  const BackwardEulerObjective& objective = problem.objective();
  const Material& m = objective.material();
  return {problem.grid().rows,
          problem.grid().cols,
          problem.grid().spacing,
          objective.dt(),
          m.stretch,
          m.shear,
          m.bend,
          m.density,
          m.damping,
          problem.dirichlet().free_index()};
}

PqnFactor& PqnFactorCache::prepare(const StepProblem& problem) {
  Key key = key_of(problem);
  if (have_factor_ && key == key_) return factor_;
  const PqnMatrix matrix = build_pqn_matrix(problem.objective(), key.free_index, problem.grid().rest_positions());
  have_factor_ = factor_.factorize(matrix);
  ++factorizations_;
  // A is the inertia (positive) plus PSD terms: a failure means a non-finite material or dt.
  require(have_factor_, "pqn", "the prefactored matrix is not positive definite (check the material and dt)");
  key_ = std::move(key);
  return factor_;
}

}  // namespace fnopt
