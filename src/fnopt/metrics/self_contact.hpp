#pragma once
// Self-contact metrics of a rollout (the paper's Table 6.5): how much a configuration
// interpenetrates, whatever the energy it was simulated with.
//
// Per frame, over the non-adjacent vertex pairs (repulsion_term.hpp) found afresh with the
// spatial hash: the repulsive energy of the configuration under the same barrier
// (repulsion_kernel.hpp) with a fixed reference lambda_ref = 1 N/m and delta = h, the number of
// pairs closer than delta/2 and delta/4 (penetration proxies: a cloth resting on itself under
// repulsion sits just inside delta), and the smallest pair distance.
//
// Over a rollout: the mean and largest per-frame energy and the share of frames whose energy
// exceeds each threshold of kSelfContactThresholds = {1e-5, 1e-4, 1e-3} J. With lambda_ref = 1
// N/m the energy is resolution-consistent (per pair ~ lambda h^2, pairs per area ~ 1/h^2). At
// 32^2 one pair at delta/2 is 1.7e-4 J. What the thresholds separate (fnopt repulsion-study,
// docs/design.md §7): 1e-5 J = the cloth touches itself (a fold resting on itself under
// repulsion); 1e-4 J = pressed contact; 1e-3 J = deep contact, reached only without
// repulsion.
#include <array>
#include <vector>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/spatial_hash.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

constexpr double kSelfContactReferenceStiffness = 1.0;                        // lambda_ref [N/m]
constexpr std::array<double, 3> kSelfContactThresholds = {1e-5, 1e-4, 1e-3};  // [J]

struct SelfContactFrame {
  double energy = 0.0;        // repulsive energy with lambda_ref, delta = h [J]
  int pairs_within = 0;       // non-adjacent pairs closer than delta
  int pairs_half = 0;         // ... closer than delta/2
  int pairs_quarter = 0;      // ... closer than delta/4
  double min_distance = 0.0;  // smallest non-adjacent pair distance below delta, in units of
                              // delta (1 when no pair is within delta)
};

struct SelfContactSummary {
  int frames = 0;
  double mean_energy = 0.0, max_energy = 0.0;
  std::array<double, 3> share_above{};  // fraction of frames above kSelfContactThresholds
  int max_pairs_half = 0, max_pairs_quarter = 0;
  double frames_with_quarter = 0.0;  // fraction of frames with a pair closer than delta/4
  double min_distance = 1.0;         // over all frames, in units of delta
};

// Measures one configuration x of `grid` (delta = h). `hash` is scratch, reused across calls.
SelfContactFrame measure_self_contact(const Grid& grid, const VecX& x, SpatialHash& hash);

SelfContactSummary summarize_self_contact(const std::vector<SelfContactFrame>& frames);

}  // namespace fnopt
