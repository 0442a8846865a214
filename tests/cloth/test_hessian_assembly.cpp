// HessianAssembly (cloth/hessian_assembly.hpp): random stencil sets of 2, 3 and 4 vertices, with
// fixed vertices, repeated stencils and vertices shared between sets, assembled into both targets and
// compared with the naive sum of the same stencil matrices into a dense matrix over the free dofs.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include <fnopt/cloth/hessian_assembly.hpp>

namespace fnopt {
namespace {

struct RandomStencils {
  int n;
  std::vector<int> vertices;
  std::vector<Eigen::MatrixXd> matrices;  // one symmetric 3n x 3n matrix per stencil
};

// `count` stencils of n distinct vertices among `vertex_count`, each with a random symmetric matrix.
RandomStencils random_stencils(std::mt19937& rng, int n, int count, int vertex_count) {
  RandomStencils set{n, {}, {}};
  std::uniform_int_distribution<int> vertex(0, vertex_count - 1);
  std::normal_distribution<double> value;
  for (int s = 0; s < count; ++s) {
    std::vector<int> stencil;
    while (static_cast<int>(stencil.size()) < n) {
      const int v = vertex(rng);
      if (std::find(stencil.begin(), stencil.end(), v) == stencil.end()) stencil.push_back(v);
    }
    set.vertices.insert(set.vertices.end(), stencil.begin(), stencil.end());
    Eigen::MatrixXd m(3 * n, 3 * n);
    for (int i = 0; i < 3 * n; ++i)
      for (int j = 0; j < 3 * n; ++j) m(i, j) = value(rng);
    set.matrices.push_back(m + m.transpose());
  }
  return set;
}

template <int N>
void scatter_all(HessianAssembly& assembly, int handle, const RandomStencils& set) {
  for (std::size_t s = 0; s < set.matrices.size(); ++s)
    assembly.scatter<N>(handle, s, Eigen::Matrix<double, 3 * N, 3 * N>(set.matrices[s]));
}

void scatter_set(HessianAssembly& assembly, int handle, const RandomStencils& set) {
  if (set.n == 2) scatter_all<2>(assembly, handle, set);
  if (set.n == 3) scatter_all<3>(assembly, handle, set);
  if (set.n == 4) scatter_all<4>(assembly, handle, set);
}

TEST(HessianAssembly, EveryTargetIsTheNaiveSumOfTheStencilMatrices) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const int vertex_count = 8 + trial * 5;
    std::vector<int> free_index(vertex_count);
    int free = 0;
    for (int v = 0; v < vertex_count; ++v) free_index[v] = (v % 7 == 3) ? -1 : free++;
    std::vector<RandomStencils> sets;
    for (int n : {4, 2, 3, 4}) sets.push_back(random_stencils(rng, n, 3 + vertex_count / 2, vertex_count));
    sets.push_back(sets[0]);  // the same stencils twice: repeated blocks sum

    Eigen::MatrixXd naive = Eigen::MatrixXd::Zero(3 * free, 3 * free);
    for (const RandomStencils& set : sets)
      for (std::size_t s = 0; s < set.matrices.size(); ++s)
        for (int a = 0; a < set.n; ++a)
          for (int b = 0; b < set.n; ++b) {
            const int fa = free_index[set.vertices[s * set.n + a]], fb = free_index[set.vertices[s * set.n + b]];
            if (fa >= 0 && fb >= 0) naive.block<3, 3>(3 * fa, 3 * fb) += set.matrices[s].block<3, 3>(3 * a, 3 * b);
          }
    for (int v = 0; v < vertex_count; ++v)
      if (free_index[v] >= 0) naive.block<3, 3>(3 * free_index[v], 3 * free_index[v]) += 2.5 * Eigen::Matrix3d::Identity();

    HessianAssembly assembly(free_index);
    std::vector<int> handles;
    for (const RandomStencils& set : sets)
      handles.push_back(assembly.add_stencils(set.vertices.data(), set.matrices.size(), set.n));
    assembly.finalize();
    for (const auto target : {HessianAssembly::Target::Matrix, HessianAssembly::Target::LowerBlocks}) {
      assembly.set_zero(target);
      for (std::size_t k = 0; k < sets.size(); ++k) scatter_set(assembly, handles[k], sets[k]);
      for (int v = 0; v < vertex_count; ++v) assembly.add_vertex_diagonal(v, 2.5);
    }
    ASSERT_EQ(assembly.matrix().rows(), 3 * free);
    EXPECT_LE((Eigen::MatrixXd(assembly.matrix()) - naive).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    // The lower blocks' product is the symmetric matrix's.
    const VecX x = VecX::Random(3 * free);
    VecX y(3 * free);
    assembly.lower_blocks().multiply(x, y);
    EXPECT_LE((y - naive * x).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + (naive * x).cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

}  // namespace
}  // namespace fnopt
