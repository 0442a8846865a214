"""The records fnopt returns: small frozen dataclasses with named, read-only fields.

Each compares equal to another with the same values, and prints as its constructor call. The
extension module builds them (fnopt._fnopt); they are plain Python so that
dataclasses.asdict, dataclasses.replace and type checkers work on them as on any dataclass.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Dict, Optional, Tuple

import numpy as np

if TYPE_CHECKING:
    from ._fnopt import Scene

__all__ = ["CompareRow", "Comparison", "Evaluation", "Material", "RolloutFile", "SceneKey", "StepRecord"]


@dataclass(frozen=True)
class StepRecord:
    """One time step's record, as `fnopt simulate` logs it.

    Parameters
    ----------
    wall_ms : float
        Wall time of the step's inner solve in milliseconds.
    status : str
        How the solve ended: ``converged``, ``iteration-budget``, ``line-search-failed``,
        ``factorization-failed``, ``non-finite`` or ``precision-limit``.
    iterations : int
        Iterations the optimizer took.
    evaluations, gradient_evaluations : int
        The step objective's evaluations in the solve, and those of them with its gradient.
    initial_loss, loss : float
        The step's objective L(a) at the start a_0 and at the answer.
    initial_gradient_norm, gradient_norm : float
        The gradient's norm at a_0 and at the answer.
    max_strain : float
        The largest edge strain of the new frame (0.05 is 5 %).
    energy : float
        The cloth's kinetic and potential energy after the step, in joules.
    """

    wall_ms: float
    status: str
    iterations: int
    evaluations: int
    gradient_evaluations: int
    initial_loss: float
    loss: float
    initial_gradient_norm: float
    gradient_norm: float
    max_strain: float
    energy: float


@dataclass(frozen=True)
class Material:
    """A scene's resolved material, in SI units.

    Parameters
    ----------
    name : str
        The preset the values started from (``default``, ...).
    stretch, shear, bend : float
        The membrane's stretching and shearing stiffness and the bending stiffness.
    density : float
        Area density in kg/m^2.
    damping : float
        The damping coefficient.
    repulsion : bool
        Whether the cloth repels itself.
    repulsion_stiffness : float
        The self-repulsion's stiffness in N/m.
    repulsion_range : float
        Its range in rest edge lengths.
    """

    name: str
    stretch: float
    shear: float
    bend: float
    density: float
    damping: float
    repulsion: bool
    repulsion_stiffness: float
    repulsion_range: float


@dataclass(frozen=True)
class SceneKey:
    """One keyword of `Scene` (`scene_keys`): the same setting as a scene file's key and a flag.

    Parameters
    ----------
    name : str
        The scene file's key and the command line's flag (``--name``).
    keyword : str
        The keyword of `Scene` (``handle_vertices``, ``obstacles``).
    type : str
        ``int``, ``float``, ``str``, ``x,y,z``, ``auto|true|false`` or ``obstacle specs``.
    unit : str
        The SI unit, empty if none.
    default : str
        The default as the command line's help says it.
    help : str
        What the setting does.
    example : str
        A valid value, as a scene file writes it.
    """

    name: str
    keyword: str
    type: str
    unit: str
    default: str
    help: str
    example: str


@dataclass(frozen=True)
class Comparison:
    """A rollout measured against a reference trajectory (`compare_trajectories`).

    Parameters
    ----------
    e_cd : float
        e_CD x 10^3: the Chamfer distance in m^2, averaged over the matched frames.
    e_3d : float
        e_3D x 10^2: ||X - X_ref|| / ||X_ref|| averaged over the matched frames (NaN for
        different grids).
    max_strain : float
        The rollout's largest edge strain over all frames.
    matched : str
        How the two trajectories' frames and grids were matched.
    """

    e_cd: float
    e_3d: float
    max_strain: float
    matched: str


@dataclass(frozen=True)
class Evaluation:
    """`fnopt compare`'s measurement of one optimizer on one scene (`evaluate_optimizer`).

    Parameters
    ----------
    optimizer : str
        The optimizer's settings, as the rollout file stores them.
    iters : int
        Its budget per step.
    ms_per_frame : float
        Mean wall time of a step after warm-up.
    e_cd, e_3d : float
        e_CD x 10^3 and e_3D x 10^2 against the Newton reference; NaN if the run diverged.
    step_error_mean, step_error_median : float
        The per-step error over the sampled reference states.
    step_errors : tuple of float
        The per-step error of each sampled state.
    max_strain : float
        The rollout's largest edge strain.
    frames : int
        The frames the rollout ran (fewer than the scene's if it diverged).
    diverged : bool
        Whether the rollout diverged.
    divergence : str
        Why it diverged, empty if it did not.
    """

    optimizer: str
    iters: int
    ms_per_frame: float
    e_cd: float
    e_3d: float
    step_error_mean: float
    step_error_median: float
    step_errors: Tuple[float, ...]
    max_strain: float
    frames: int
    diverged: bool
    divergence: str


# One NaN object for every empty cell, so that rows with the same empty cells compare equal
# (a tuple's comparison takes an object as equal to itself).
_EMPTY = float("nan")


def _number(text: str) -> float:
    return float(text) if text else _EMPTY


@dataclass(frozen=True)
class CompareRow:
    """One run of `compare`: a row of compare.csv, its fields the file's columns.

    Numbers are floats as the file rounds them (NaN where a cell is empty: a diverged run's
    errors, a learning rate a method does not take).

    Parameters
    ----------
    method : str
        The optimizer.
    N : str
        Its budget per step, or ``converged`` for Newton.
    lr : float
        The learning rate, for methods that take one.
    lr_source : str
        Where the learning rate came from.
    resolution, motion : str
        The scene (``32x32``, ``xy_v2``).
    frames : str
        Frames finished of those requested, ``390/390``.
    threads : int
        The thread count of the timing.
    ms_per_frame, cpu_share, ms_per_frame_cpu, iterations_per_frame : float
        Wall time per frame, the share of it on the CPU, their product, iterations per frame.
    e_cd_x1e3, e_3d_x1e2 : float
        e_CD x 10^3 and e_3D x 10^2 against the Newton reference.
    step_error_mean, step_error_median : float
        The per-step error.
    max_strain_pct : float
        The largest edge strain in percent.
    min_obstacle_distance_m : float
        The smallest cloth-obstacle distance over the rollout in metres; NaN without obstacles.
    min_cloth_distance_m : float
        On a contact scene (obstacles or self-contact), the smallest distance between cloth primitives
        that share no vertex, in metres; NaN elsewhere.
    self_intersections, mesh_intersections : float
        On a contact scene, the exact crossings of the stored frames, summed (mesh: with a mesh
        obstacle); NaN where not measured.
    diverged : str
        ``no``, ``yes``, or ``error`` for a run that failed.
    frontier : bool
        On the error-time frontier of its scene.
    e_cd_arcsim_x1e3 : float
        e_CD x 10^3 against ARCSim, where a file was given.
    note : str
        Anything the run adds.
    """

    method: str
    N: str
    lr: float
    lr_source: str
    resolution: str
    motion: str
    frames: str
    threads: int
    ms_per_frame: float
    cpu_share: float
    ms_per_frame_cpu: float
    iterations_per_frame: float
    e_cd_x1e3: float
    e_3d_x1e2: float
    step_error_mean: float
    step_error_median: float
    max_strain_pct: float
    min_obstacle_distance_m: float
    min_cloth_distance_m: float
    self_intersections: float
    mesh_intersections: float
    diverged: str
    frontier: bool
    e_cd_arcsim_x1e3: float
    note: str

    @classmethod
    def from_cells(cls, cells: Dict[str, str]) -> "CompareRow":
        """The record of a compare.csv row.

        Parameters
        ----------
        cells : dict of str to str
            Column name to cell text, every column of the record.

        Returns
        -------
        CompareRow
            The row with its numbers parsed.
        """
        values = {}
        for field in dataclasses.fields(cls):
            text = cells[field.name]
            if field.type == "float":
                values[field.name] = _number(text)
            elif field.type == "int":
                values[field.name] = int(text)
            elif field.type == "bool":
                values[field.name] = text == "yes"
            else:
                values[field.name] = text
        return cls(**values)


@dataclass(frozen=True, eq=False)
class RolloutFile:
    """A rollout file's contents (`read_rollout`): fnopt's, or an ARCSim reference.

    Two are equal when every field is, arrays element by element.

    Parameters
    ----------
    positions : numpy.ndarray
        (frames, rows, cols, 3) float32 positions, frame 0 the rest state.
    times : numpy.ndarray
        (frames,) times in seconds.
    rows, cols : int
        The grid.
    scene : Scene or None
        The scene it was run on; None for an ARCSim file.
    optimizer : str or None
        The optimizer's settings; None for an ARCSim file.
    version : str or None
        The fnopt version that wrote it; None for an ARCSim file.
    divergence : str or None
        Why the rollout diverged, empty if it did not; None for an ARCSim file.
    """

    positions: np.ndarray
    times: np.ndarray
    rows: int
    cols: int
    scene: Optional["Scene"]
    optimizer: Optional[str]
    version: Optional[str]
    divergence: Optional[str]

    def __eq__(self, other: object) -> bool:
        """Field-by-field equality, arrays compared element by element.

        Parameters
        ----------
        other : object
            Another record.

        Returns
        -------
        bool
            True if `other` is a RolloutFile with equal fields.
        """
        if not isinstance(other, RolloutFile):
            return NotImplemented
        for field in dataclasses.fields(self):
            mine, theirs = getattr(self, field.name), getattr(other, field.name)
            if isinstance(mine, np.ndarray):
                if not np.array_equal(mine, theirs):
                    return False
            elif mine != theirs:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]
