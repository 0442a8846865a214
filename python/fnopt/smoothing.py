"""Randomized smoothing of a loss for gradient-based fits (docs/design.md §15), as `fnopt fit-handles
--smoothing` does: where a buckling cloth makes the exact gradient hold only for tiny steps, minimise
L_sigma(x) = E[L(x + sigma e)], e ~ N(0, I), estimated over fixed antithetic draws (the same at every x,
so that the estimate is one smooth function an optimiser's line search can work on).

    import fnopt, fnopt.smoothing
    smoothed = fnopt.smoothing.smoothed(loss_and_gradient, sigma=0.01, samples=8)
    value, gradient = smoothed(x)            # as loss_and_gradient, averaged over the draws
    smoothed.standard_error                  # of the last mean gradient
"""
import numpy as np


class smoothed:
    """`loss_and_gradient(x) -> (L, dL/dx)` averaged over x + sigma e_k, k < samples (antithetic pairs
    e, -e from `seed`); calling it returns (mean L, mean dL/dx) and sets `standard_error`, the norm of the
    mean gradient's standard error. Raises fnopt.Error-like ValueError for a negative sigma or an odd or
    too small sample count."""

    def __init__(self, loss_and_gradient, sigma, samples=8, seed=1):
        if not np.isfinite(sigma) or sigma < 0:
            raise ValueError("sigma: must be at least 0 (0: the exact gradient)")
        if samples < 2 or samples % 2:
            raise ValueError("samples: must be an even number of at least 2 (antithetic pairs)")
        self.loss_and_gradient = loss_and_gradient
        self.sigma, self.samples, self.seed = float(sigma), int(samples), seed
        self.standard_error = 0.0
        self._draws = None

    def __call__(self, x):
        x = np.asarray(x, dtype=np.float64)
        if self._draws is None or self._draws.shape[1:] != x.shape:
            half = np.random.default_rng(self.seed).standard_normal((self.samples // 2,) + x.shape)
            self._draws = self.sigma * np.concatenate([half, -half])
        values, gradients = [], []
        for draw in self._draws:
            value, gradient = self.loss_and_gradient(x + draw)
            values.append(float(value))
            gradients.append(np.asarray(gradient, dtype=np.float64))
        gradients = np.array(gradients)
        self.standard_error = float(np.sqrt(gradients.var(axis=0, ddof=1).sum() / len(gradients)))
        return float(np.mean(values)), gradients.mean(axis=0)
