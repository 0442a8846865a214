#pragma once
// Losses on a recorded rollout's positions and their gradients dL/dx per frame, the input of the
// backward pass (adjoint/rollout_adjoint.hpp, docs/design.md §15). A caller's own loss passes its
// FrameGradients to backpropagate directly.
#include <vector>

#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/metrics/chamfer.hpp>

namespace fnopt {

// Target positions of every vertex at one frame.
struct FramePositions {
  int frame = 0;
  VecX positions;  // 3 per vertex
};

// Observed points at one frame (any number, e.g. a scan).
struct FramePoints {
  int frame = 0;
  std::vector<Vec3> points;
};

struct RolloutLoss {
  double value = 0.0;
  std::vector<FrameGradient> gradient;  // one per frame of the loss
  // Parallel to `gradient`, per dof: the lumped diagonal of the frame's loss's Hessian in its
  // positions (nearest neighbours and samples' triangles held fixed), the weights W_f of the
  // Gauss-Newton model L(theta + d) ~ L + g.d + d^T (sum_f J_f^T W_f J_f) d / 2, J_f = dx_f/dtheta
  // (fits/material_fit_gradient.hpp).
  std::vector<VecX> gauss_newton_weights;
};

// L = sum over the given frames of sum_i |x_f,i - target_f,i|^2 [m^2], dL/dx_f = 2 (x_f - target_f).
// Throws Error("loss", ...) for a frame outside the rollout or targets of the wrong size.
RolloutLoss position_loss(const RecordedRollout& rollout, const std::vector<FramePositions>& targets);

// L = sum over the given frames of the Chamfer distance between the cloth's vertices X and the
// observed points Y (metrics/chamfer.hpp's, squared distances, both directions),
//   CD = mean_{x in X} min_y |x - y|^2 + mean_{y in Y} min_x |x - y|^2,
// and its gradient with the nearest neighbours held fixed (differentiable wherever each nearest
// neighbour is unique, i.e. almost everywhere):
//   dCD/dx = (2/|X|)(x - nn_Y(x)) + (2/|Y|) sum_{y : nn_X(y) = x} (x - y).
// The cloth's points are its vertices, not points sampled on its triangles (the e_CD metric's).
// Throws Error("loss", ...) for a frame outside the rollout or an empty point set.
RolloutLoss chamfer_loss(const RecordedRollout& rollout, const std::vector<FramePoints>& observed);

// e_CD itself (metrics/chamfer.hpp, docs/design.md §8) as a loss: L = mean over the given frames
// of CD(S(x_f), Y_f), S(x_f) the `options.samples` points sample_mesh_surface draws on the cloth's
// triangles with options.seed. Each sample is a fixed barycentric combination of its triangle's
// vertices, p = sum_i w_i x_i, so dL/dx_i = sum over the samples on x_i's triangles of w_i dCD/dp
// (chamfer_loss's dCD/dp, nearest neighbours held fixed). The triangle a sample falls on is held
// fixed too: it changes with the triangles' areas only in jumps. With Y_f the observed mesh's
// samples under the same options, L is the e_CD that `fnopt evaluate` reports for those frames.
// Throws as chamfer_loss does.
RolloutLoss surface_chamfer_loss(const RecordedRollout& rollout, const std::vector<FramePoints>& observed,
                                 const ChamferOptions& options = {});

}  // namespace fnopt
