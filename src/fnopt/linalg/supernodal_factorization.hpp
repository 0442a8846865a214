#pragma once
// The numeric phase of a supernodal Cholesky factorization, into a factor CHOLMOD analysed.
//
// Why not cholmod_factorize: CHOLMOD 3 (SuiteSparse 5, Debian bookworm) opens an OpenMP region for
// each of a supernode's copy and assembly loops (`if` clauses make them inactive on small ones), and
// libgomp runs even an inactive region as a team of one, whose closing barrier makes a futex system
// call: about 1.2 us each, some 7500 regions per factorization at 64^2, a quarter of its time
// (docs/results.md, "The factorisation without OpenMP regions"). This is the same left-looking
// algorithm (CHOLMOD's t_cholmod_super_numeric; Ng and Peyton 1993) without those regions: the same
// BLAS and LAPACK calls on the same blocks, descendants taken in the same order, so L is the same bit
// for bit. What it adds: A's entries go straight to their places in L (a scatter computed once per
// pattern), where CHOLMOD first forms the permuted matrix A(p,p) at every factorization.
#include <vector>

#include <cholmod.h>
#include <Eigen/SparseCore>

namespace fnopt {

class SupernodalFactorization {
 public:
  // Prepares to factorize matrices of A's pattern (its lower triangle is read) into L, a supernodal
  // factor that cholmod_analyze made for that pattern; gives L room for its values.
  void analyse(const Eigen::SparseMatrix<double>& A, cholmod_factor* L, cholmod_common* common);
  // L <- the Cholesky factor of A(p,p), p = L's permutation; A has the analysed pattern (a matrix of
  // another size or count of entries throws std::logic_error). False if A is not positive definite;
  // then L->minor is the column whose pivot failed, and L's values are not a factor.
  bool factorize(const Eigen::SparseMatrix<double>& A, cholmod_factor* L);

 private:
  Eigen::Index analysed_entries_ = -1;  // A's stored entries (both triangles), for factorize's check
  // Where an entry of A's lower triangle lands in L's values.
  struct Placement {
    int source;  // index in A's values
    int target;  // index in L->x
  };
  std::vector<Placement> placements_;  // grouped by supernode
  std::vector<int> placement_start_;   // supernode s's placements: [start[s], start[s + 1])
  std::vector<int> supernode_of_column_;
  // Workspaces of the factorization (CHOLMOD's names): row -> its place in the current supernode,
  // a descendant's rows -> their places, the linked lists of descendants still to be applied, and
  // the first row of each descendant not yet applied; the update block C.
  std::vector<int> map_;
  std::vector<int> relative_map_;
  std::vector<int> head_;
  std::vector<int> next_;
  std::vector<int> position_;
  std::vector<double> update_;
};

}  // namespace fnopt
