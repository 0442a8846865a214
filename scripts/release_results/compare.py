"""fnopt compare, as the parts that run it share it: the flags of a budget plan, the rows of compare.csv, the
runs grouped by method and budget, and the frontier table's summary of them."""

import os

from .files import read_csv
from .runner import PartFailed
from .tables import max_cell, mean_cell, unique


def budget_flags(budgets):
    """--optimizers and --iters-for of a {method: [N, ...]} plan ([] = the method's own budget)."""
    flags = ["--optimizers", ",".join(budgets)]
    for method, ns in budgets.items():
        if ns:
            flags += ["--iters-for", "%s=%s" % (method, ",".join(str(n) for n in ns))]
    return flags


def compare_rows(directory):
    """The rows of the compare.csv fnopt compare wrote in directory; PartFailed when there is none."""
    path = os.path.join(directory, "compare.csv")
    if not os.path.exists(path):
        raise PartFailed("%s: no compare.csv" % directory)
    return read_csv(path)


def method_order(rows):
    """The (method, N) pairs of the rows, in the order compare ran them."""
    return unique((r["method"], r["N"]) for r in rows)


def method_groups(rows):
    """(method, N, its runs, the runs that did not diverge) for each (method, N) of the rows, in order: the
    rows of the tables that average over motions."""
    for method, n in method_order(rows):
        runs = [r for r in rows if r["method"] == method and r["N"] == n]
        yield method, n, runs, [r for r in runs if r["diverged"] == "no"]


def summarise_compare(rows):
    """Means over the motions per (method, N): the frontier table's header and rows."""
    header = ["method", "N", "ms/frame (CPU)", "e_CD × 10³", "e_3D × 10²", "per-step error (median)",
              "max strain %", "diverged", "on the frontier"]
    table = []
    for method, n, runs, finished in method_groups(rows):
        table.append([method, n or "converged",
                      mean_cell(runs, "ms_per_frame_cpu"),
                      mean_cell(finished, "e_cd_x1e3"),
                      mean_cell(finished, "e_3d_x1e2"),
                      mean_cell(finished, "step_error_median"),
                      max_cell(runs, "max_strain_pct"),
                      "%d/%d" % (sum(r["diverged"] != "no" for r in runs), len(runs)),
                      "%d/%d" % (sum(r["frontier"] == "yes" for r in runs), len(runs))])
    return header, table
