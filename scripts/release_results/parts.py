"""The parts of a run in order, and the context each is called with: a part is a function
part_*(ctx, name, *plan) that returns (its section of results.md, the CSV files it wrote; None where it was
skipped)."""

import os
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait

from .adjoint import part_adjoint
from .arcsim import part_arcsim
from .contact import part_contact
from .files import write_atomic
from .frontier import part_frontier
from .newton_cost import part_newton_cost
from .offcorner import part_offcorner
from .paper import part_paper
from .plan import plan
from .runner import Runner, command_text
from .stability import part_stability
from .speed import part_speed
from .superres import part_superres


class Context:
    """What every part gets: the binary, --out and the options, the plan, and the runner of its fnopt runs."""

    def __init__(self, args):
        self.binary = os.path.abspath(args.binary)
        self.out = os.path.abspath(args.out)
        self.quick = args.quick
        self.resume = args.resume
        self.arcsim_dir = os.path.abspath(args.arcsim_dir) if args.arcsim_dir else None
        self.note = args.note
        self.jobs = args.jobs
        self.splice = os.path.abspath(args.splice) if args.splice else None
        self.plan = plan(args)
        self.runner = Runner(self.binary, self.out)

    def run(self, part, args):
        """Runs fnopt with args for part (Runner.run): its standard output; PartFailed when it fails."""
        return self.runner.run(part, args)

    def run_all(self, runs):
        """run() of each (part, args) of runs, --jobs at a time: their standard outputs in order. The first failure
        stops the runs not yet started and kills those running (as one run's failure stops a part), then raises."""
        if self.jobs == 1:
            return [self.run(part, args) for part, args in runs]
        with ThreadPoolExecutor(self.jobs) as pool:
            futures = [pool.submit(self.run, part, args) for part, args in runs]
            try:
                done, _ = wait(futures, return_when=FIRST_EXCEPTION)
                for f in done:
                    if f.exception() is not None:
                        raise f.exception()
                return [f.result() for f in futures]
            except BaseException:
                for f in futures:
                    f.cancel()
                self.runner.kill_all()
                raise

    def run_kept(self, part, args, stdout_path):
        """run(), its output kept in stdout_path; with --resume a finished run's file is read again instead of
        running it again (a bench's timings)."""
        if self.resume and os.path.exists(stdout_path):
            with open(stdout_path, encoding="utf-8") as f:
                return f.read()
        text = self.run(part, args)
        write_atomic(stdout_path, text)
        return text

    def rel(self, path):
        """path relative to --out, as the commands name it."""
        return self.runner.rel(path)

    def shown(self, args):
        """The fnopt command of args as results.md shows it."""
        return command_text([self.binary] + args)

    def out_flags(self, directory):
        """--out DIRECTORY for a compare or stability run, and --resume with --resume (it keeps their finished
        rows)."""
        return ["--out", self.rel(directory)] + (["--resume"] if self.resume else [])


class Part:
    """A part of the run: its name (for --only, state.json and the logs), its title, its function and the
    plan arguments the function gets after (ctx, name)."""

    def __init__(self, name, title, func, *fargs):
        self.name, self.title, self.func, self.fargs = name, title, func, fargs


def make_parts(ctx):
    """The run's parts in results.md's order, each with its plan."""
    p = ctx.plan
    parts = []
    for grid, motions, frames, budgets in p["frontier"]:
        parts.append(Part("frontier-%d" % grid, "frontier %d²" % grid, part_frontier, grid, motions, frames,
                          budgets))
    parts.append(Part("newton-cost", "Newton's cost", part_newton_cost, p["bench"]))
    parts.append(Part("speed", "every method's cost", part_speed, p["speed"]))
    parts.append(Part("superres", "super-resolution", part_superres, p["superres"]))
    for grid, presets, frames, n in p["offcorner"]:
        parts.append(Part("offcorner-%d" % grid, "off the corners %d²" % grid, part_offcorner, grid, presets,
                          frames, n))
    parts.append(Part("arcsim", "against ARCSim", part_arcsim, p["arcsim"]))
    parts.append(Part("stability", "stability", part_stability, p["stability"]))
    parts.append(Part("contact", "contact", part_contact, p["contact"]))
    parts.append(Part("adjoint", "the adjoint", part_adjoint, p["adjoint"]))
    parts.append(Part("paper", "the paper beside ours", part_paper))
    return parts
