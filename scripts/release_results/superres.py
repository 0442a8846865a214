"""Zero-shot super-resolution (fnopt compare --preset superres, up to 200²): a grid per row, a method per column,
each cell e_CD against the grid's own Newton reference and CPU ms/frame; its chart is copied beside results.md."""

import os

from .assemble import publish_picture, section
from .compare import compare_rows, method_order
from .files import write_csv
from .tables import fmt, fnum, markdown_table, unique


def superres_cell(rows, grid, method, n):
    """The cell of a grid and a (method, N): "e_CD, ms/frame ms", "diverged, ..." or "—" where it did not run."""
    hit = [r for r in rows if r["resolution"] == grid and r["method"] == method and r["N"] == n]
    if not hit:
        return "—"
    r = hit[0]
    e = "diverged" if r["diverged"] != "no" else fmt(fnum(r["e_cd_x1e3"]), 2)
    return "%s, %s ms" % (e, fmt(fnum(r["ms_per_frame_cpu"]), 3))


def part_superres(ctx, part, sr):
    """The super-resolution table: the section and superres.csv."""
    d = os.path.join(ctx.out, part)
    args = ["compare", "--preset", "superres", "--res", sr["res"], "--threads", "1"]
    if sr["frames"]:
        args += ["--frames", str(sr["frames"])]
    if sr["step_samples"]:
        args += ["--step-samples", str(sr["step_samples"])]
    if ctx.quick:
        args += ["--cd-samples", "2000"]
    args += ctx.out_flags(d)
    ctx.run(part, args)
    rows = compare_rows(d)
    methods = method_order(rows)
    header = ["grid"] + ["%s%s" % (m, " (N = %s)" % n if n and n != "10" else "") for m, n in methods]
    table = [[g if "x" in g else g + "²"] + [superres_cell(rows, g, m, n) for m, n in methods]
             for g in unique(r["resolution"] for r in rows)]
    write_csv(os.path.join(d, "superres.csv"), header, table)
    body = ("e_CD × 10³ against each grid's own Newton reference, and CPU ms/frame; N = 10 unless the column "
            "says; METHOD-interp32 solves on the grid with 32 vertices along the longer edge and prolongs "
            "bilinearly. Per-step errors, max strain: `superres/compare.csv`.\n\n")
    chart = publish_picture(ctx, os.path.join(d, "superres.svg"), "superres.svg",
                            "e_CD against the grid, one line per method")
    return section("Zero-shot super-resolution", [ctx.shown(args)],
                   body + markdown_table(header, table) + chart), [os.path.join(d, "superres.csv")]
