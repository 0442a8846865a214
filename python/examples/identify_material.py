"""A hidden material identified from a rollout's observed positions by the rollout's gradient.

The default material scaled by --hidden is rolled out (exact steps, fnopt.record_rollout); its
frames 1 .. --frames, with Gaussian noise of --noise metres on every coordinate, are the
observations. From the default material, SciPy's L-BFGS-B in the logarithms of the --fit
coefficients (each within a factor --range of its start) minimises the squared distance of the
rollout's vertices to the observed ones, each evaluation one recorded forward and one backward
pass (RecordedRollout.gradients, docs/design.md §15). Prints CSV, a row per fitted coefficient:
its hidden, start and fitted values and fitted / hidden; then, on stderr, the rollouts taken and
the fitted rollout's RMS distance from the noise-free truth. With gravity fixed the dynamics
depend on the stiffnesses relative to the density, so fitting density with all three
stiffnesses leaves their common scale free: compare their ratios to density then.

    python3 identify_material.py --res 32 --frames 25 --noise 0.001
"""
import argparse
import sys

import numpy as np
from scipy.optimize import minimize

import fnopt

NAMES = ("stretch", "shear", "bend", "density", "damping")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--res", type=int, default=32)
    parser.add_argument("--frames", type=int, default=25, help="observed frames after the initial one")
    parser.add_argument("--motion", default="xy_v2", help="the handles' motion")
    parser.add_argument("--speed", type=float, default=4.0, help="handle speed (the motion x this)")
    parser.add_argument("--noise", type=float, default=0.0, help="observation noise, std in metres")
    parser.add_argument("--fit", default=",".join(NAMES))
    parser.add_argument("--hidden", default="1.6,0.6,2.0,1.3,0.7",
                        help="the hidden material over the default, per coefficient")
    parser.add_argument("--range", type=float, default=3.0,
                        help="each coefficient within start / this .. start x this")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    fit = args.fit.split(",")
    scene = fnopt.Scene(res=args.res, frames=args.frames, motion=args.motion, speed=args.speed)
    start = {n: getattr(scene.material, n) for n in NAMES}
    hidden = {n: start[n] * float(f) for n, f in zip(NAMES, args.hidden.split(","))}
    truth = fnopt.record_rollout(scene.replace(**{n: hidden[n] for n in fit})).positions
    observed = truth + args.noise * np.random.default_rng(args.seed).standard_normal(truth.shape)
    observed[0] = truth[0]  # the initial state is the rest state, known
    rollouts = diverged = 0

    def loss_and_gradient(log_k):
        nonlocal rollouts, diverged
        rollouts += 1
        rollout = fnopt.record_rollout(scene.replace(**{n: float(np.exp(v)) for n, v in zip(fit, log_k)}))
        if rollout.diverged:  # a trial too soft for its mass: a loss above any other, the line search steps back
            diverged += 1
            return 1e6, np.zeros(len(fit))
        residual = rollout.positions - observed
        gradients = rollout.gradients(2.0 * residual)
        return float((residual**2).sum()), np.array([gradients["log_" + n] for n in fit])

    x0 = np.log([start[n] for n in fit])
    result = minimize(loss_and_gradient, x0, jac=True, method="L-BFGS-B",
                      bounds=[(x - np.log(args.range), x + np.log(args.range)) for x in x0],
                      options={"maxiter": 100, "ftol": 1e-15, "gtol": 1e-12})
    fitted = dict(zip(fit, np.exp(result.x)))
    print("coefficient,hidden,start,fitted,fitted_over_hidden")
    for n in fit:
        print(f"{n},{hidden[n]:.6g},{start[n]:.6g},{fitted[n]:.6g},{fitted[n] / hidden[n]:.5f}")
    final = fnopt.record_rollout(scene.replace(**{n: float(v) for n, v in fitted.items()})).positions
    rms = np.sqrt(((final - truth) ** 2).sum(axis=-1).mean())
    print(f"{rollouts} evaluations ({rollouts} forward + {rollouts} backward passes, {diverged} diverged), "
          f"{result.nit} iterations ({result.message}); RMS distance from the noise-free truth {rms:.3g} m",
          file=sys.stderr)


if __name__ == "__main__":
    main()
