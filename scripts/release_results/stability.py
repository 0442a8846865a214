"""The stability suite (fnopt stability): one row per method over the stiff and extreme cases, summarising the
suite's own stability.csv."""

import os

from .assemble import section
from .files import read_csv, write_csv
from .runner import PartFailed
from .tables import fmt, fnum, markdown_table, unique

HEADER = ["method", "N", "finished", "diverged on", "worst e_3D × 10² (case)", "largest energy growth (case)",
          "unconverged steps"]


def method_row(method, rows):
    """A method's summary over its rows of stability.csv: cases finished and diverged, the worst e_3D and
    energy growth with their case, the unconverged steps."""
    mine = [r for r in rows if r["method"] == method]
    fin = [r for r in mine if r["outcome"] == "finished"]
    div = ["%s (step %s)" % (r["case"], r["diverged_step"]) for r in mine if r["outcome"] == "diverged"]
    worst = max(fin, key=lambda r: fnum(r["e_3d_x1e2"]) or 0.0, default=None)
    growth = max(fin, key=lambda r: fnum(r["energy_growth"]) or 0.0, default=None)
    uncon = sum(int(r["unconverged_steps"] or 0) for r in mine)
    return [method, mine[0]["N"], "%d/%d" % (len(fin), len(mine)), ", ".join(div) or "none",
            "%s (%s)" % (fmt(fnum(worst["e_3d_x1e2"])), worst["case"]) if worst else "—",
            "%s (%s)" % (fmt(fnum(growth["energy_growth"])), growth["case"]) if growth else "—",
            str(uncon)]


def part_stability(ctx, part, st):
    """The stability summary: the section and stability-summary.csv."""
    d = os.path.join(ctx.out, part)
    args = ["stability", "--cases", st["cases"], "--optimizers", st["optimizers"], "--threads", "1"]
    if st["frames"]:
        args += ["--frames", str(st["frames"])]
    args += ctx.out_flags(d)
    ctx.run(part, args)
    path = os.path.join(d, "stability.csv")
    if not os.path.exists(path):
        raise PartFailed("%s: no stability.csv" % part)
    rows = read_csv(path)
    table = [method_row(m, rows) for m in unique(r["method"] for r in rows)]
    out_path = os.path.join(d, "stability-summary.csv")
    write_csv(out_path, HEADER, table)
    body = ("One row per method over the cases (`fnopt stability --list-cases`); e_3D against Newton on the same "
            "case; energy growth is the largest total energy over the first; every case and method: "
            "`stability/stability.csv` and `stability/report.md`.\n\n")
    return section("Stability", [ctx.shown(args)], body + markdown_table(HEADER, table)), [out_path]
