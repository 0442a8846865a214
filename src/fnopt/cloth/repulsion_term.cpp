#include <fnopt/cloth/repulsion_term.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fnopt/cloth/pattern_slots.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

RepulsionTerm::RepulsionTerm(const Grid& grid, const RepulsionParams& params)
    : grid_(grid), params_(params), kernel_{params.stiffness, params.range} {
  require(std::isfinite(params.stiffness) && params.stiffness > 0.0, "repulsion.stiffness",
          "must be a positive finite number");
  require(std::isfinite(params.range) && params.range > 0.0, "repulsion.range", "must be a positive length");
  require(params.candidate_margin >= 0.0 && params.pattern_margin >= params.candidate_margin, "repulsion.margin",
          "needs 0 <= candidate margin <= pattern margin");
}

bool RepulsionTerm::adjacent(const Grid& grid, int a, int b) {
  return std::abs(a / grid.cols - b / grid.cols) <= 1 && std::abs(a % grid.cols - b % grid.cols) <= 1;
}

void RepulsionTerm::collect(const VecX& x) {
  const double radius = params_.range * (1.0 + params_.pattern_margin);
  hash_.build(x, radius);
  const std::size_t first = found_.size();
  hash_.pairs_within(x, radius, found_);
  found_.erase(std::remove_if(found_.begin() + first, found_.end(),
                              [&](const SpatialHash::Pair& p) { return adjacent(grid_, p.i, p.j); }),
               found_.end());
}

void RepulsionTerm::begin_step(const VecX& x_start, const VecX& x_predicted) {
  const double delta = params_.range;
  const double candidate_radius = delta * (1.0 + params_.candidate_margin);
  found_.clear();
  collect(x_start);

  // Pairs in range at the start that the previous step did not have (see the header).
  missed_last_ = 0;
  for (const auto& p : found_)
    if (p.distance < delta && !std::binary_search(candidates_.begin(), candidates_.end(), Pair{p.i, p.j}))
      ++missed_last_;
  missed_total_ += missed_last_;

  if (&x_predicted != &x_start && x_predicted != x_start) collect(x_predicted);
  // Each pair once, at its smaller distance of the two states.
  std::sort(found_.begin(), found_.end(), [](const SpatialHash::Pair& a, const SpatialHash::Pair& b) {
    if (a.i != b.i) return a.i < b.i;
    if (a.j != b.j) return a.j < b.j;
    return a.distance < b.distance;
  });
  found_.erase(
      std::unique(found_.begin(), found_.end(),
                  [](const SpatialHash::Pair& a, const SpatialHash::Pair& b) { return a.i == b.i && a.j == b.j; }),
      found_.end());

  candidates_.clear();
  for (const auto& p : found_)
    if (p.distance < candidate_radius) candidates_.push_back({p.i, p.j});

  // Keep the pattern while it holds every candidate.
  if (!pattern_slots(candidates_, pattern_, candidate_slot_)) {
    pattern_.clear();
    for (const auto& p : found_) pattern_.push_back({p.i, p.j});
    ++generation_;
    pattern_slots(candidates_, pattern_, candidate_slot_);
  }

  if (static_cast<long>(candidates_.size()) >= kParallelThreshold) {
    gradients_.resize(candidates_.size());
    hessians_.resize(candidates_.size());
    active_.resize(candidates_.size());
  }
}

double RepulsionTerm::energy(const VecX& x) const {
  const long count = static_cast<long>(candidates_.size());
  double total = 0.0;
#pragma omp parallel for reduction(+ : total) schedule(static) if (count >= kParallelThreshold)
  for (long c = 0; c < count; ++c) total += kernel_.energy(gather(x, candidates_[c]));
  return total;
}

double RepulsionTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  const long count = static_cast<long>(candidates_.size());
  double total = 0.0;
  if (count < kParallelThreshold) {
    RepulsionKernel::Vec g;
    for (long c = 0; c < count; ++c) {
      const RepulsionKernel::Vec local = gather(x, candidates_[c]);
      if (!kernel_.active(local)) continue;
      total += kernel_.gradient(local, g);
      grad.segment<3>(3 * candidates_[c][0]) += g.head<3>();
      grad.segment<3>(3 * candidates_[c][1]) += g.tail<3>();
    }
    return total;
  }
#pragma omp parallel for reduction(+ : total) schedule(static)
  for (long c = 0; c < count; ++c) {
    const RepulsionKernel::Vec local = gather(x, candidates_[c]);
    active_[c] = kernel_.active(local);
    if (active_[c]) total += kernel_.gradient(local, gradients_[c]);
  }
  for (long c = 0; c < count; ++c) {
    if (!active_[c]) continue;
    grad.segment<3>(3 * candidates_[c][0]) += gradients_[c].head<3>();
    grad.segment<3>(3 * candidates_[c][1]) += gradients_[c].tail<3>();
  }
  return total;
}

int RepulsionTerm::register_hessian(HessianAssembly& assembly) const {
  return assembly.add_stencils(pattern_.empty() ? nullptr : pattern_[0].data(), pattern_.size(), 2);
}

void RepulsionTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  const long count = static_cast<long>(candidates_.size());
  if (count < kParallelThreshold) {
    RepulsionKernel::Mat H;
    for (long c = 0; c < count; ++c) {
      const RepulsionKernel::Vec local = gather(x, candidates_[c]);
      if (!kernel_.active(local)) continue;
      kernel_.hessian(local, H, project);
      assembly.scatter<2>(handle, candidate_slot_[c], H);
    }
    return;
  }
#pragma omp parallel for schedule(static)
  for (long c = 0; c < count; ++c) {
    const RepulsionKernel::Vec local = gather(x, candidates_[c]);
    active_[c] = kernel_.active(local);
    if (active_[c]) kernel_.hessian(local, hessians_[c], project);
  }
  for (long c = 0; c < count; ++c)
    if (active_[c]) assembly.scatter<2>(handle, candidate_slot_[c], hessians_[c]);
}

}  // namespace fnopt
