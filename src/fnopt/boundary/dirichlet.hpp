#pragma once
// Dirichlet elimination of handle vertices (docs/design.md §3). A handle's position at t+1 is
// prescribed, so its acceleration is fixed,
//   a_h = (x_h(t+1) - x_t - dt v_t) / dt^2,
// and it is removed from every optimizer's unknowns: gradients and updates are masked.
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class DirichletSet {
 public:
  DirichletSet() = default;
  DirichletSet(int vertex_count, std::vector<int> fixed_vertices);

  const std::vector<int>& fixed_vertices() const { return fixed_; }
  // Index of a vertex among the free ones (the reduced unknowns), -1 for a fixed vertex.
  const std::vector<int>& free_index() const { return free_index_; }
  int free_count() const { return free_count_; }
  int vertex_count() const { return static_cast<int>(free_index_.size()); }

  // Sets the three coordinates of every fixed vertex to zero (mask a gradient or an update).
  void zero_fixed(VecX& v) const;
  // The free vertices' dofs of a full vector in the reduced numbering (free vertex f at 3f).
  void gather_free(const VecX& full, VecX& reduced) const;
  // The inverse: a full vector with `reduced` on the free dofs and zero on the fixed ones.
  void scatter_free(const VecX& reduced, VecX& full) const;
  // Writes the prescribed accelerations of the fixed vertices into `a`: targets[k] is the
  // position at t+1 of fixed_vertices()[k].
  void prescribe(VecX& a, const VecX& x, const VecX& v, const std::vector<Vec3>& targets, double dt) const;

 private:
  std::vector<int> fixed_;
  std::vector<int> free_index_;
  int free_count_ = 0;
};

}  // namespace fnopt
