#include <fnopt/linalg/supernodal_factorization.hpp>

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <stdexcept>

// The BLAS and LAPACK that CHOLMOD calls (OpenBLAS here), with their Fortran string lengths.
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc, std::size_t, std::size_t);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc, std::size_t, std::size_t);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb, std::size_t, std::size_t,
            std::size_t, std::size_t);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
}

namespace fnopt {

void SupernodalFactorization::analyse(const Eigen::SparseMatrix<double>& A, cholmod_factor* L, cholmod_common* common) {
  assert(L->is_super && L->itype == CHOLMOD_INT && static_cast<Eigen::Index>(L->n) == A.rows());
  if (L->xtype == CHOLMOD_PATTERN) cholmod_change_factor(CHOLMOD_REAL, true, true, true, true, L, common);
  const int n = static_cast<int>(L->n);
  const int supernodes = static_cast<int>(L->nsuper);
  const int* super = static_cast<const int*>(L->super);
  const int* pi = static_cast<const int*>(L->pi);
  const int* px = static_cast<const int*>(L->px);
  const int* rows = static_cast<const int*>(L->s);
  const int* perm = static_cast<const int*>(L->Perm);

  supernode_of_column_.resize(n);
  for (int s = 0; s < supernodes; ++s)
    std::fill(supernode_of_column_.begin() + super[s], supernode_of_column_.begin() + super[s + 1], s);
  std::vector<int> inverse(n);
  for (int k = 0; k < n; ++k) inverse[perm[k]] = k;

  // A's lower entries by column of A(p,p)'s lower triangle (counting sort); a supernode's columns
  // are consecutive, so this also groups them by supernode.
  struct Entry {
    int source, row, column;
  };
  std::vector<Entry> entries;
  entries.reserve(A.nonZeros());
  std::vector<int> column_start(n + 1, 0);
  for (int j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (it.row() < j) continue;
      const int a = inverse[it.row()], b = inverse[j];
      entries.push_back({static_cast<int>(&it.value() - A.valuePtr()), std::max(a, b), std::min(a, b)});
      ++column_start[entries.back().column + 1];
    }
  for (int k = 0; k < n; ++k) column_start[k + 1] += column_start[k];
  std::vector<Entry> by_column(entries.size());
  {
    std::vector<int> next = column_start;
    for (const Entry& e : entries) by_column[next[e.column]++] = e;
  }

  map_.assign(n, -1);
  placements_.resize(by_column.size());
  placement_start_.assign(supernodes + 1, 0);
  for (int s = 0; s < supernodes; ++s) {
    const int nsrow = pi[s + 1] - pi[s];
    for (int k = 0; k < nsrow; ++k) map_[rows[pi[s] + k]] = k;
    for (int e = column_start[super[s]]; e < column_start[super[s + 1]]; ++e) {
      const Entry& entry = by_column[e];
      const int place = map_[entry.row];
      if (place < 0 || place >= nsrow || rows[pi[s] + place] != entry.row)
        throw std::logic_error("supernodal factorization: the matrix has an entry outside the analysed pattern");
      placements_[e] = {entry.source, px[s] + (entry.column - super[s]) * nsrow + place};
    }
    placement_start_[s + 1] = column_start[super[s + 1]];
  }
  analysed_entries_ = A.nonZeros();
  relative_map_.resize(n);
  head_.resize(supernodes);
  next_.resize(supernodes);
  position_.resize(supernodes);
  update_.resize(L->maxcsize);
}

bool SupernodalFactorization::factorize(const Eigen::SparseMatrix<double>& A, cholmod_factor* L) {
  if (A.rows() != static_cast<Eigen::Index>(L->n) || A.nonZeros() != analysed_entries_)
    throw std::logic_error("supernodal factorization: the matrix's pattern is not the analysed one");
  const int supernodes = static_cast<int>(L->nsuper);
  const int* super = static_cast<const int*>(L->super);
  const int* pi = static_cast<const int*>(L->pi);
  const int* px = static_cast<const int*>(L->px);
  const int* rows = static_cast<const int*>(L->s);
  double* x = static_cast<double*>(L->x);
  const double* a = A.valuePtr();
  double* C = update_.data();
  const double one = 1.0, zero = 0.0;

  std::fill(head_.begin(), head_.end(), -1);
  for (int s = 0; s < supernodes; ++s) {
    // Supernode s: columns k1..k2-1, its rows rows[psi..], its values x[psx..], nsrow x nscol,
    // column-major.
    const int k1 = super[s], k2 = super[s + 1], nscol = k2 - k1;
    const int psi = pi[s], nsrow = pi[s + 1] - psi;
    double* block = x + px[s];
    std::fill(block, block + static_cast<std::ptrdiff_t>(nsrow) * nscol, 0.0);
    for (int e = placement_start_[s]; e < placement_start_[s + 1]; ++e)
      x[placements_[e].target] = a[placements_[e].source];
    for (int k = 0; k < nsrow; ++k) map_[rows[psi + k]] = k;

    // s -= L1 L_d^T for each descendant d with rows among s's columns, where L1 is d's rows from
    // the first not yet applied (position_[d]) on, against those of them inside k1..k2-1.
    for (int d = head_[s]; d != -1;) {
      const int ndcol = super[d + 1] - super[d];
      const int pdi = pi[d], ndrow = pi[d + 1] - pdi;
      const int pdi1 = pdi + position_[d];
      const double* Ld = x + px[d] + position_[d];
      int pdi2 = pdi1;
      while (pdi2 < pdi + ndrow && rows[pdi2] < k2) ++pdi2;
      const int ndrow1 = pdi2 - pdi1, ndrow2 = pdi + ndrow - pdi1, ndrow3 = ndrow2 - ndrow1;
      dsyrk_("L", "N", &ndrow1, &ndcol, &one, Ld, &ndrow, &zero, C, &ndrow2, 1, 1);
      if (ndrow3 > 0)
        dgemm_("N", "C", &ndrow3, &ndrow1, &ndcol, &one, Ld + ndrow1, &ndrow, Ld, &ndrow, &zero, C + ndrow1, &ndrow2, 1,
               1);
      for (int i = 0; i < ndrow2; ++i) relative_map_[i] = map_[rows[pdi1 + i]];
      for (int j = 0; j < ndrow1; ++j) {
        double* column = block + static_cast<std::ptrdiff_t>(relative_map_[j]) * nsrow;
        const double* c = C + static_cast<std::ptrdiff_t>(ndrow2) * j;
        for (int i = j; i < ndrow2; ++i) column[relative_map_[i]] -= c[i];
      }
      // d goes on to the supernode of its next row, if it has one.
      const int following = next_[d];
      position_[d] = pdi2 - pdi;
      if (position_[d] < ndrow) {
        const int ancestor = supernode_of_column_[rows[pdi2]];
        next_[d] = head_[ancestor];
        head_[ancestor] = d;
      }
      d = following;
    }

    int info = 0;
    dpotrf_("L", &nscol, block, &nsrow, &info, 1);
    if (info != 0) {
      L->minor = static_cast<std::size_t>(k1 + info - 1);
      return false;
    }
    if (const int below = nsrow - nscol; below > 0) {
      dtrsm_("R", "L", "C", "N", &below, &nscol, &one, block, &nsrow, block + nscol, &nsrow, 1, 1, 1, 1);
      position_[s] = nscol;
      const int parent = supernode_of_column_[rows[psi + nscol]];
      next_[s] = head_[parent];
      head_[parent] = s;
    }
    head_[s] = -1;
  }
  L->minor = L->n;
  return true;
}

}  // namespace fnopt
