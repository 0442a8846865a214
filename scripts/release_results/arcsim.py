"""Against ARCSim (fnopt compare --arcsim-dir): means over the motions ARCSim has at each grid, e_CD against
ARCSim and against Newton. Skipped, with a note in its section, without --arcsim-dir (the ARCSim runs are not
in the repository)."""

import glob
import os

from .assemble import section
from .compare import budget_flags, compare_rows, method_groups
from .files import write_csv
from .tables import markdown_table, max_cell, mean_cell

TITLE = "Against ARCSim"
HEADER = ["grid", "motions", "method", "N", "e_CD × 10³ vs ARCSim", "e_CD × 10³ vs Newton", "ms/frame (CPU)",
          "max strain %", "diverged"]


def link_frontier_references(ctx, grid, d):
    """The frontier part's Newton references are this part's too (same scene): linked into d, not solved
    again. Where a link cannot be made, compare solves the reference itself."""
    for ref in glob.glob(os.path.join(ctx.out, "frontier-%d" % grid, "newton_reference_*.h5")):
        target = os.path.join(d, os.path.basename(ref))
        if not os.path.exists(target):
            try:
                os.link(ref, target)
            except OSError:
                pass


def grid_rows(grid, rows):
    """The table's rows of one grid's compare.csv: a row per (method, N), means over its motions."""
    n_motions = len(set(r["motion"] for r in rows))
    return [["%d²" % grid, str(n_motions), method, n or "converged",
             mean_cell(finished, "e_cd_arcsim_x1e3"),
             mean_cell(finished, "e_cd_x1e3"),
             mean_cell(runs, "ms_per_frame_cpu"),
             max_cell(runs, "max_strain_pct"),
             "%d/%d" % (len(runs) - len(finished), len(runs))]
            for method, n, runs, finished in method_groups(rows)]


def part_arcsim(ctx, part, runs):
    """The ARCSim table over runs (grid, motions, frames, budgets): the section and arcsim.csv; the section
    alone (files None: skipped) without --arcsim-dir."""
    if not ctx.arcsim_dir:
        print("note: part arcsim skipped: no --arcsim-dir (the ARCSim runs are not in the repository)", flush=True)
        return section(TITLE, [], "Skipped: no `--arcsim-dir` given (the ARCSim runs are not in the "
                                  "repository).\n"), None
    table, commands = [], []
    for grid, motions, frames, budgets in runs:
        d = os.path.join(ctx.out, part, str(grid))
        os.makedirs(d, exist_ok=True)
        link_frontier_references(ctx, grid, d)
        args = (["compare", "--res", str(grid), "--motions", motions, "--frames", str(frames)] +
                budget_flags(budgets) + ["--threads", "1", "--arcsim-dir", ctx.arcsim_dir] +
                ctx.plan["compare_extra"] + ctx.out_flags(d))
        commands.append(ctx.shown(args).replace(ctx.arcsim_dir, "ARCSIM_DIR"))
        ctx.run(part, args)
        table += grid_rows(grid, compare_rows(d))
    path = os.path.join(ctx.out, part, "arcsim.csv")
    write_csv(path, HEADER, table)
    body = ("Means over the motions ARCSim has at each grid (32²: the fifteen; 64²: xy_v2, rot_h0, xyz_v3; "
            "100²: xy_v2), e_CD against ARCSim at its stored frames (every 1/30 s).\n\n")
    return section(TITLE, commands, body + markdown_table(HEADER, table)), [path]
