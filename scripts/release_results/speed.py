"""Every method's cost (fnopt bench speed): pqn 10, fnopt 10 and Newton with 1 and 2 threads, each in a process of
its own, beside fnopt 1.0's figures; the bench's table as it printed it."""

import os
import re

from .assemble import section
from .files import write_csv
from .runner import PartFailed
from .tables import markdown_table

HEADER = ["grid", "method", "ms/frame, 1 thread", "2 threads", "2 threads' speed-up", "1.0 ms/frame", "vs 1.0",
          "evaluations / frame", "gradients / frame", "peak MB, 1 / 2 threads", "converged"]
ROW = re.compile(r"^\s*(\d+)\^2\s+(pqn \d+|fnopt \d+|newton)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)"
                 r"\s+(\S+)\s+(\S+)\s*$")


def merged_rows(text):
    """The bench's rows, one per grid and method: its 1-thread row with the 2-thread row's ms/frame, speed-up and
    peak memory beside."""
    rows, one = [], {}
    for m in (ROW.match(l) for l in text.splitlines()):
        if not m:
            continue
        grid, method, threads, ms, then, versus, two, evals, grads, peak, converged = m.groups()
        if threads == "1":
            one[(grid, method)] = (ms, then, versus, evals, grads, peak, converged)
        elif (grid, method) in one:
            ms1, then, versus, evals, grads, peak1, converged = one.pop((grid, method))
            rows.append([grid + "²", method, ms1, ms, two, then, versus, evals, grads, peak1 + " / " + peak,
                         converged])
    return rows


def part_speed(ctx, part, bench):
    """The section and speed.csv; with --resume a finished bench's output (bench.txt) is read again."""
    d = os.path.join(ctx.out, part)
    os.makedirs(d, exist_ok=True)
    args = ["bench", "speed", "--res", bench["res"], "--frames", str(bench["frames"])]
    text = ctx.run_kept(part, args, os.path.join(d, "bench.txt"))
    rows = merged_rows(text)
    if not rows:
        raise PartFailed("%s: no table in the bench's output (%s)" % (part, os.path.join(d, "bench.txt")))
    path = os.path.join(d, "speed.csv")
    write_csv(path, HEADER, rows)
    first = text.splitlines()[0] if text else ""
    return section("Every method's cost", [ctx.shown(args)],
                   first.rstrip(".") + ".\n\n" + markdown_table(HEADER, rows)), [path]
