"""The Python examples (python/examples) run, and what they print holds together."""
import csv
import io
import pathlib
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_step_error_spectrum_splits_the_error_into_bands_that_add_up():
    run = subprocess.run([sys.executable, str(EXAMPLES / "step_error_spectrum.py"), "--res", "12", "--states", "3,5",
                          "--methods", "pqn,lbfgs", "--iters", "3", "--modes", "2"],
                         capture_output=True, text=True, check=True)
    rows = list(csv.DictReader(io.StringIO(run.stdout)))
    assert len(rows) == 2 * 2 * 3  # methods x states x bands
    for key in {(r["method"], r["state"]) for r in rows}:
        bands = [r for r in rows if (r["method"], r["state"]) == key]
        assert 0.0 < float(bands[0]["step_error"]) < 1.0
        # The bands split |e|^2 (an orthonormal DCT; the handles' entries are zero before and after).
        assert abs(sum(float(b["l2_share"]) for b in bands) - 1.0) < 0.02


def test_identify_material_recovers_a_hidden_material_from_noise_free_frames():
    run = subprocess.run([sys.executable, str(EXAMPLES / "identify_material.py"), "--res", "6", "--frames", "8",
                          "--fit", "stretch,damping"], capture_output=True, text=True, check=True)
    rows = list(csv.DictReader(io.StringIO(run.stdout)))
    assert [r["coefficient"] for r in rows] == ["stretch", "damping"]
    for r in rows:
        assert abs(float(r["fitted_over_hidden"]) - 1.0) < 1e-3, r
        assert abs(float(r["start"]) / float(r["hidden"]) - 1.0) > 0.3, r
    assert "forward +" in run.stderr


def test_fit_start_state_in_stages_ends_far_below_the_whole_horizons_fit():
    # A 10^2 cloth buckling under fast handles, 16 frames: the same rollout budget for both fits.
    run = subprocess.run([sys.executable, str(EXAMPLES / "fit_start_state.py"), "--res", "10", "--frames", "16",
                          "--stages", "2,4,8,16", "--evaluations", "12"], capture_output=True, text=True, check=True)
    rows = {r["fit"]: r for r in csv.DictReader(io.StringIO(run.stdout))}
    assert set(rows) == {"whole horizon", "in stages", "hidden + 1e-8"}
    whole, staged = rows["whole horizon"], rows["in stages"]
    assert float(staged["loss_m2"]) < 0.1 * float(whole["loss_m2"]), run.stdout
    assert float(staged["loss_m2"]) < 1e-3 * float(staged["start_loss_m2"]), run.stdout
    assert abs(int(staged["rollouts"]) - int(whole["rollouts"])) <= 4 + int(whole["rollouts"]) // 2
    assert "stage of 16 frames" in run.stderr
