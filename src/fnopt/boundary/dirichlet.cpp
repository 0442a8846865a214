#include <fnopt/boundary/dirichlet.hpp>

#include <cassert>

namespace fnopt {

DirichletSet::DirichletSet(int vertex_count, std::vector<int> fixed_vertices)
    : fixed_(std::move(fixed_vertices)), free_index_(vertex_count, 0) {
  for (int k : fixed_) {
    assert(k >= 0 && k < vertex_count);
    free_index_[k] = -1;
  }
  for (int& f : free_index_)
    if (f == 0) f = free_count_++;
}

void DirichletSet::zero_fixed(VecX& v) const {
  for (int k : fixed_) vertex(v, k).setZero();
}

void DirichletSet::gather_free(const VecX& full, VecX& reduced) const {
  reduced.resize(3 * free_count_);
  for (int k = 0; k < vertex_count(); ++k)
    if (free_index_[k] >= 0) reduced.segment<3>(3 * free_index_[k]) = full.segment<3>(3 * k);
}

void DirichletSet::scatter_free(const VecX& reduced, VecX& full) const {
  full.setZero(3 * vertex_count());
  for (int k = 0; k < vertex_count(); ++k)
    if (free_index_[k] >= 0) full.segment<3>(3 * k) = reduced.segment<3>(3 * free_index_[k]);
}

void DirichletSet::prescribe(VecX& a, const VecX& x, const VecX& v, const std::vector<Vec3>& targets, double dt) const {
  assert(targets.size() == fixed_.size());
  for (std::size_t h = 0; h < fixed_.size(); ++h) {
    const int k = fixed_[h];
    vertex(a, k) = (targets[h] - vertex(x, k) - dt * vertex(v, k)) / (dt * dt);
  }
}

}  // namespace fnopt
