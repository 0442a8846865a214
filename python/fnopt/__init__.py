"""fnopt: cloth on regular grids, solved by classical and learned inner optimizers.

    import fnopt
    scene = fnopt.Scene(res=32, handles="corner", motion="xy_v2", frames=60)
    sim = fnopt.Simulator(scene, optimizer="pqn", iters=10)
    frames = sim.rollout(60)          # (61, 32, 32, 3)

Arrays are NumPy arrays shaped (rows, cols, 3) per frame; errors are fnopt.Error, a
ValueError, with the command line's texts. The whole surface is in docs/api.md.
"""
from ._fnopt import (
    Error,
    Rollout,
    Scene,
    Simulator,
    StepProblem,
    __version__,
    compare,
    compare_trajectories,
    evaluate_optimizer,
    optimizer_names,
    read_rollout,
    run_rollout,
    set_threads,
    shipped_model_path,
    multires_model_path,
    threads,
)

__all__ = [
    "Error",
    "Rollout",
    "Scene",
    "Simulator",
    "StepProblem",
    "compare",
    "compare_trajectories",
    "evaluate_optimizer",
    "optimizer_names",
    "read_rollout",
    "run_rollout",
    "set_threads",
    "shipped_model_path",
    "multires_model_path",
    "threads",
]
