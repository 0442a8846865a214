#include <fnopt/metrics/self_contact.hpp>

#include <algorithm>

#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/cloth/repulsion_term.hpp>

namespace fnopt {

SelfContactFrame measure_self_contact(const Grid& grid, const VecX& x, SpatialHash& hash) {
  const double delta = grid.spacing;
  const RepulsionKernel kernel{kSelfContactReferenceStiffness, delta};
  thread_local std::vector<SpatialHash::Pair> pairs;
  pairs.clear();
  hash.build(x, delta);
  hash.pairs_within(x, delta, pairs);
  SelfContactFrame frame;
  frame.min_distance = 1.0;
  for (const auto& p : pairs) {
    if (RepulsionTerm::adjacent(grid, p.i, p.j)) continue;
    ++frame.pairs_within;
    frame.pairs_half += p.distance < 0.5 * delta;
    frame.pairs_quarter += p.distance < 0.25 * delta;
    frame.energy += kernel.barrier(p.distance);
    frame.min_distance = std::min(frame.min_distance, p.distance / delta);
  }
  return frame;
}

SelfContactSummary summarize_self_contact(const std::vector<SelfContactFrame>& frames) {
  SelfContactSummary s;
  s.frames = static_cast<int>(frames.size());
  if (frames.empty()) return s;
  int with_quarter = 0;
  for (const auto& f : frames) {
    s.mean_energy += f.energy;
    s.max_energy = std::max(s.max_energy, f.energy);
    for (std::size_t k = 0; k < kSelfContactThresholds.size(); ++k)
      s.share_above[k] += f.energy > kSelfContactThresholds[k];
    s.max_pairs_half = std::max(s.max_pairs_half, f.pairs_half);
    s.max_pairs_quarter = std::max(s.max_pairs_quarter, f.pairs_quarter);
    with_quarter += f.pairs_quarter > 0;
    s.min_distance = std::min(s.min_distance, f.min_distance);
  }
  s.mean_energy /= s.frames;
  for (double& share : s.share_above) share /= s.frames;
  s.frames_with_quarter = static_cast<double>(with_quarter) / s.frames;
  return s;
}

}  // namespace fnopt
