#pragma once
// fnopt::core in one include (docs/api.md): scenes, the cloth's backward-Euler step, the
// classical inner optimizers, rollouts step by step or whole, rollout files, the metrics and
// gradients through rollouts (adjoint/).
// The learned optimizers and the registry of optimizers by name are <fnopt/learned.hpp>.
#include <fnopt/version.hpp>

#include <fnopt/util/error.hpp>
#include <fnopt/util/types.hpp>

#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/material.hpp>
#include <fnopt/cloth/strain.hpp>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/boundary/handles.hpp>
#include <fnopt/boundary/trajectory.hpp>

#include <fnopt/scenes/scene.hpp>

#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/optimizer/solve_status.hpp>
#include <fnopt/optimizer/step_problem.hpp>

#include <fnopt/baselines/adam.hpp>
#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/implicit_euler.hpp>
#include <fnopt/baselines/lbfgs.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>

#include <fnopt/simulation/newton_reference.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/simulation/simulator.hpp>

#include <fnopt/metrics/chamfer.hpp>
#include <fnopt/metrics/trajectory_error.hpp>

#include <fnopt/adjoint/adjoint_bench.hpp>
#include <fnopt/fits/bounded_lbfgs.hpp>
#include <fnopt/fits/compass_search.hpp>
#include <fnopt/adjoint/gradient_check.hpp>
#include <fnopt/fits/material_fit_gradient.hpp>
#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/fits/handle_path_fit.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
