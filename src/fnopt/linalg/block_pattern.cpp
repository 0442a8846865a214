#include <fnopt/linalg/block_pattern.hpp>

#include <fnopt/util/error.hpp>

namespace fnopt {

BlockPattern read_block_pattern(const Eigen::SparseMatrix<double>& A, const std::string& field) {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const int n = static_cast<int>(A.cols() / 3);
  BlockPattern pattern;
  pattern.row_start.assign(1, 0);
  for (int i = 0; i < n; ++i) {
    const int begin = outer[3 * i], count = outer[3 * i + 1] - begin;
    require(count % 3 == 0, field, "the matrix is not made of 3x3 blocks");
    for (int c = 1; c < 3; ++c)
      require(outer[3 * i + c + 1] - outer[3 * i + c] == count, field, "the matrix is not made of 3x3 blocks");
    for (int m = 0; m < count / 3; ++m) {
      const int j = inner[begin + 3 * m] / 3;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
          require(inner[outer[3 * i + c] + 3 * m + r] == 3 * j + r, field, "the matrix is not made of 3x3 blocks");
      pattern.column.push_back(j);
    }
    pattern.row_start.push_back(static_cast<int>(pattern.column.size()));
  }
  return pattern;
}

}  // namespace fnopt
