"""Gradients through rollouts from Python (docs/design.md §15): fnopt.record_rollout, its
gradients against central differences of the rollout, the checks on its input, and the PyTorch
bridge under torch.autograd.gradcheck."""
import warnings

import numpy as np
import pytest

import fnopt

# 6 x 6 over 10 steps, the two corner handles' xy_v2 four times faster so that they move within it.
SCENE = fnopt.Scene(res=6, frames=10, speed=4)


def linear_loss_weights(rollout, seed=3):
    return np.random.default_rng(seed).standard_normal(rollout.positions.shape)


def test_a_recorded_rollout_has_the_frames_of_a_rollout():
    recorded = fnopt.record_rollout(SCENE)
    reference = fnopt.run_rollout(SCENE, optimizer="newton")
    assert recorded.positions.shape == (11, 6, 6, 3)
    assert repr(recorded) == "RecordedRollout(frames=10, rows=6, cols=6, optimizer='newton', diverged=False)"
    assert recorded.handle_count == 2 and not recorded.diverged
    # Newton to a far tighter tolerance: the same frames to well below a millimetre.
    assert np.abs(recorded.positions - reference.positions).max() < 1e-4


def test_the_gradients_match_differences_of_the_rollout():
    recorded = fnopt.record_rollout(SCENE)
    w = linear_loss_weights(recorded)
    g = recorded.gradients(w)
    assert set(g) >= {"stretch", "log_stretch", "damping", "gravity", "handle_targets", "initial_positions",
                      "initial_velocities"}
    assert g["gravity"].shape == (3,)
    assert g["handle_targets"].shape == (10, 2, 3)
    assert g["initial_positions"].shape == (6, 6, 3)
    assert g["log_stretch"] == pytest.approx(473.2 * g["stretch"])

    def loss(**settings):
        return float((w * fnopt.record_rollout(SCENE.replace(**settings)).positions).sum())

    e = 1e-5
    for name, value in (("stretch", 473.2), ("damping", 4.0)):
        difference = (loss(**{name: value * np.exp(e)}) - loss(**{name: value * np.exp(-e)})) / (2 * e)
        assert g["log_" + name] == pytest.approx(difference, rel=1e-4), name
    # Along the initial velocities: a direction d, <dL/dv0, d> against the central difference.
    d = np.random.default_rng(5).standard_normal((6, 6, 3))
    h = 1e-6
    plus = fnopt.record_rollout(SCENE, initial_velocities=h * d).positions
    minus = fnopt.record_rollout(SCENE, initial_velocities=-h * d).positions
    assert (g["initial_velocities"] * d).sum() == pytest.approx(((plus - minus) * w).sum() / (2 * h), rel=1e-4)


def test_gradients_through_contact_and_friction_match_differences():
    # A sphere 2 cm behind the cloth, within the contact range: the barrier pushes it off its plane
    # and friction holds it (docs/design.md §15).
    scene = fnopt.Scene(res=8, frames=20, speed=4, obstacles=["sphere center=0.5,0.12,-0.6 radius=0.1 friction=0.5"])
    recorded = fnopt.record_rollout(scene)
    w = linear_loss_weights(recorded)
    g = recorded.gradients(w)
    d = np.random.default_rng(7).standard_normal((8, 8, 3))
    h = 1e-6
    for name in ("initial_positions", "initial_velocities"):
        plus = fnopt.record_rollout(scene, **{name: (recorded.positions[0] if name == "initial_positions" else 0) + h * d})
        minus = fnopt.record_rollout(scene, **{name: (recorded.positions[0] if name == "initial_positions" else 0) - h * d})
        difference = ((plus.positions - minus.positions) * w).sum() / (2 * h)
        assert (g[name] * d).sum() == pytest.approx(difference, rel=1e-4), name


def test_the_gradients_carry_the_backward_pass_verdict():
    # A small cloth pulled along is well conditioned; at 12² over 30 steps it buckles and a start
    # perturbation grows millions of times: the verdict says how far each kind's gradient holds.
    g = fnopt.record_rollout(SCENE).gradients(linear_loss_weights(fnopt.record_rollout(SCENE)))
    assert g["status"] == "exact"
    assert g["verdict"]["conditioning"] == "well-conditioned"
    buckling = fnopt.record_rollout(fnopt.Scene(res=12, frames=30, speed=4))
    v = buckling.gradients(linear_loss_weights(buckling))["verdict"]
    assert v["conditioning"] == "ill-conditioned"
    assert v["start_radius"] < 1e-6 * g["verdict"]["start_radius"] and v["growth"] > 1e5
    assert v["valid_below"]["initial_positions"] == pytest.approx(v["start_radius"])
    assert set(v["valid_below"]) == {"stretch", "shear", "bend", "density", "damping", "gravity", "handle_targets",
                                     "initial_positions", "initial_velocities"}
    assert 0.0 < v["precision"] < 1.0 and v["loss_radius"] > 0.0 and 1 <= v["binding_frame"] <= 30


def test_a_dict_of_frames_is_the_same_loss_as_the_whole_array():
    recorded = fnopt.record_rollout(SCENE)
    w = linear_loss_weights(recorded)
    sparse = np.zeros_like(w)
    sparse[[4, 10]] = w[[4, 10]]
    whole = recorded.gradients(sparse)
    frames = recorded.gradients({4: w[4], 10: w[10]})
    for name in ("stretch", "bend", "gravity", "handle_targets", "initial_positions"):
        np.testing.assert_allclose(frames[name], whole[name], rtol=1e-12, atol=1e-15)


def test_the_handle_path_gradient_is_the_chain_rule_of_the_targets():
    path = np.zeros((2, 3, 3))
    recorded = fnopt.record_rollout(SCENE, handle_path=path, path_basis="linear")
    g = recorded.gradients(linear_loss_weights(recorded))
    assert g["handle_path"].shape == (2, 3, 3)
    # The linear basis: offsets interpolate linearly between 0 at t = 0 and control point k at
    # t = (k + 1) T dt / K; dL/dc_k = sum_s B_k(t_{s+1}) dL/dy_s with those hat functions.
    steps, points = 10, 3
    knots = np.concatenate([[0.0], (np.arange(points) + 1) * steps / points])
    times = np.arange(1, steps + 1)
    weights = np.stack([np.interp(times, knots, np.eye(points + 1)[k + 1]) for k in range(points)], axis=1)
    np.testing.assert_allclose(g["handle_path"], np.einsum("sk,shd->hkd", weights, g["handle_targets"]),
                               rtol=1e-10, atol=1e-14)
    assert np.abs(g["handle_path"]).max() > 0


def test_chamfer_loss_is_e_cd_and_its_gradient_matches_differences():
    # Another material's frames as the observation, sampled as e_CD samples them.
    recorded = fnopt.record_rollout(SCENE)
    other = fnopt.record_rollout(SCENE.replace(stretch=700.0, shear=15.0))
    observed = {f: fnopt.sample_surface(other.positions[f], samples=300) for f in (0, 5, 10)}
    assert observed[5].shape == (300, 3)
    value, dL_dX = recorded.chamfer_loss(observed, samples=300)
    assert value > 0 and sorted(dL_dX) == [0, 5, 10] and dL_dX[5].shape == (6, 6, 3)
    own = other.chamfer_loss(observed, samples=300)
    assert own[0] == 0.0 and all(not g.any() for g in own[1].values())
    g = recorded.gradients(dL_dX)

    def loss(stretch):
        return fnopt.record_rollout(SCENE.replace(stretch=stretch)).chamfer_loss(observed, samples=300)[0]

    e = 1e-5
    difference = (loss(473.2 * np.exp(e)) - loss(473.2 * np.exp(-e))) / (2 * e)
    assert g["log_stretch"] == pytest.approx(difference, rel=1e-4)


def test_bad_input_raises_the_one_line_errors():
    recorded = fnopt.record_rollout(SCENE)
    with pytest.raises(fnopt.Error, match=r"^dL_dX: expected shape \(11, 6, 6, 3\) \(the positions'\) or a dict"):
        recorded.gradients(np.zeros((10, 6, 6, 3)))
    with pytest.raises(fnopt.Error, match=r"^dL_dX: frame 11 is outside the rollout's frames 0..10$"):
        recorded.gradients({11: np.zeros((6, 6, 3))})
    with pytest.raises(fnopt.Error, match=r"^dL_dX: expected shape \(6, 6, 3\) or \(108,\)$"):
        recorded.gradients({3: np.zeros((6, 3))})
    with pytest.raises(fnopt.Error, match=r"^path_basis: expected cubic-bspline or linear, got 'spline'$"):
        fnopt.record_rollout(SCENE, handle_path=np.zeros((2, 2, 3)), path_basis="spline")
    with pytest.raises(fnopt.Error, match=r"^handle_path: expected shape \(2, K, 3\)"):
        fnopt.record_rollout(SCENE, handle_path=np.zeros((3, 2, 3)))
    with pytest.raises(fnopt.Error, match=r"^handle_targets: expected shape \(10, 2, 3\)$"):
        fnopt.record_rollout(SCENE, handle_targets=np.zeros((9, 2, 3)))
    with pytest.raises(fnopt.Error, match=r"^initial_positions: expected shape \(6, 6, 3\)"):
        fnopt.record_rollout(SCENE, initial_positions=np.zeros((5, 6, 3)))
    with pytest.raises(fnopt.Error, match=r"^optimizer: unknown optimizer 'sgd' \(choose from: pqn, newton, "):
        fnopt.record_rollout(SCENE, optimizer="sgd")
    with pytest.raises(fnopt.Error, match=r"^observed\[3\]: expected shape \(P, 3\), P >= 1$"):
        recorded.chamfer_loss({3: np.zeros((4, 2))})
    with pytest.raises(fnopt.Error, match=r"^loss: frame 12 is outside the rollout's 0..10$"):
        recorded.chamfer_loss({12: np.zeros((4, 3))})
    with pytest.raises(fnopt.Error, match=r"^samples: must lie in \[1, 10\^7\]$"):
        fnopt.sample_surface(recorded.positions[0], samples=0)
    with pytest.raises(fnopt.Error, match=r"^positions: expected shape \(rows, cols, 3\)"):
        fnopt.sample_surface(np.zeros((6, 3)))


def test_any_optimizer_polished_by_newton_records_the_same_rollout():
    polished = fnopt.record_rollout(SCENE, optimizer="pqn", iters=5)
    assert repr(polished).endswith("optimizer='pqn', diverged=False)")
    # Every step ends at the same stationary point as Newton's, to the tight tolerance.
    np.testing.assert_allclose(polished.positions, fnopt.record_rollout(SCENE).positions, atol=1e-8)


def test_the_torch_bridge_passes_gradcheck():
    torch = pytest.importorskip("torch")
    import fnopt.torch as ftorch

    scene = fnopt.Scene(res=4, frames=6, speed=4)
    rest = fnopt.record_rollout(scene.replace(frames=1))
    dtype = torch.float64
    log_k = torch.log(torch.tensor([473.2, 29.18, 2e-5, 0.187, 4.0], dtype=dtype)).requires_grad_()
    path = torch.zeros((2, 2, 3), dtype=dtype, requires_grad=True)
    x0 = torch.tensor(rest.positions[0], dtype=dtype, requires_grad=True)
    v0 = torch.zeros((4, 4, 3), dtype=dtype, requires_grad=True)

    def positions(log_k, path, x0, v0):
        return ftorch.rollout(scene, torch.exp(log_k), path, x0, v0, frames=[3, 6])

    # A well-conditioned rollout: its backward pass warns of nothing.
    with warnings.catch_warnings():
        warnings.simplefilter("error", ftorch.GradientWarning)
        positions(log_k, path, x0, v0).sum().backward()
    # gradcheck's defaults (eps 1e-6, atol 1e-5, rtol 1e-3): each perturbed rollout is Newton-solved
    # to 1e-10 m/s^2 again, so a difference's solver error, about dt^2 1e-10 / eps, stays far below atol.
    assert torch.autograd.gradcheck(positions, (log_k, path, x0, v0))


def test_the_torch_bridge_warns_where_the_gradient_is_ill_conditioned():
    torch = pytest.importorskip("torch")
    import fnopt.torch as ftorch

    scene = fnopt.Scene(res=12, frames=30, speed=4)
    material = torch.tensor([473.2, 29.18, 2e-5, 0.187, 4.0], dtype=torch.float64, requires_grad=True)
    x = ftorch.rollout(scene, material, frames=[30])
    with pytest.warns(ftorch.GradientWarning, match=r"^fnopt: rollout gradient ill-conditioned: valid for start "):
        x.sum().backward()
    assert torch.isfinite(material.grad).all()


def test_smoothing_averages_over_antithetic_draws():
    import fnopt.smoothing

    a = np.array([1.0, 2.0, 0.5])
    calls = []

    def quadratic(x):
        calls.append(x.copy())
        return float(x @ (a * x)), 2.0 * a * x

    smoothed = fnopt.smoothing.smoothed(quadratic, sigma=0.3, samples=6, seed=7)
    x = np.array([0.4, 0.1, -1.0])
    value, gradient = smoothed(x)
    # The antithetic pairs cancel the gradient's odd terms: on a quadratic it is the gradient itself.
    np.testing.assert_allclose(gradient, 2.0 * a * x, atol=1e-12)
    assert value > float(x @ (a * x)) and smoothed.standard_error > 0.0
    assert len(calls) == 6 and np.allclose(calls[0] - x, -(calls[3] - x))
    smoothed(x + 1.0)  # the same draws at another point
    np.testing.assert_allclose(calls[6] - (x + 1.0), calls[0] - x, atol=1e-15)
    with pytest.raises(ValueError, match="^samples: must be an even number"):
        fnopt.smoothing.smoothed(quadratic, sigma=0.1, samples=3)
    with pytest.raises(ValueError, match="^sigma: must be at least 0"):
        fnopt.smoothing.smoothed(quadratic, sigma=-1.0)


def test_a_fit_in_stages_minimises_each_horizon_from_the_last_answer():
    import fnopt.horizons

    target = np.array([0.3, -0.2, 0.5, 0.1])
    calls = []

    def loss_for(h):
        # The first h coordinates matter over a horizon of h: a later stage sees more of them.
        def loss_and_gradient(x):
            calls.append(h)
            r = np.zeros_like(x)
            r[:h] = x[:h] - target[:h]
            return float(r @ r), 2.0 * r
        return loss_and_gradient

    fit = fnopt.horizons.fit_in_stages(loss_for, np.zeros(4), [1, 2, 4], evaluations_per_stage=20)
    np.testing.assert_allclose(fit.x, target, atol=1e-6)
    assert [s.horizon for s in fit.stages] == [1, 2, 4]
    # Each stage starts where the last ended: its start loss is its horizon's loss there.
    assert fit.stages[1].start_loss == pytest.approx(0.2**2, rel=1e-5)
    assert fit.stages[2].start_loss == pytest.approx(0.5**2 + 0.1**2, rel=1e-5)
    assert all(s.loss < 1e-10 for s in fit.stages)
    # Every evaluation is counted once, the stage's start (which is also the optimiser's first) included.
    assert [s.evaluations for s in fit.stages] == [calls.count(h) for h in (1, 2, 4)]
    assert fit.evaluations == len(calls)
    with pytest.raises(ValueError, match="^horizons: must be increasing"):
        fnopt.horizons.fit_in_stages(loss_for, np.zeros(4), [2, 2])
    with pytest.raises(ValueError, match="^evaluations_per_stage: must be at least 1"):
        fnopt.horizons.fit_in_stages(loss_for, np.zeros(4), [1], evaluations_per_stage=0)
