"""The frontier part: every current method and budget at one grid (fnopt compare), means over the motions, and
which runs are on the error-time frontier; its chart is copied beside results.md."""

import os

from .assemble import publish_picture, section
from .compare import budget_flags, compare_rows, summarise_compare
from .files import write_csv
from .plan import EVAL
from .tables import markdown_table


def part_frontier(ctx, part, grid, motions, frames, budgets):
    """The error-time frontier at grid: the section and frontier.csv."""
    d = os.path.join(ctx.out, part)
    args = (["compare", "--res", str(grid), "--motions", motions, "--frames", str(frames)] +
            budget_flags(budgets) + ["--threads", "1"] + ctx.plan["compare_extra"] + ctx.out_flags(d))
    ctx.run(part, args)
    rows = compare_rows(d)
    header, table = summarise_compare(rows)
    write_csv(os.path.join(d, "frontier.csv"), header, table)
    n_motions = len(set(r["motion"] for r in rows))
    body = ("Means over the %d motion%s (%s), %d frames, one thread; errors against the converged Newton "
            "reference; ms/frame is CPU time (wall × the CPU share); \"on the frontier\": motions where no "
            "other run is at most as slow and at most as far (compare.csv, column frontier).\n\n"
            % (n_motions, "" if n_motions == 1 else "s",
               "the evaluation motions" if motions == EVAL else motions.replace(",", ", "), frames))
    chart = publish_picture(ctx, os.path.join(d, "compare.svg"), "%s.svg" % part,
                            "e_CD against CPU ms/frame at %d², one line per method through its budgets" % grid)
    return section("The error–time frontier at %d²" % grid, [ctx.shown(args)],
                   body + markdown_table(header, table) + chart), [os.path.join(d, "frontier.csv")]
