"""The Newton reference's cost (fnopt bench newton --repeat N): the bench's table as it printed it, its columns
named as it names them."""

import os

from .assemble import section
from .files import write_csv
from .runner import PartFailed
from .tables import bench_table, markdown_table

# Column names the bench prints as two words.
TWO_WORD_COLUMNS = {("max", "ms"), ("max", "it"), ("cg", "it/st"), ("neg", "curv")}


def column_names(header_line):
    """The bench's header line as column names, its two-word columns joined; the first column is "grid"."""
    names = header_line.split()
    header = []
    skip = False
    for i, w in enumerate(names):
        if skip:
            skip = False
            continue
        if i + 1 < len(names) and (w, names[i + 1]) in TWO_WORD_COLUMNS:
            header.append(w + " " + names[i + 1])
            skip = True
        else:
            header.append(w)
    header[0] = "grid"
    return header


def part_newton_cost(ctx, part, bench):
    """The Newton reference's cost per grid: the section and newton-cost.csv. With --resume, a finished bench's
    output (bench.txt) is read again instead of timing it again."""
    d = os.path.join(ctx.out, part)
    args = ["bench", "newton", "--res", bench["res"], "--frames", str(bench["frames"]), "--threads", "1",
            "--repeat", str(bench["repeat"])]
    stdout_path = os.path.join(d, "bench.txt")
    text = ctx.run_kept(part, args, stdout_path)
    header_line, rows = bench_table(text)
    if header_line is None or not rows:
        raise PartFailed("%s: no table in the bench's output (%s)" % (part, stdout_path))
    header = column_names(header_line)
    rows = [r[:len(header)] for r in rows]
    write_csv(os.path.join(d, "newton-cost.csv"), header, rows)
    first = text.splitlines()[0] if text else ""
    body = ("%s. Columns: ms/frame (median of the runs) and its range, the slowest step, Newton iterations per "
            "step and the most in one step, factorisations and CG products per step, the share of iterations "
            "with negative curvature, rejected trials per step, steps converged.\n\n" % first.rstrip("."))
    return section("The Newton reference's cost", [ctx.shown(args)],
                   body + markdown_table(header, rows)), [os.path.join(d, "newton-cost.csv")]
