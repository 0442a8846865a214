"""fnopt: cloth on regular grids, solved by classical and learned inner optimizers.

    import fnopt
    scene = fnopt.Scene(res=32, handles="corner", motion="xy_v2", frames=60)
    sim = fnopt.Simulator(scene, optimizer="pqn", iters=10)
    frames = sim.rollout(60)          # (61, 32, 32, 3)
    sim.last_step                     # StepRecord(wall_ms=..., status='iteration-budget', ...)

Arrays are NumPy arrays shaped (rows, cols, 3) per frame; records (StepRecord, Evaluation, ...)
are frozen dataclasses; errors are fnopt.Error, a ValueError, with the command line's texts.
Gradients through rollouts: fnopt.record_rollout and RecordedRollout.gradients (e_CD as a loss:
RecordedRollout.chamfer_loss against fnopt.sample_surface of observed meshes), and the PyTorch
bridge fnopt.torch (imported on its own: it imports torch). The whole surface is in docs/api.md.
"""
from ._fnopt import (
    Error,
    RecordedRollout,
    Rollout,
    Scene,
    Simulator,
    StepProblem,
    __version__,
    compare,
    compare_trajectories,
    evaluate_optimizer,
    multires_model_path,
    optimizer_names,
    read_rollout,
    record_rollout,
    run_rollout,
    sample_surface,
    scene_keys,
    set_threads,
    shipped_model_path,
    threads,
)
from .records import CompareRow, Comparison, Evaluation, Material, RolloutFile, SceneKey, StepRecord

__all__ = [
    "CompareRow",
    "Comparison",
    "Error",
    "Evaluation",
    "Material",
    "RecordedRollout",
    "Rollout",
    "RolloutFile",
    "Scene",
    "SceneKey",
    "Simulator",
    "StepProblem",
    "StepRecord",
    "compare",
    "compare_trajectories",
    "evaluate_optimizer",
    "multires_model_path",
    "optimizer_names",
    "read_rollout",
    "record_rollout",
    "run_rollout",
    "sample_surface",
    "scene_keys",
    "set_threads",
    "shipped_model_path",
    "threads",
]
