"""A fit over a horizon in stages (docs/design.md §15), as `fnopt fit-material --horizons` does: where a
buckling cloth makes the loss over the whole horizon rough (its exact gradient holds for steps far shorter
than a fit takes), minimise it first over the first frames, which have not branched yet, then over longer
and longer horizons, each stage from the last one's answer, so that every stage starts in the basin of the
next.

    import fnopt.horizons
    fit = fnopt.horizons.fit_in_stages(loss_for, x0, horizons=[2, 4, 8, 16, 40])
    fit.x                 # the last stage's answer
    fit.stages            # a Stage per horizon: its loss at the start and end, evaluations, why it stopped
"""
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize


@dataclass
class Stage:
    """One stage of a fit: its horizon (frames), its loss at its start and its end, the evaluations it
    took (its start's among them) and SciPy's message on why it stopped."""
    horizon: int
    start_loss: float
    loss: float
    evaluations: int
    message: str


@dataclass
class StagedFit:
    """The answer of the last stage and every stage's record."""
    x: np.ndarray
    stages: list

    @property
    def evaluations(self):
        return sum(s.evaluations for s in self.stages)


def fit_in_stages(loss_for, x0, horizons, evaluations_per_stage=30, bounds=None):
    """Minimise loss_for(h)(x) -> (L, dL/dx) over each horizon h of `horizons` in turn (increasing), with
    SciPy's L-BFGS-B from x0 and then from each stage's answer, at most `evaluations_per_stage` evaluations
    a stage. Each stage minimises its loss divided by the loss at its start, so that the optimiser's
    tolerances are relative on a short horizon's small loss as on the whole one's. Returns a StagedFit.
    Raises ValueError for horizons that are empty, not increasing or below 1."""
    horizons = [int(h) for h in horizons]
    if not horizons or horizons[0] < 1 or any(b <= a for a, b in zip(horizons, horizons[1:])):
        raise ValueError("horizons: must be increasing frame counts of at least 1")
    if evaluations_per_stage < 1:
        raise ValueError("evaluations_per_stage: must be at least 1")
    x = np.asarray(x0, dtype=np.float64).copy()
    stages = []
    for h in horizons:
        loss_and_gradient = loss_for(h)
        # Every point evaluated, by its coordinates: the start's evaluation, which sets the scale, is also
        # the optimiser's first, and the stage's loss is read at the answer SciPy returns (after a failed
        # line search its `fun` is the failed trial's, not the answer's).
        evaluated = {x.tobytes(): loss_and_gradient(x)}
        start_loss = float(evaluated[x.tobytes()][0])
        scale = start_loss if start_loss > 0 else 1.0

        def at(y, f=loss_and_gradient, evaluated=evaluated):
            key = np.asarray(y, dtype=np.float64).tobytes()
            if key not in evaluated:
                evaluated[key] = f(y)
            return evaluated[key]

        def scaled(y, at=at, scale=scale):
            value, gradient = at(y)
            return float(value) / scale, np.asarray(gradient, dtype=np.float64) / scale

        fit = minimize(scaled, x, jac=True, method="L-BFGS-B", bounds=bounds,
                       options={"maxfun": evaluations_per_stage})
        x = np.asarray(fit.x, dtype=np.float64)
        stages.append(Stage(h, start_loss, float(at(x)[0]), len(evaluated), str(fit.message)))
    return StagedFit(x, stages)
