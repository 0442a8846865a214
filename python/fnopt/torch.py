"""fnopt.torch: a rollout of exact steps as a differentiable PyTorch function (docs/design.md §15).

    import torch, fnopt, fnopt.torch
    scene = fnopt.Scene(res=6, frames=10, speed=4)
    material = torch.tensor([473.2, 29.18, 2e-5, 0.187, 4.0], dtype=torch.float64, requires_grad=True)
    x = fnopt.torch.rollout(scene, material, frames=[10])      # (1, 6, 6, 3)
    x.square().sum().backward()                                 # material.grad: dL/dk

The forward pass is `fnopt.record_rollout`, the backward pass the rollout's adjoint
(`RecordedRollout.gradients`). Importing this module imports torch (Debian's python3-torch); the
package `fnopt` itself does not.
"""
import warnings

import numpy as np
import torch

from ._fnopt import record_rollout

#: The material coefficients in the order of the `material` tensor.
COEFFICIENTS = ("stretch", "shear", "bend", "density", "damping")


class RolloutFunction(torch.autograd.Function):
    """The positions of chosen frames of a recorded rollout, with the adjoint as its backward pass.

    Inputs: the material coefficients (5,), the handle path's control points (handles, K, 3),
    the initial positions and velocities (rows, cols, 3), all float64; output (len(frames), rows,
    cols, 3). Use it through `rollout`.
    """

    @staticmethod
    def forward(ctx, material, handle_path, initial_positions, initial_velocities, scene, frames, optimizer, basis):
        settings = {name: float(value) for name, value in zip(COEFFICIENTS, material.detach().tolist())}
        recorded = record_rollout(
            scene.replace(**settings),
            optimizer=optimizer,
            initial_positions=initial_positions.detach().numpy(),
            initial_velocities=initial_velocities.detach().numpy(),
            handle_path=handle_path.detach().numpy(),
            path_basis=basis,
        )
        if recorded.diverged:
            raise ValueError("rollout: diverged")
        ctx.recorded, ctx.frames = recorded, list(frames)
        positions = recorded.positions[ctx.frames]
        return torch.from_numpy(np.ascontiguousarray(positions)).to(material.dtype)

    @staticmethod
    def backward(ctx, grad_output):
        upstream = grad_output.detach().to(torch.float64).numpy()
        dL_dX = {}
        for k, frame in enumerate(ctx.frames):
            dL_dX[frame] = dL_dX.get(frame, 0.0) + upstream[k]
        g = ctx.recorded.gradients(dL_dX)
        warn_unless_well_conditioned(g["verdict"])
        as_tensor = lambda a: torch.as_tensor(np.asarray(a), dtype=grad_output.dtype)
        return (
            as_tensor([g[name] for name in COEFFICIENTS]),
            as_tensor(g["handle_path"]),
            as_tensor(g["initial_positions"]),
            as_tensor(g["initial_velocities"]),
            None,
            None,
            None,
            None,
        )


class GradientWarning(UserWarning):
    """A rollout's gradient that holds only for small perturbations, or not at all (docs/design.md §15)."""


def warn_unless_well_conditioned(verdict):
    """Warns (GradientWarning) with the backward pass's verdict where it is not 'well-conditioned'."""
    if verdict["conditioning"] == "well-conditioned":
        return
    warnings.warn(
        "fnopt: rollout gradient %s: valid for start perturbations below %.3g m (a start perturbation grows "
        "%.3g-fold; the solves' residuals alone move it by %.1e)"
        % (verdict["conditioning"], verdict["start_radius"], verdict["growth"], verdict["precision"]),
        GradientWarning, stacklevel=2)


def rollout(scene, material, handle_path=None, initial_positions=None, initial_velocities=None, frames=None,
            optimizer="newton", path_basis="cubic-bspline", control_points=8):
    """The positions of a scene's frames, differentiable in its material, handle path and initial state.

    Parameters
    ----------
    scene : fnopt.Scene
        The scene, its frames included; its material is replaced by `material`.
    material : torch.Tensor
        (5,) float64: stretch, shear, bend, density, damping (`COEFFICIENTS`).
    handle_path : torch.Tensor, optional
        (handles, K, 3): control points of offsets added to the scene's handle motion; default zeros
        with K = `control_points`.
    initial_positions, initial_velocities : torch.Tensor, optional
        (rows, cols, 3); default the grid's rest positions and zero.
    frames : sequence of int, optional
        The frames returned, 0 the initial state; default every frame.
    optimizer : str, optional
        As for `fnopt.record_rollout`.
    path_basis : str, optional
        'cubic-bspline' or 'linear'.
    control_points : int, optional
        K of the default handle path.

    Returns
    -------
    torch.Tensor
        (len(frames), rows, cols, 3) positions.
    """
    dtype = material.dtype
    if handle_path is None or initial_positions is None or initial_velocities is None:
        # The defaults' shapes and the rest positions, from a one-step record of the same scene.
        rest = record_rollout(scene.replace(frames=1))
        rows, cols, handles = rest.rows, rest.cols, rest.handle_count
        if handle_path is None:
            handle_path = torch.zeros((handles, control_points, 3), dtype=dtype)
        if initial_positions is None:
            initial_positions = torch.as_tensor(rest.positions[0], dtype=dtype)
        if initial_velocities is None:
            initial_velocities = torch.zeros((rows, cols, 3), dtype=dtype)
    if frames is None:
        frames = range(scene.frames + 1)
    return RolloutFunction.apply(material, handle_path, initial_positions, initial_velocities, scene, tuple(frames),
                                 optimizer, path_basis)
