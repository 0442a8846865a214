#pragma once
// The 3x3 block pattern of a symmetric sparse matrix stored with both triangles, 3 dofs per vertex
// (as HessianAssembly builds it), read once for the solvers that keep it in blocks
// (BlockMultigrid).
#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace fnopt {

// Block row i's blocks at [row_start[i], row_start[i + 1]), in increasing block column column[k].
struct BlockPattern {
  std::vector<int> row_start, column;
};

// Reads A's block pattern from the first column of each vertex's three; the other two must match.
// Throws Error(field, "the matrix is not made of 3x3 blocks") where they do not (A square, with a
// multiple of 3 rows and compressed, is the caller's to check).
BlockPattern read_block_pattern(const Eigen::SparseMatrix<double>& A, const std::string& field);

// The position in A.valuePtr() of entry (r, c) of block k = row_start[i] + m, A(3i + r, 3j + c) =
// A(3j + c, 3i + r): in column 3i + r of the symmetric A, its m-th block of rows.
inline int block_entry(const Eigen::SparseMatrix<double>& A, int i, int m, int r, int c) {
  return A.outerIndexPtr()[3 * i + r] + 3 * m + c;
}

}  // namespace fnopt
