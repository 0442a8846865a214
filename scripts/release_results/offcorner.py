"""The off-corner handle presets at one grid: each method's e_3D against the reference (newton, which can end at
a saddle of the step's energy) from fnopt compare --keep-rollouts, and against newton-min (which ends at a
minimum) from fnopt evaluate on the rollouts compare kept."""

import glob
import os
import re

from .assemble import section
from .compare import compare_rows
from .files import write_csv
from .runner import PartFailed
from .tables import fmt, fnum, markdown_table

EVAL_E3D = re.compile(r"e_3D x 10\^2 = ([0-9.eE+-]+)")
EVALUATE_COMMAND = "fnopt evaluate --reference ROLLOUT_OF_NEWTON_MIN ROLLOUT"


def kept_rollout(d, method, n, grid, motion):
    """The rollout of method (budget n; "" for its own) that compare --keep-rollouts kept in d; None if none."""
    budget = "_%s" % n if n else ""
    path = os.path.join(d, "rollout_%s%s_%s_%s.h5" % (method, budget, grid, motion))
    if os.path.exists(path):
        return path
    hits = glob.glob(os.path.join(d, "rollout_%s%s_%s*_%s.h5" % (method, budget, grid, motion)))
    return hits[0] if hits else None


def evaluate_e3d(ctx, label, reference, rollout):
    """e_3D × 10² of rollout against reference (fnopt evaluate, logged under label); None if it printed none."""
    args = ["evaluate", "--reference", ctx.rel(reference), ctx.rel(rollout)]
    if ctx.quick:
        args += ["--cd-samples", "2000"]
    m = EVAL_E3D.search(ctx.run(label, args))
    return fnum(m.group(1)) if m else None


def compare_args(ctx, d, grid, preset, frames, n):
    """The fnopt compare of one preset: newton-min and the part's methods at budget n, rollouts kept."""
    return (["compare", "--res", str(grid), "--handles", preset, "--motions", "xy_v2", "--frames", str(frames),
             "--optimizers", "newton-min," + ",".join(ctx.plan["offcorner_methods"]), "--iters", str(n),
             "--threads", "1", "--keep-rollouts"] + ctx.plan["compare_extra"] + ctx.out_flags(d))


def preset_row(ctx, part, preset, d, grid, n):
    """The table's row of a preset whose compare has run in d: newton against newton-min, then each method
    against newton (compare's e_3D) and against newton-min (fnopt evaluate on the kept rollouts)."""
    against_newton = {r["method"]: r for r in compare_rows(d)}
    newton_min = kept_rollout(d, "newton-min", "", grid, "xy_v2")
    refs = glob.glob(os.path.join(d, "newton_reference_*.h5"))
    if newton_min is None or not refs:
        raise PartFailed("%s: newton-min's rollout or the reference missing in %s" % (part, d))
    label = part + " " + preset
    line = [preset, fmt(evaluate_e3d(ctx, label + " newton", newton_min, refs[0]))]
    vs_min = []
    for m in ctx.plan["offcorner_methods"]:
        r = against_newton.get(m)
        line.append(fmt(fnum(r["e_3d_x1e2"])) if r and r["diverged"] == "no" else "—")
        rollout = kept_rollout(d, m, n, grid, "xy_v2")
        if rollout is None:
            raise PartFailed("%s: no kept rollout of %s in %s" % (part, m, d))
        vs_min.append(fmt(evaluate_e3d(ctx, label + " " + m, newton_min, rollout)))
    return line + vs_min


def part_offcorner(ctx, part, grid, presets, frames, n):
    """The off-corner table at grid, a row per preset: the section and offcorner.csv."""
    methods = ctx.plan["offcorner_methods"]
    header = ["preset", "newton vs newton-min"]
    header += ["vs newton: %s" % m for m in methods] + ["vs newton-min: %s" % m for m in methods]
    table = []
    for preset in presets:
        d = os.path.join(ctx.out, part, preset)
        ctx.run(part + " " + preset, compare_args(ctx, d, grid, preset, frames, n))
        table.append(preset_row(ctx, part, preset, d, grid, n))
    path = os.path.join(ctx.out, part, "offcorner.csv")
    write_csv(path, header, table)
    first = presets[0]
    commands = [ctx.shown(compare_args(ctx, os.path.join(ctx.out, part, first), grid, first, frames, n))
                .replace(first, "PRESET"), EVALUATE_COMMAND]
    body = ("e_3D × 10² over %d frames of xy_v2 at %d², N = %d, against the reference (newton, which can end "
            "at a saddle of the step's energy) and against newton-min (Newton that leaves saddles and ends at "
            "a minimum). The newton columns come from compare, the newton-min columns from `fnopt evaluate` "
            "on the rollouts compare kept.\n\n" % (frames, grid, n))
    return section("Off the corners at %d²" % grid, commands, body + markdown_table(header, table)), [path]
