"""Where in the spectrum a method's per-step error sits.

From states of the converged Newton rollout of a scene, one step is solved by Newton (a*) and by
each method at its budget (a_N), both from a = 0 as fnopt's per-step error does. The error field
e = a_N - a* (rows, cols, 3) is split by wavenumber with an orthonormal 2-D DCT over the grid (the
cloth's edges are free: no periodic wrap-around) into three bands, by c = max(cy, cx), the cycles
across the cloth: the scales an FNO with `modes` modes per axis keeps (c < modes), those from
there to a wavelength of 4 cells (c < N/4), and the few-cell scales below. Per band it prints
the share of |e|^2 (the bands' shares add up to 1) and `fixed`: the share of the step's energy
error L(a_N) - L(a*) that would go if that band's error were removed (a_N - e_band), which is
what the per-step error measures.

    PYTHONPATH=build/python python3 python/examples/step_error_spectrum.py --res 32,64,100
"""
import argparse

import numpy as np
from scipy.fft import dctn, idctn

import fnopt


def band_masks(rows, cols, modes):
    # DCT-II index k is k/2 cycles across the grid.
    cycles = np.maximum(np.arange(rows)[:, None], np.arange(cols)[None, :]) / 2
    quarter = max(rows, cols) / 4
    return {
        f"kept c<{modes}": cycles < modes,
        f"mid {modes}<=c<{quarter:g}": (cycles >= modes) & (cycles < quarter),
        f"fine c>={quarter:g}": cycles >= quarter,
    }


def band_fields(error, masks):
    """The error field restricted to each band (inverse DCT of the masked coefficients)."""
    coefficients = dctn(error, axes=(0, 1), norm="ortho")
    return {name: idctn(coefficients * mask[..., None], axes=(0, 1), norm="ortho") for name, mask in masks.items()}


def acceleration(before, after, velocity, dt):
    return ((after - before) / dt - velocity) / dt


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--res", default="32,64,100")
    parser.add_argument("--motion", default="xy_v2")
    parser.add_argument("--states", default="20,40,60", help="frames of the Newton rollout to start from")
    parser.add_argument("--methods", default="pqn,fnopt-ss")
    parser.add_argument("--iters", type=int, default=10)
    parser.add_argument("--modes", type=int, default=8, help="Fourier modes per axis of the FNO")
    args = parser.parse_args()
    fnopt.set_threads(1)
    states = sorted(int(s) for s in args.states.split(","))
    methods = args.methods.split(",")
    print("res,method,state,step_error,band,l2_share,fixed")
    for res in (int(r) for r in args.res.split(",")):
        scene = fnopt.Scene(res=res, motion=args.motion, frames=states[-1])
        newton = fnopt.Simulator(scene, optimizer="newton")
        solvers = {m: fnopt.Simulator(scene, optimizer=m, iters=args.iters) for m in methods}
        masks = band_masks(scene.rows, scene.cols, args.modes)
        for t in range(1, states[-1] + 1):
            x, v = newton.positions, newton.velocities
            if t in states:
                problem = newton.problem()
                start = problem.start
                exact = acceleration(x, newton.step(), v, scene.dt)
                for m, sim in solvers.items():
                    sim.set_state(x, v, steps=t - 1)
                    mine = acceleration(x, sim.step(), v, scene.dt)
                    sim.set_state(x, v, steps=t - 1)  # the step's problem at the same state
                    step = sim.problem()
                    free = step.free_mask[..., None]
                    l_star = step.energy(exact)
                    step_error = (step.energy(mine) - l_star) / (step.energy(start) - l_star)
                    error = (mine - exact) * free
                    total = np.sum(error**2)
                    for band, field in band_fields(error, masks).items():
                        field = field * free  # the handles stay prescribed
                        fixed = 1 - (step.energy(mine - field) - l_star) / (step.energy(mine) - l_star)
                        print(f"{res},{m},{t},{step_error:.4g},{band},{np.sum(field**2) / total:.3f},{fixed:.3f}",
                              flush=True)
            else:
                newton.step()


if __name__ == "__main__":
    main()
