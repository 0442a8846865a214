"""A hidden start velocity fitted to a buckling cloth's observed frames: over the whole horizon at once,
and over a horizon in stages (fnopt.horizons, docs/design.md §15).

The default cloth at rest, its handles pulled at --speed, starts with a hidden smooth velocity field
(--knots x --knots control values of --scale m/s, bilinear over the grid); its frames 1 .. --frames are
observed. From a start at rest, SciPy's L-BFGS-B fits the control values by the rollout's exact gradient
(fnopt.record_rollout, RecordedRollout.gradients), minimising the squared distance of the vertices to the
observed ones over every frame: first over the whole horizon at once, then in stages over the first
--stages frames. At rest the cloth sits on the symmetric point of its buckling, so the whole horizon's
loss is rough at far smaller steps than the fit takes; its first frames are not. Prints CSV, a row per
fit: its stages, rollouts and the whole horizon's loss at the start and the end; then the loss of the
hidden field moved by 1e-8 of its size, which says how much of the horizon the frames determine.

    python3 fit_start_state.py --res 32 --frames 40 --stages 2,4,8,16,40
"""
import argparse
import sys

import numpy as np
from scipy.optimize import minimize

import fnopt
import fnopt.horizons


def bilinear_rows(res, knots):
    """res x knots weights of the knots' hat functions at the grid's rows (or columns)."""
    weights = np.zeros((res, knots))
    for i, t in enumerate(np.linspace(0.0, knots - 1.0, res)):
        j = min(int(t), knots - 2)
        weights[i, j], weights[i, j + 1] = j + 1 - t, t - j
    return weights


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--res", type=int, default=32)
    parser.add_argument("--frames", type=int, default=40, help="observed frames after the initial one")
    parser.add_argument("--speed", type=float, default=4.0, help="handle speed (the motion x this)")
    parser.add_argument("--knots", type=int, default=6, help="control values per side of the velocity field")
    parser.add_argument("--scale", type=float, default=0.1, help="the hidden control values' std, m/s")
    parser.add_argument("--stages", default="2,4,8,16,40", help="the staged fit's horizons, frames")
    parser.add_argument("--evaluations", type=int, default=30, help="rollouts per stage at most")
    parser.add_argument("--seed", type=int, default=3)
    args = parser.parse_args()

    scene = fnopt.Scene(res=args.res, frames=args.frames, speed=args.speed)
    weights = bilinear_rows(args.res, args.knots)
    shape = (args.knots, args.knots, 3)

    def field(c):
        return np.einsum("ia,abk,jb->ijk", weights, c.reshape(shape), weights)

    hidden = args.scale * np.random.default_rng(args.seed).standard_normal(shape)
    observed = fnopt.record_rollout(scene, initial_velocities=field(hidden)).positions
    rollouts = [0]

    def loss_for(horizon):
        short = scene.replace(frames=horizon)

        def loss_and_gradient(c):
            rollouts[0] += 1
            rollout = fnopt.record_rollout(short, initial_velocities=field(c))
            residual = rollout.positions - observed[: horizon + 1]
            dv = rollout.gradients(2.0 * residual)["initial_velocities"]
            return float((residual**2).sum()), np.einsum("ia,ijk,jb->abk", weights, dv, weights).ravel()
        return loss_and_gradient

    whole = loss_for(args.frames)
    start = np.zeros(hidden.size)
    start_loss = whole(start)[0]
    stages = [int(h) for h in args.stages.split(",")]
    print("fit,stages,rollouts,start_loss_m2,loss_m2")

    rollouts[0] = 0
    exact = minimize(whole, start, jac=True, method="L-BFGS-B", options={"maxfun": args.evaluations * len(stages)})
    print("whole horizon,%d,%d,%.6g,%.6g" % (args.frames, rollouts[0], start_loss, whole(exact.x)[0]))

    rollouts[0] = 0
    staged = fnopt.horizons.fit_in_stages(loss_for, start, stages, evaluations_per_stage=args.evaluations)
    spent = rollouts[0]
    print("in stages,%s,%d,%.6g,%.6g" % (" ".join(map(str, stages)), spent, start_loss, whole(staged.x)[0]))
    # How far the frames themselves pin the start down: the hidden field moved by 1e-8 of its size.
    nudge = np.random.default_rng(args.seed + 1).standard_normal(hidden.size)
    nudge *= 1e-8 * np.linalg.norm(hidden) / np.linalg.norm(nudge)
    print("hidden + 1e-8,,1,%.6g,%.6g" % (start_loss, whole(hidden.ravel() + nudge)[0]))
    for s in staged.stages:
        print("stage of %d frames: loss %.4g -> %.4g, %d rollouts (%s)" % (s.horizon, s.start_loss, s.loss,
                                                                          s.evaluations, s.message), file=sys.stderr)


if __name__ == "__main__":
    main()
