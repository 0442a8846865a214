"""Optimizers written in Python, measured as fnopt compare measures fnopt's own."""
import csv
import dataclasses

import pytest

import fnopt


def test_gradient_descent_in_python_gives_the_built_in_gds_per_step_error():
    scene = fnopt.Scene(res=8, frames=12)
    reference = fnopt.run_rollout(scene, optimizer="newton")
    lr = 0.003  # a fixed step below 2 / lambda_max(P^-1 H) of this grid

    def gradient_descent(problem, a, iters):
        for _ in range(iters):
            a = a - lr * (problem.inverse_metric * problem.gradient(a))
        return a

    mine = fnopt.evaluate_optimizer(gradient_descent, scene, iters=20, reference=reference, samples=4)
    built_in = fnopt.evaluate_optimizer("gd", scene, iters=20, reference=reference, samples=4, lr=lr,
                                        gd_curvature_scaled=False)
    assert isinstance(mine, fnopt.Evaluation)
    assert mine.step_error_mean == pytest.approx(built_in.step_error_mean, rel=1e-9)
    assert mine.step_errors == pytest.approx(built_in.step_errors, rel=1e-9) and len(mine.step_errors) == 4
    assert mine.e_cd == pytest.approx(built_in.e_cd, rel=1e-9)
    assert 0.0 < mine.step_error_mean < 1.0
    assert mine.frames == 12 and not mine.diverged and mine.iters == 20
    assert mine.optimizer.startswith("python " + gradient_descent.__qualname__)


def test_a_newton_reference_is_zero_from_itself_and_pqn_is_close():
    scene = fnopt.Scene(res=8, frames=10)
    newton = fnopt.run_rollout(scene, optimizer="newton")
    same = fnopt.compare_trajectories(newton, newton)
    assert isinstance(same, fnopt.Comparison)
    assert same.e_cd == 0.0 and same.e_3d == 0.0 and same.max_strain == pytest.approx(newton.max_strain)
    row = fnopt.evaluate_optimizer("pqn", scene, iters=10, reference=newton, samples=4)
    assert 0.0 < row.e_cd < 1.0
    assert abs(row.step_error_mean) < 0.5
    pqn = fnopt.run_rollout(scene, optimizer="pqn", iters=10)
    assert fnopt.compare_trajectories(newton, pqn) == fnopt.compare_trajectories(newton, pqn)
    assert fnopt.compare_trajectories(newton, pqn, cd_stride=2).e_cd == pytest.approx(row.e_cd, rel=1e-9)


def test_an_optimizer_that_raises_stops_the_evaluation_with_its_error():
    def broken(problem, a, iters):
        raise RuntimeError("my optimizer failed")

    with pytest.raises(RuntimeError, match="my optimizer failed"):
        fnopt.evaluate_optimizer(broken, fnopt.Scene(res=6, frames=2), iters=3)


def test_compare_returns_its_rows(tmp_path):
    rows = fnopt.compare(fnopt.Scene(res=8, frames=6), ["pqn", "newton"], iters=[5], out=str(tmp_path),
                         step_samples=2)
    assert [(r.method, r.N) for r in rows] == [("pqn", "5"), ("newton", "converged")]
    assert rows[0].e_cd_x1e3 > 0.0 and rows[1].e_cd_x1e3 == 0.0 and rows[0].threads == 1
    # The record's fields are compare.csv's columns, its values the file's cells.
    with open(tmp_path / "compare.csv", newline="") as file:
        cells = list(csv.DictReader(file))
    assert [f.name for f in dataclasses.fields(fnopt.CompareRow)] == list(cells[0])
    assert rows == [fnopt.CompareRow.from_cells(c) for c in cells]
    for row, text in zip(rows, cells):
        assert row.frontier == (text["frontier"] == "yes") and row.diverged == text["diverged"] == "no"
        assert row.ms_per_frame == float(text["ms_per_frame"])
