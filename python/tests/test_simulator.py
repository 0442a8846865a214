"""fnopt.Simulator and run_rollout: the command line's rollouts, step by step and whole."""
import pathlib
import shutil
import threading
import time

import numpy as np
import pytest

import fnopt


def test_a_16x16_rollout_equals_the_command_lines_bit_for_bit(run_cli, tmp_path):
    out = tmp_path / "cli.h5"
    cli = run_cli("simulate", "--res", "16", "--frames", "20", "--optimizer", "pqn", "--iters", "10",
                  "--threads", "1", "--out", str(out))
    assert cli.returncode == 0, cli.stderr
    expected = fnopt.read_rollout(str(out))
    scene = fnopt.Scene(res=16, frames=20)
    frames = fnopt.Simulator(scene, optimizer="pqn", iters=10).rollout(20)
    assert frames.shape == (21, 16, 16, 3) and frames.dtype == np.float64
    assert np.array_equal(frames.astype(np.float32), expected.positions)  # the file stores float32
    whole = fnopt.run_rollout(scene, optimizer="pqn", iters=10)
    assert np.array_equal(whole.positions, expected.positions)
    assert np.array_equal(whole.times, expected.times)
    assert expected.scene == scene and whole.scene == scene


def test_a_rollout_file_round_trips(tmp_path):
    rollout = fnopt.run_rollout(fnopt.Scene(res=8, frames=5), optimizer="lbfgs", iters=5)
    path = tmp_path / "r.h5"
    rollout.write(str(path))
    back = fnopt.read_rollout(str(path))
    assert isinstance(back, fnopt.RolloutFile)
    assert np.array_equal(back.positions, rollout.positions)
    assert (back.rows, back.cols, back.divergence) == (8, 8, "")
    assert back.optimizer == rollout.optimizer_settings
    assert back.version == fnopt.__version__
    assert back == fnopt.read_rollout(str(path))
    assert back != fnopt.RolloutFile(**{**vars(back), "positions": back.positions + 1})


def test_a_rollouts_step_records_are_those_the_simulator_reports():
    scene = fnopt.Scene(res=8, frames=4)
    rollout = fnopt.run_rollout(scene, optimizer="lbfgs", iters=5)
    sim = fnopt.Simulator(scene, optimizer="lbfgs", iters=5)
    assert sim.last_step is None
    assert len(rollout.steps) == 4 and all(isinstance(s, fnopt.StepRecord) for s in rollout.steps)
    for expected in rollout.steps:
        sim.step()
        mine = sim.last_step
        # the same step, only its wall time differs
        assert mine == fnopt.StepRecord(**{**vars(expected), "wall_ms": mine.wall_ms})
        assert mine.iterations <= 5 and mine.loss <= mine.initial_loss
        # every iteration needs the gradient at its iterate; line-search trials may add values
        assert mine.evaluations >= mine.gradient_evaluations >= mine.iterations >= 1
    with pytest.raises(AttributeError):
        mine.loss = 0.0
    assert repr(mine).startswith("StepRecord(wall_ms=")


def test_reprs_say_what_a_rollout_simulator_and_problem_are():
    rollout = fnopt.run_rollout(fnopt.Scene(res=8, frames=3), optimizer="newton")
    assert repr(rollout) == "Rollout(frames=3, rows=8, cols=8, optimizer='newton', diverged=False)"
    assert (rollout.rows, rollout.cols, rollout.optimizer) == (8, 8, "newton")
    sim = fnopt.Simulator(fnopt.Scene(res=6, frames=3), optimizer="pqn", iters=4)
    sim.step()
    assert repr(sim) == f"Simulator(rows=6, cols=6, optimizer='pqn', steps_done=1, time={sim.time:g}, diverged=False)"
    problem = sim.problem()
    handles = len(sim.handle_vertices)
    assert repr(problem) == f"StepProblem(rows=6, cols=6, dt={problem.dt:g}, handles={handles}, valid=True)"
    sim.step()
    assert not problem.valid and repr(problem).endswith("valid=False)")


def test_optimizer_names_is_a_list_of_the_names_the_simulator_takes():
    names = fnopt.optimizer_names()
    assert isinstance(names, list) and {"pqn", "newton", "lbfgs", "gd", "fnopt-ss"} <= set(names)
    assert len(names) == len(set(names))
    # The names the command line's error lists, in its order, before the METHOD-interpK pattern.
    with pytest.raises(fnopt.Error) as raised:
        fnopt.Simulator(fnopt.Scene(res=8), optimizer="no-such-method")
    listed = str(raised.value).split("choose from: ", 1)[1].split(", METHOD-interpK")[0]
    methods, ablations = listed.split("; ablations: ")
    assert fnopt.optimizer_names(ablations=False) == methods.split(", ")
    assert names == methods.split(", ") + ablations.split(", ")
    for name in names:
        sim = fnopt.Simulator(fnopt.Scene(res=12, frames=1), optimizer=name, iters=2)
        assert f"optimizer='{name}'" in repr(sim)


def test_stepping_with_the_trajectorys_handles_equals_the_rollout():
    scene = fnopt.Scene(res=8, frames=6)
    whole = fnopt.Simulator(scene).rollout(6)
    sim = fnopt.Simulator(scene)
    for t in range(1, 7):
        handles = sim.trajectory_targets(t * scene.dt)
        assert np.array_equal(sim.step(handles=handles), whole[t])
    assert sim.steps_done == 6 and sim.time == pytest.approx(6 * scene.dt)
    ij = sim.handle_vertices
    assert np.allclose(sim.positions[ij[:, 0], ij[:, 1]], sim.trajectory_targets(sim.time), atol=1e-12)


def test_closed_loop_handles_go_where_they_are_told():
    scene = fnopt.Scene(res=8, motion="static")
    sim = fnopt.Simulator(scene, optimizer="pqn", iters=10)
    ij = sim.handle_vertices
    for _ in range(5):
        handles = sim.positions[ij[:, 0], ij[:, 1]] + np.array([0.0, 0.0, 0.01])  # lift 1 cm per step
        x = sim.step(handles=handles)
        assert np.allclose(x[ij[:, 0], ij[:, 1]], handles, atol=1e-12)
    with pytest.raises(ValueError, match="handles"):
        sim.step(handles=np.zeros((ij.shape[0] + 1, 3)))


def test_gradient_agrees_with_central_differences_of_energy():
    scene = fnopt.Scene(res=6, frames=2)
    sim = fnopt.Simulator(scene)
    sim.step()
    problem = sim.problem()
    rng = np.random.default_rng(7)
    a = problem.start + rng.normal(scale=2.0, size=problem.start.shape) * problem.free_mask[..., None]
    g = problem.gradient(a)
    assert np.all(g[~problem.free_mask] == 0.0)
    direction = rng.normal(size=a.shape) * problem.free_mask[..., None]
    eps = 1e-4
    fd = (problem.energy(a + eps * direction) - problem.energy(a - eps * direction)) / (2 * eps)
    assert fd == pytest.approx(np.sum(g * direction), rel=1e-6)


def test_hessian_agrees_with_differences_of_the_gradient():
    sim = fnopt.Simulator(fnopt.Scene(res=5, frames=2))
    problem = sim.problem()
    a = problem.start
    H = problem.hessian(a)
    assert H.shape == (75, 75)
    rng = np.random.default_rng(3)
    direction = rng.normal(size=a.shape) * problem.free_mask[..., None]
    eps = 1e-5
    fd = (problem.gradient(a + eps * direction) - problem.gradient(a - eps * direction)) / (2 * eps)
    assert np.allclose(H @ direction.ravel(), fd.ravel(), rtol=1e-5, atol=1e-9 * np.abs(fd).max())
    # A Newton step with it solves the step: the answer Newton gives.
    from scipy.sparse.linalg import spsolve
    step = spsolve(H.tocsc(), -problem.gradient(a).ravel()).reshape(a.shape)
    newton = a + step
    for _ in range(10):
        newton = newton + spsolve(problem.hessian(newton).tocsc(), -problem.gradient(newton).ravel()).reshape(a.shape)
    assert problem.residual_acceleration(newton) < 1e-6


def test_a_step_with_ones_own_acceleration_and_a_stale_problem():
    sim = fnopt.Simulator(fnopt.Scene(res=6, frames=3))
    problem = sim.problem()
    a = problem.start
    x = sim.step(acceleration=a)  # free fall for one step
    assert x.shape == (6, 6, 3)
    with pytest.raises(ValueError, match="problem: its time step is over"):
        problem.energy(a)


def test_another_python_thread_runs_while_a_rollout_does():
    # 120 frames: long enough (well over 0.1 s) on an idle machine too.
    sim = fnopt.Simulator(fnopt.Scene(res=24, frames=120), optimizer="newton")
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=tick)
    thread.start()
    time.sleep(0.01)
    before = len(ticks)
    start = time.perf_counter()
    sim.rollout(120)
    seconds = time.perf_counter() - start
    during = len(ticks) - before
    done.set()
    thread.join()
    assert seconds > 0.1
    assert during > 10, f"{during} ticks in {seconds:.2f} s of rollout"


def test_the_learned_optimizer_with_pqns_direction_runs_by_name_on_the_shipped_model():
    rollout = fnopt.run_rollout(fnopt.Scene(res=16, frames=4), optimizer="fnopt", iters=3)
    assert "fnopt:" in rollout.optimizer_settings and "pqn_direction=isotropic" in rollout.optimizer_settings
    assert rollout.positions.shape == (5, 16, 16, 3) and np.isfinite(rollout.positions).all()
    with pytest.raises(fnopt.Error, match="fnopt-ss-pqm"):
        fnopt.run_rollout(fnopt.Scene(res=8, frames=2), optimizer="fnopt-ss-pqm")


def test_fnopt_ss_runs_the_multires_model_and_fnopt_ss_32_the_32_model():
    for name, model in (("fnopt-ss", fnopt.multires_model_path()), ("fnopt-ss-32", fnopt.shipped_model_path())):
        rollout = fnopt.run_rollout(fnopt.Scene(res=12, frames=2), optimizer=name, iters=3)
        assert rollout.optimizer_settings.startswith(name + ": model=" + model), rollout.optimizer_settings
        assert np.isfinite(rollout.positions).all()


def test_newton_min_runs_by_name_and_says_it_leaves_saddles():
    rollout = fnopt.run_rollout(fnopt.Scene(res=8, frames=3), optimizer="newton-min")
    assert "escape_saddles=1" in rollout.optimizer_settings
    assert rollout.positions.shape == (4, 8, 8, 3) and np.isfinite(rollout.positions).all()


SPHERE_OBJ = pathlib.Path(__file__).resolve().parents[2] / "examples" / "meshes" / "sphere.obj"


def mesh_sphere(obj, center, radius):
    """The spec of the example sphere's mesh (read from `obj`) scaled and moved to `center` and `radius`."""
    scale = radius / 0.25
    x, y, z = np.asarray(center, dtype=float) - scale * np.array([0.0, 0.0, -0.3])
    return f"mesh file={obj} scale={scale!r} offset={x!r},{y!r},{z!r}"


# The example sphere mesh (centre (0, 0, -0.3), radius 0.25, every vertex on the sphere and every facet
# within 0.9 mm inside it) scaled to radius 0.15: its facets within 0.6 mm of the sphere.
@pytest.mark.parametrize("spec, inside", [("sphere center=0,-0.3,-0.4 radius=0.15", 0.0),
                                          (mesh_sphere(SPHERE_OBJ, [0.0, -0.3, -0.4], 0.15), 0.0006)])
def test_obstacles_steered_step_by_step_push_the_cloth_and_stay_outside_it(spec, inside):
    scene = fnopt.Scene(res=8, frames=40, motion="static", obstacles=[spec])
    sim = fnopt.Simulator(scene, optimizer="pqn")
    assert sim.obstacle_offsets.tolist() == [[0.0, 0.0, 0.0]]
    pushed = 0.0
    for t in range(1, 41):
        offset = np.array([[0.0, 0.015 * t, 0.0]])  # through the cloth's plane y = 0 and beyond
        x = sim.step(obstacles=offset).reshape(-1, 3)
        assert np.array_equal(sim.obstacle_offsets, offset)
        assert (np.linalg.norm(x - (np.array([0.0, -0.3, -0.4]) + offset[0]), axis=1) >= 0.15 - inside).all()
        pushed = max(pushed, x[:, 1].max())
    assert pushed > 0.1
    with pytest.raises(fnopt.Error, match="obstacles"):
        sim.step(obstacles=np.zeros((2, 3)))


def test_a_cloth_dropped_on_a_mesh_stays_outside_and_its_rollout_reads_without_the_obj(tmp_path):
    obj = tmp_path / "sphere.obj"
    shutil.copy(SPHERE_OBJ, obj)
    scene = fnopt.Scene(res=8, frames=20, handles="none", placement="horizontal",
                        obstacles=[mesh_sphere(obj, [0.0, 0.0, -0.3], 0.25) + " friction=0.3",
                                   "plane point=0,0,-0.6 normal=0,0,1"])
    rollout = fnopt.run_rollout(scene, optimizer="pqn")
    assert not rollout.diverged
    x = rollout.positions.reshape(21, -1, 3)
    distance = np.linalg.norm(x - np.array([0.0, 0.0, -0.3]), axis=2) - 0.25
    assert distance.min() > -0.001  # outside the mesh, whose facets lie within 0.9 mm of the sphere
    # It fell onto the sphere and rests within the barrier's range (dhat = h / 2, h = 1/7) of it,
    # its edges hanging past it.
    assert distance[-1].min() < 0.5 / 7 + 0.001 and x[-1, :, 2].min() < -0.3
    path = tmp_path / "drop.h5"
    rollout.write(str(path))
    obj.unlink()
    back = fnopt.read_rollout(str(path))  # the mesh from the file, its OBJ gone
    assert back.scene == scene and np.array_equal(back.positions, rollout.positions)
