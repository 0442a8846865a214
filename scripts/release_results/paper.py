"""The FNOPT paper's tables (scripts/data/paper-tables.csv) beside ours: no run of its own, it reads the ARCSim
part's means (ours are empty without --arcsim-dir) and says on each row what differs."""

import os

from . import REPOSITORY
from .assemble import section
from .files import read_csv, write_csv
from .tables import markdown_table

PAPER_CSV = os.path.join(REPOSITORY, "scripts", "data", "paper-tables.csv")
HEADER = ["paper table", "grid", "N", "paper e_CD × 10³", "ours e_CD × 10³: fnopt / fnopt-ss",
          "paper ms/frame (A100)", "ours ms/frame (CPU): fnopt / fnopt-ss", "what differs"]
# What differs at each grid besides what differs on every row (the note under the section's title).
DIFFERS = {"32": "the same fifteen motions", "64": "ours: 3 of the 15 motions (ARCSim's 64² runs)",
           "100": "ours: xy_v2 only (ARCSim's one 100² run); the paper's xy_v2 at N = 10: 4.2"}


def paper_figure(paper, table, quantity, method, grid, n):
    """The paper's mean ± sd of quantity for method at grid and N in table; "—" where the paper has none."""
    hit = [r for r in paper if (r["table"], r["quantity"], r["method"], r["resolution"], r["N"]) ==
           (table, quantity, method, grid, n)]
    return "%s ± %s" % (hit[0]["value"], hit[0]["sd"]) if hit else "—"


def our_figure(ours, grid, method, n, column):
    """Our arcsim.csv's column for method at grid and N; "—" where it did not run."""
    r = ours.get((grid, method, n))
    return r[column] if r else "—"


def comparison_rows(paper, ours):
    """Table 6.7's FNOPT rows at each grid and N against our fnopt and fnopt-ss, and table 6.3's L-BFGS row."""
    table = []
    for grid in ("32", "64", "100"):
        for n in ("5", "10", "20"):
            table.append(["6.7 (6.1 at N = 10)", grid + "²", n,
                          paper_figure(paper, "6.7", "e_CD x 1e3", "FNOPT", grid, n),
                          "%s / %s" % (our_figure(ours, grid, "fnopt", n, "e_CD × 10³ vs ARCSim"),
                                       our_figure(ours, grid, "fnopt-ss", n, "e_CD × 10³ vs ARCSim")),
                          paper_figure(paper, "6.7", "ms per frame (A100)", "FNOPT", grid, n),
                          "%s / %s" % (our_figure(ours, grid, "fnopt", n, "ms/frame (CPU)"),
                                       our_figure(ours, grid, "fnopt-ss", n, "ms/frame (CPU)")),
                          DIFFERS[grid]])
    table.append(["6.3, L-BFGS (step 1)", "100²", "120",
                  paper_figure(paper, "6.3", "e_CD x 1e3", "L-BFGS (step 1)", "100", "120"),
                  "lbfgs: %s" % our_figure(ours, "100", "lbfgs", "120", "e_CD × 10³ vs ARCSim"), "—",
                  "lbfgs: %s" % our_figure(ours, "100", "lbfgs", "120", "ms/frame (CPU)"),
                  "paper: L-BFGS with step 1; ours: lbfgs (fixed step 1, mass-metric start); ours: xy_v2 only"])
    return table


def part_paper(ctx, part):
    """The paper's figures (scripts/data/paper-tables.csv) beside ours, each row saying what differs."""
    paper = [r for r in read_csv(PAPER_CSV) if r["motion"] == "mean"]
    ours = {}
    arcsim_csv = os.path.join(ctx.out, "arcsim", "arcsim.csv")
    if os.path.exists(arcsim_csv):
        for r in read_csv(arcsim_csv):
            ours[(r["grid"].rstrip("²"), r["method"], r["N"])] = r
    table = comparison_rows(paper, ours)
    path = os.path.join(ctx.out, part, "paper.csv")
    write_csv(path, HEADER, table)
    note = ("The paper's figures are `scripts/data/paper-tables.csv` (the FNOPT thesis, chapter 6; means ± standard "
            "deviation over the fifteen motions, against the paper's ARCSim runs). Ours: the ARCSim part's means "
            "against ARCSim%s. What differs on every row: the paper runs its model per protocol on an A100 with the "
            "material held in grid units across resolutions; ours runs on one CPU thread with the physical material "
            "fitted to ARCSim; our fnopt is the FNO update with pqn's direction in its subspace (32² model), our "
            "fnopt-ss the paper's method on the multi-resolution model. The last column says what differs besides."
            "\n\n" % ("" if ours else " (not run: no `--arcsim-dir`, so our columns are empty)"))
    return section("The paper's tables beside ours", [], note + markdown_table(HEADER, table)), [path]
