#!/usr/bin/python3
"""Regenerate the release's result tables (docs/results.md) from a built fnopt.

Runs every measurement the release reports, one part at a time, and writes each part's
outputs (the fnopt run's directory, a CSV of its table, a report section) under --out, then
assembles OUT/results.md: the current tables only, each headed by the exact command that made it.

Parts, in order:
  frontier-R   the error-time frontier at R^2 (fnopt compare, every current method and budget)
  newton-cost  the Newton reference's cost (fnopt bench newton --repeat N)
  superres     zero-shot super-resolution up to 200^2 (fnopt compare --preset superres)
  offcorner-R  the off-corner handle presets, against newton and against newton-min
               (fnopt compare --keep-rollouts, then fnopt evaluate against newton-min's rollout)
  arcsim       against ARCSim (fnopt compare --arcsim-dir; skipped without --arcsim-dir)
  stability    the stability suite's summary (fnopt stability)
  contact      every method on the contact scenes of examples/scenes (fnopt compare --scene), and far
               obstacles' cost (fnopt bench contact)
  adjoint      gradients through rollouts: fnopt gradcheck (plain and with an obstacle), fnopt bench adjoint,
               fnopt fit-handles, and with --arcsim-dir fnopt fit-material by gradient and by compass
  paper        the FNOPT paper's tables beside ours (scripts/data/paper-tables.csv; no run)

--quick is a smoke pass for CI (tiny grids, a few frames, a couple of methods, every part
exercised: a minute or two on 2 cores). The full run takes many hours on one thread per run;
--resume keeps the parts already finished and passes --resume to compare and stability, which
keep their finished rows. A line per part says what is done and left, with the run's ETA; under it, the part's
fnopt runs print their progress (a line per 10 %, with their own ETA); OUT/logs/ has their whole output. A part
that fails stops the run: exit status 1 and one line naming it.

Python 3 standard library only.
"""

import argparse
import csv
import glob
import io
import json
import os
import re
import shlex
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.normpath(os.path.join(HERE, "..", "examples", "scenes"))
CONTACT_SCENES = [("drape", 120), ("table", 120), ("pushed-sphere", 150), ("tilted-plane", 120)]
# design.md §7's fit: the start the fit-material comparison begins from (stretch, shear, damping far off).
FIT_START = "stretch = 300\nshear = 3\nbend = 2e-5\ndensity = 0.187\ndamping = 1\n"
GRADCHECK_OBSTACLE = "sphere center=0.5,0.12,-0.6 radius=0.1 friction=0.3"
PAPER_CSV = os.path.join(HERE, "data", "paper-tables.csv")

EVAL = "eval"  # compare's name for the fifteen evaluation motions
OFF_CORNER_PRESETS = ["diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center"]


class PartFailed(Exception):
    """A part's command failed or its output is missing; the message names the part."""


# ---------------------------------------------------------------------------------------------
# The plans: what each part runs, in full and in --quick.


def frontier_runs(quick):
    """(grid, motions, frames, optimizers, budgets per method) of each frontier part."""
    if quick:
        budgets = {"fnopt": [2], "pqn": [2, 5], "newton": [2]}
        return [(12, "xy_v2,rot_h0", 3, budgets), (16, "xy_v2,rot_h0", 3, budgets)]
    budgets = {
        "fnopt": [10, 20],
        "fnopt-ss": [10, 20],
        "pqn": [5, 10, 20, 40],
        "implicit-euler": [],
        "newton": [2, 3, 5],
        "lbfgs": [120],
        "lbfgs-ls": [120],
    }
    three = "xy_v2,rot_h0,xyz_v3"
    return [(32, EVAL, 390, budgets), (64, three, 390, budgets), (100, three, 390, budgets)]


def plan(args):
    quick = args.quick
    p = {"quick": quick}
    p["frontier"] = frontier_runs(quick)
    p["bench"] = {"res": "12,16" if quick else "32,64,100", "frames": 3 if quick else 390,
                  "repeat": 2 if quick else args.repeat}
    # The preset's own grids and methods, with 200^2 added; --quick: one grid finer than 32.
    p["superres"] = ({"res": "40", "frames": 2, "step_samples": 1} if quick else
                     {"res": "32x64,64x32,48,48x80,64,100,128,200", "frames": None, "step_samples": None})
    p["offcorner"] = ([(12, ["diagonal", "mid-edge"], 3, 2)] if quick else
                      [(32, OFF_CORNER_PRESETS, 150, 10), (64, OFF_CORNER_PRESETS, 150, 10)])
    p["offcorner_methods"] = ["pqn", "fnopt"] if quick else ["pqn", "fnopt", "fnopt-ss"]
    # ARCSim has every 32^2 motion, and xy_v2, xyz_v3, rot_h0 at 64^2, xy_v2 at 100^2.
    p["arcsim"] = ([(32, "xy_v2", 4, {"pqn": [2], "fnopt": [2]})] if quick else
                   [(32, EVAL, 390, {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10], "newton": []}),
                    (64, "xy_v2,rot_h0,xyz_v3", 390,
                     {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10], "newton": []}),
                    (100, "xy_v2", 390, {"fnopt": [5, 10, 20], "fnopt-ss": [5, 10, 20], "pqn": [10],
                                         "lbfgs": [120], "newton": []})])
    p["stability"] = ({"cases": "baseline,stretch-x100", "frames": 3, "optimizers": "pqn,fnopt"} if quick else
                      {"cases": "all", "frames": None,
                       "optimizers": "newton,pqn,fnopt,fnopt-ss,implicit-euler,lbfgs,lbfgs-ls"})
    p["contact"] = ({"res": "12", "scenes": [(name, 4) for name, _ in CONTACT_SCENES],
                     "budgets": {"newton": [], "pqn": [2]}, "bench": ["--res", "12", "--frames", "3"]} if quick else
                    {"res": "32,64,100", "scenes": CONTACT_SCENES,
                     "budgets": {"newton": [], "pqn": [10], "fnopt": [10], "fnopt-ss": [10], "implicit-euler": [],
                                 "lbfgs": [100], "lbfgs-ls": [100], "adam": [500], "gd": [500]},
                     "bench": ["--res", "32,64,100", "--frames", "60", "--repeat", "4"]})
    p["adjoint"] = ({"gradcheck": ["--res", "6", "--frames", "8"], "contact_gradcheck": ["--res", "6", "--frames", "8"],
                     "bench": ["--res", "8", "--frames", "3"],
                     "fit_handles": ["--res", "6", "--frames", "12", "--passes", "8"], "passes": [2, 4, 8],
                     "fit_material": None} if quick else
                    {"gradcheck": [], "contact_gradcheck": ["--res", "8", "--frames", "30"],
                     "bench": ["--res", "32,64,100", "--frames", "390"],
                     "fit_handles": ["--passes", "100"], "passes": [10, 20, 40, 60, 100],
                     "fit_material": ["--frames", "210", "--cd-samples", "4000", "--cd-stride", "4"]})
    # Rough seconds per part on one idle core, for the ETA only (scaled by how the finished parts went).
    p["estimate_s"] = ({"frontier-12": 15, "frontier-16": 20, "newton-cost": 3, "superres": 20, "offcorner-12": 20,
                        "arcsim": 10, "stability": 10, "contact": 10, "adjoint": 10, "paper": 0} if quick else
                       {"frontier-32": 9000, "frontier-64": 14400, "frontier-100": 36000,
                        "newton-cost": 1500 * args.repeat, "superres": 10800, "offcorner-32": 3600,
                        "offcorner-64": 24000, "arcsim": 12000, "stability": 3600, "contact": 14400,
                        "adjoint": 7200, "paper": 0})
    # Fewer samples where the grids are tiny: the per-step error's reference states, e_CD's points.
    p["compare_extra"] = ["--step-samples", "2", "--cd-samples", "2000"] if quick else []
    return p


# ---------------------------------------------------------------------------------------------
# Files and commands.


def write_atomic(path, text):
    """Write text to path through a temporary file in the same directory and a rename."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=directory, prefix="." + os.path.basename(path) + ".")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_csv(path, header, rows):
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    write_atomic(path, out.getvalue())


def publish_picture(ctx, source, name, alt):
    """Copies a chart a run wrote to OUT/name (beside results.md, so that results.md and its pictures move to
    docs/ together) and returns the markdown that shows it; "" when the run wrote none."""
    if not os.path.exists(source):
        return ""
    with open(source, encoding="utf-8") as f:
        write_atomic(os.path.join(ctx.out, name), f.read())
    return "\n\n![%s](%s)" % (alt, name)


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def command_text(cmd):
    """The command as docs show it: 'fnopt ...' with the output directory relative to --out (and without
    --resume, which changes what is run, not what is measured)."""
    return " ".join(shlex.quote(c) for c in ["fnopt"] + [c for c in cmd[1:] if c != "--resume"])


def run_capture(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    return r.stdout


# fnopt's progress bar in a log (util/progress_bar.hpp): "LABEL 3/10  30% elapsed 1m05s ETA 2m31s ...".
PROGRESS_LINE = re.compile(r" \d+/\d+ +\d+% elapsed \S+ ETA ")


class Runner:
    """Runs fnopt commands for one part, their output in the part's log files."""

    def __init__(self, binary, out):
        self.binary = binary
        self.out = out

    def run(self, part, args):
        """Runs fnopt with args in --out (the paths in args are relative to it); its output is logged in
        OUT/logs/PART.txt. Returns its standard output; raises PartFailed when it fails."""
        cmd = [self.binary] + args
        log = os.path.join(self.out, "logs", re.sub(r"[^A-Za-z0-9_.-]+", "_", part) + ".txt")
        os.makedirs(os.path.dirname(log), exist_ok=True)
        with open(log, "a", encoding="utf-8") as f:
            f.write("$ " + command_text(cmd) + "\n")
            f.flush()
            stdout, returncode = self._run_logged(part, cmd, f)
            f.write(stdout)
        if returncode != 0:
            with open(log, encoding="utf-8", errors="replace") as f:
                lines = [l.strip() for l in f.read().replace("\r", "\n").splitlines()
                         if l.strip() and not l.startswith("$ ")]
            raise PartFailed("'%s' exited with %d (%s; log %s)" %
                             (command_text(cmd), returncode, lines[-1] if lines else "no output", log))
        return stdout

    def _run_logged(self, part, cmd, log):
        """Runs cmd with its standard error into the log, echoing fnopt's progress lines (a line per 10 %, with
        the ETA) under the part's name, so that an hours-long part shows how far it is. Returns (stdout, exit
        status); an exception (SIGTERM included) kills the child first, as subprocess.run does."""
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
                                cwd=self.out)
        stdout = []
        reader = threading.Thread(target=lambda: stdout.append(proc.stdout.read()))
        reader.start()
        try:
            for line in proc.stderr:
                log.write(line)
                log.flush()
                if PROGRESS_LINE.search(line):
                    print("    %s: %s" % (part, line.strip()), flush=True)
            proc.wait()
        except BaseException:
            proc.kill()
            proc.wait()
            raise
        finally:
            reader.join()
        return "".join(stdout), proc.returncode

    def rel(self, path):
        return os.path.relpath(path, self.out)


# ---------------------------------------------------------------------------------------------
# Table helpers.


def fnum(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def fmt(value, digits=3):
    if value is None:
        return "—"
    if value == 0:
        return "0"
    if 10 ** digits - 0.5 <= abs(value) < 1e7:
        return "%.0f" % value  # 1670, not 1.67e+03
    return "%.*g" % (digits, value)


def mean(values):
    values = [v for v in values if v is not None]
    return statistics.mean(values) if values else None


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def budget_flags(budgets):
    """--optimizers and --iters-for of a {method: [N, ...]} plan ([] = the method's own budget)."""
    flags = ["--optimizers", ",".join(budgets)]
    for method, ns in budgets.items():
        if ns:
            flags += ["--iters-for", "%s=%s" % (method, ",".join(str(n) for n in ns))]
    return flags


def compare_rows(directory):
    path = os.path.join(directory, "compare.csv")
    if not os.path.exists(path):
        raise PartFailed("%s: no compare.csv" % directory)
    return read_csv(path)


def method_order(rows):
    order = []
    for r in rows:
        key = (r["method"], r["N"])
        if key not in order:
            order.append(key)
    return order


def summarise_compare(rows, with_arcsim=False):
    """Means over the motions per (method, N): the frontier table's rows."""
    header = ["method", "N", "ms/frame (CPU)", "e_CD × 10³", "e_3D × 10²", "per-step error (median)",
              "max strain %", "diverged", "on the frontier"]
    if with_arcsim:
        header.insert(5, "e_CD × 10³ vs ARCSim")
    table = []
    for method, n in method_order(rows):
        runs = [r for r in rows if r["method"] == method and r["N"] == n]
        finished = [r for r in runs if r["diverged"] == "no"]
        row = [method, n or "converged",
               fmt(mean(fnum(r["ms_per_frame_cpu"]) for r in runs)),
               fmt(mean(fnum(r["e_cd_x1e3"]) for r in finished)) if finished else "—",
               fmt(mean(fnum(r["e_3d_x1e2"]) for r in finished)) if finished else "—",
               fmt(mean(fnum(r["step_error_median"]) for r in finished)) if finished else "—",
               fmt(max((fnum(r["max_strain_pct"]) or 0.0) for r in runs), 3),
               "%d/%d" % (sum(r["diverged"] != "no" for r in runs), len(runs)),
               "%d/%d" % (sum(r["frontier"] == "yes" for r in runs), len(runs))]
        if with_arcsim:
            row.insert(5, fmt(mean(fnum(r["e_cd_arcsim_x1e3"]) for r in finished)) if finished else "—")
        table.append(row)
    return header, table


# ---------------------------------------------------------------------------------------------
# The parts. Each returns (a section of results.md, the CSV files it wrote; None where it was skipped).


class Part:
    def __init__(self, name, title, func, *fargs):
        self.name, self.title, self.func, self.fargs = name, title, func, fargs


def section(title, commands, body, note=None):
    text = "## %s\n\n" % title
    if note:
        text += note + "\n\n"
    if commands:
        text += "```\n" + "\n".join(commands) + "\n```\n\n"
    return text + body.rstrip() + "\n"


def part_frontier(ctx, part, grid, motions, frames, budgets):
    d = os.path.join(ctx.out, part)
    args = (["compare", "--res", str(grid), "--motions", motions, "--frames", str(frames)] +
            budget_flags(budgets) + ["--threads", "1"] + ctx.plan["compare_extra"] +
            ["--out", ctx.runner.rel(d)])
    if ctx.resume:
        args.append("--resume")
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
    return section(part_title(part, grid), [command_text([ctx.binary] + args)],
                   body + markdown_table(header, table) + chart), [os.path.join(d, "frontier.csv")]


def part_title(part, grid):
    return "The error–time frontier at %d²" % grid if part.startswith("frontier") else part


BENCH_ROW = re.compile(r"^\s*(\d+)\^2\s+(.*)$")


def part_newton_cost(ctx, part, bench):
    d = os.path.join(ctx.out, part)
    args = ["bench", "newton", "--res", bench["res"], "--frames", str(bench["frames"]), "--threads", "1",
            "--repeat", str(bench["repeat"])]
    stdout_path = os.path.join(d, "bench.txt")
    if ctx.resume and os.path.exists(stdout_path):
        text = open(stdout_path, encoding="utf-8").read()
    else:
        text = ctx.run(part, args)
        write_atomic(stdout_path, text)
    header_line = next((l for l in text.splitlines() if l.strip().startswith("res")), None)
    rows = []
    for line in text.splitlines():
        m = BENCH_ROW.match(line)
        if m:
            rows.append([m.group(1) + "²"] + m.group(2).split())
    if header_line is None or not rows:
        raise PartFailed("%s: no table in the bench's output (%s)" % (part, stdout_path))
    names = header_line.split()
    # Two-word columns as the bench prints them.
    header = []
    skip = False
    for i, w in enumerate(names):
        if skip:
            skip = False
            continue
        if i + 1 < len(names) and (w, names[i + 1]) in {("max", "ms"), ("max", "it"), ("cg", "it/st"),
                                                       ("neg", "curv")}:
            header.append(w + " " + names[i + 1])
            skip = True
        else:
            header.append(w)
    header[0] = "grid"
    rows = [r[:len(header)] for r in rows]
    write_csv(os.path.join(d, "newton-cost.csv"), header, rows)
    first = text.splitlines()[0] if text else ""
    body = ("%s. Columns: ms/frame (median of the runs) and its range, the slowest step, Newton iterations per "
            "step and the most in one step, factorisations and CG products per step, the share of iterations "
            "with negative curvature, rejected trials per step, steps converged.\n\n" % first.rstrip("."))
    return section("The Newton reference's cost", [command_text([ctx.binary] + args)],
                   body + markdown_table(header, rows)), [os.path.join(d, "newton-cost.csv")]


def part_superres(ctx, part, sr):
    d = os.path.join(ctx.out, part)
    args = ["compare", "--preset", "superres", "--res", sr["res"], "--threads", "1"]
    if sr["frames"]:
        args += ["--frames", str(sr["frames"])]
    if sr["step_samples"]:
        args += ["--step-samples", str(sr["step_samples"])]
    if ctx.quick:
        args += ["--cd-samples", "2000"]
    args += ["--out", ctx.runner.rel(d)]
    if ctx.resume:
        args.append("--resume")
    ctx.run(part, args)
    rows = compare_rows(d)
    grids = []
    for r in rows:
        if r["resolution"] not in grids:
            grids.append(r["resolution"])
    methods = method_order(rows)
    header = ["grid"] + ["%s%s" % (m, " (N = %s)" % n if n and n != "10" else "") for m, n in methods]
    table = []
    for g in grids:
        line = [g if "x" in g else g + "²"]
        for m, n in methods:
            hit = [r for r in rows if r["resolution"] == g and r["method"] == m and r["N"] == n]
            if not hit:
                line.append("—")
                continue
            r = hit[0]
            e = "diverged" if r["diverged"] != "no" else fmt(fnum(r["e_cd_x1e3"]), 2)
            line.append("%s, %s ms" % (e, fmt(fnum(r["ms_per_frame_cpu"]), 3)))
        table.append(line)
    write_csv(os.path.join(d, "superres.csv"), header, table)
    body = ("e_CD × 10³ against each grid's own Newton reference, and CPU ms/frame; N = 10 unless the column "
            "says; METHOD-interp32 solves on the grid with 32 vertices along the longer edge and prolongs "
            "bilinearly. Per-step errors, max strain: `superres/compare.csv`.\n\n")
    chart = publish_picture(ctx, os.path.join(d, "superres.svg"), "superres.svg",
                            "e_CD against the grid, one line per method")
    return section("Zero-shot super-resolution", [command_text([ctx.binary] + args)],
                   body + markdown_table(header, table) + chart), [os.path.join(d, "superres.csv")]


EVAL_E3D = re.compile(r"e_3D x 10\^2 = ([0-9.eE+-]+)")
EVAL_ECD = re.compile(r"e_CD x 10\^3 = ([0-9.eE+-]+)")


def kept_rollout(d, method, n, grid, motion):
    budget = "_%s" % n if n else ""
    path = os.path.join(d, "rollout_%s%s_%s_%s.h5" % (method, budget, grid, motion))
    if os.path.exists(path):
        return path
    hits = glob.glob(os.path.join(d, "rollout_%s%s_%s*_%s.h5" % (method, budget, grid, motion)))
    return hits[0] if hits else None


def part_offcorner(ctx, part, grid, presets, frames, n):
    methods = ctx.plan["offcorner_methods"]
    header = ["preset", "newton vs newton-min"]
    header += ["vs newton: %s" % m for m in methods] + ["vs newton-min: %s" % m for m in methods]
    table, commands = [], []
    for preset in presets:
        d = os.path.join(ctx.out, part, preset)
        args = (["compare", "--res", str(grid), "--handles", preset, "--motions", "xy_v2", "--frames", str(frames),
                 "--optimizers", "newton-min," + ",".join(methods), "--iters", str(n),
                 "--threads", "1", "--keep-rollouts"] + ctx.plan["compare_extra"] + ["--out", ctx.runner.rel(d)])
        if ctx.resume:
            args.append("--resume")
        if not commands:
            commands.append(command_text([ctx.binary] + args).replace(preset, "PRESET"))
        ctx.run(part + " " + preset, args)
        rows = compare_rows(d)
        against_newton = {r["method"]: r for r in rows}
        nm = kept_rollout(d, "newton-min", "", grid, "xy_v2")
        refs = glob.glob(os.path.join(d, "newton_reference_*.h5"))
        if nm is None or not refs:
            raise PartFailed("%s: newton-min's rollout or the reference missing in %s" % (part, d))

        def evaluate(rollout, label):
            eval_args = ["evaluate", "--reference", ctx.runner.rel(nm), ctx.runner.rel(rollout)]
            if ctx.quick:
                eval_args += ["--cd-samples", "2000"]
            out = ctx.run(part + " " + preset + " " + label, eval_args)
            m = EVAL_E3D.search(out)
            return fnum(m.group(1)) if m else None

        if len(commands) == 1:
            commands.append("fnopt evaluate --reference ROLLOUT_OF_NEWTON_MIN ROLLOUT")
        line = [preset, fmt(evaluate(refs[0], "newton"))]
        vs_min = []
        for m in methods:
            r = against_newton.get(m)
            line.append(fmt(fnum(r["e_3d_x1e2"])) if r and r["diverged"] == "no" else "—")
            rollout = kept_rollout(d, m, n, grid, "xy_v2")
            if rollout is None:
                raise PartFailed("%s: no kept rollout of %s in %s" % (part, m, d))
            vs_min.append(fmt(evaluate(rollout, m)))
        table.append(line + vs_min)
    path = os.path.join(ctx.out, part, "offcorner.csv")
    write_csv(path, header, table)
    body = ("e_3D × 10² over %d frames of xy_v2 at %d², N = %d, against the reference (newton, which can end "
            "at a saddle of the step's energy) and against newton-min (Newton that leaves saddles and ends at "
            "a minimum). The newton columns come from compare, the newton-min columns from `fnopt evaluate` "
            "on the rollouts compare kept.\n\n" % (frames, grid, n))
    return section("Off the corners at %d²" % grid, commands, body + markdown_table(header, table)), [path]


def part_arcsim(ctx, part, runs):
    if not ctx.arcsim_dir:
        print("note: part arcsim skipped: no --arcsim-dir (the ARCSim runs are not in the repository)", flush=True)
        return section("Against ARCSim", [], "Skipped: no `--arcsim-dir` given (the ARCSim runs are not in the "
                                              "repository).\n"), None
    header = ["grid", "motions", "method", "N", "e_CD × 10³ vs ARCSim", "e_CD × 10³ vs Newton", "ms/frame (CPU)",
              "max strain %", "diverged"]
    table, commands, files = [], [], []
    for grid, motions, frames, budgets in runs:
        d = os.path.join(ctx.out, part, str(grid))
        os.makedirs(d, exist_ok=True)
        # The frontier part's Newton references are this part's too (same scene): linked, not solved again.
        for ref in glob.glob(os.path.join(ctx.out, "frontier-%d" % grid, "newton_reference_*.h5")):
            target = os.path.join(d, os.path.basename(ref))
            if not os.path.exists(target):
                try:
                    os.link(ref, target)
                except OSError:
                    pass
        args = (["compare", "--res", str(grid), "--motions", motions, "--frames", str(frames)] +
                budget_flags(budgets) + ["--threads", "1", "--arcsim-dir", ctx.arcsim_dir] +
                ctx.plan["compare_extra"] + ["--out", ctx.runner.rel(d)])
        if ctx.resume:
            args.append("--resume")
        commands.append(command_text([ctx.binary] + args).replace(ctx.arcsim_dir, "ARCSIM_DIR"))
        ctx.run(part, args)
        rows = compare_rows(d)
        n_motions = len(set(r["motion"] for r in rows))
        for method, n in method_order(rows):
            runs_ = [r for r in rows if r["method"] == method and r["N"] == n]
            fin = [r for r in runs_ if r["diverged"] == "no"]
            table.append(["%d²" % grid, str(n_motions), method, n or "converged",
                          fmt(mean(fnum(r["e_cd_arcsim_x1e3"]) for r in fin)),
                          fmt(mean(fnum(r["e_cd_x1e3"]) for r in fin)),
                          fmt(mean(fnum(r["ms_per_frame_cpu"]) for r in runs_)),
                          fmt(max((fnum(r["max_strain_pct"]) or 0.0) for r in runs_)),
                          "%d/%d" % (len(runs_) - len(fin), len(runs_))])
    path = os.path.join(ctx.out, part, "arcsim.csv")
    write_csv(path, header, table)
    files.append(path)
    body = ("Means over the motions ARCSim has at each grid (32²: the fifteen; 64²: xy_v2, rot_h0, xyz_v3; "
            "100²: xy_v2), e_CD against ARCSim at its stored frames (every 1/30 s).\n\n")
    return section("Against ARCSim", commands, body + markdown_table(header, table)), files


def part_stability(ctx, part, st):
    d = os.path.join(ctx.out, part)
    args = ["stability", "--cases", st["cases"], "--optimizers",
            ",".join(st["optimizers"].split(",")), "--threads", "1"]
    if st["frames"]:
        args += ["--frames", str(st["frames"])]
    args += ["--out", ctx.runner.rel(d)]
    if ctx.resume:
        args.append("--resume")
    ctx.run(part, args)
    path = os.path.join(d, "stability.csv")
    if not os.path.exists(path):
        raise PartFailed("%s: no stability.csv" % part)
    rows = read_csv(path)
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    header = ["method", "N", "finished", "diverged on", "worst e_3D × 10² (case)", "largest energy growth (case)",
              "unconverged steps"]
    table = []
    for m in methods:
        mine = [r for r in rows if r["method"] == m]
        fin = [r for r in mine if r["outcome"] == "finished"]
        div = ["%s (step %s)" % (r["case"], r["diverged_step"]) for r in mine if r["outcome"] == "diverged"]
        worst = max(fin, key=lambda r: fnum(r["e_3d_x1e2"]) or 0.0, default=None)
        growth = max(fin, key=lambda r: fnum(r["energy_growth"]) or 0.0, default=None)
        uncon = sum(int(r["unconverged_steps"] or 0) for r in mine)
        table.append([m, mine[0]["N"], "%d/%d" % (len(fin), len(mine)), ", ".join(div) or "none",
                      "%s (%s)" % (fmt(fnum(worst["e_3d_x1e2"])), worst["case"]) if worst else "—",
                      "%s (%s)" % (fmt(fnum(growth["energy_growth"])), growth["case"]) if growth else "—",
                      str(uncon)])
    out_path = os.path.join(d, "stability-summary.csv")
    write_csv(out_path, header, table)
    body = ("One row per method over the cases (`fnopt stability --list-cases`); e_3D against Newton on the same "
            "case; energy growth is the largest total energy over the first; every case and method: "
            "`stability/stability.csv` and `stability/report.md`.\n\n")
    return section("Stability", [command_text([ctx.binary] + args)], body + markdown_table(header, table)), \
        [out_path]


def part_contact(ctx, part, plan_):
    """Every method on the example contact scenes at each grid: e_CD against Newton per scene and grid, and the
    smallest vertex-obstacle distance of any run; then far obstacles' cost."""
    grids = plan_["res"].split(",")
    header = ["method", "N"] + ["%s e_CD × 10³ (%s)" % (name, " / ".join(g + "²" for g in grids))
                                for name, _ in plan_["scenes"]] + ["smallest distance (mm)", "diverged"]
    cells, smallest, diverged, commands = {}, {}, {}, []
    for name, frames in plan_["scenes"]:
        d = os.path.join(ctx.out, part, name)
        scene = os.path.join(SCENES, name + ".scene")
        args = (["compare", "--scene", scene, "--res", plan_["res"], "--frames", str(frames), "--motions", "static"] +
                budget_flags(plan_["budgets"]) + ["--threads", "1"] + ctx.plan["compare_extra"] +
                ["--out", ctx.runner.rel(d)])
        if ctx.resume:
            args.append("--resume")
        commands.append(command_text([ctx.binary] + args).replace(SCENES + os.sep, "examples/scenes/"))
        ctx.run(part + " " + name, args)
        for r in compare_rows(d):
            key = (r["method"], r["N"])
            done = r["diverged"] == "no"
            cells.setdefault(key, {}).setdefault(name, {})[r["resolution"]] = (
                fmt(fnum(r["e_cd_x1e3"])) if done else "diverged")
            distance = fnum(r.get("min_obstacle_distance_m"))
            if distance is not None:
                smallest[key] = min(smallest.get(key, distance), distance)
            diverged.setdefault(key, [0, 0])
            diverged[key][0] += not done
            diverged[key][1] += 1
    table = []
    for key in cells:
        row = [key[0], key[1] or "converged"]
        for name, _ in plan_["scenes"]:
            row.append(" / ".join(cells[key].get(name, {}).get(g, "—") for g in grids))
        row += [fmt(1e3 * smallest[key]) if key in smallest else "—", "%d/%d" % tuple(diverged[key])]
        table.append(row)
    path = os.path.join(ctx.out, part, "contact.csv")
    write_csv(path, header, table)
    bench_args = ["bench", "contact"] + plan_["bench"] + ["--threads", "1"]
    text = ctx.run(part + " bench", bench_args)
    bench_rows = [m.groups() for m in (re.match(r"^\s*(\d+)\^2\s+(\S+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+(\S+)\s*$", l)
                                       for l in text.splitlines()) if m]
    if not bench_rows:
        raise PartFailed("%s: no table in bench contact's output" % part)
    bench_header = ["grid", "method", "ms/frame without obstacles", "with far obstacles", "ratio", "same rollout"]
    bench_table = [[g + "²"] + list(rest) for g, *rest in bench_rows]
    bench_path = os.path.join(ctx.out, part, "bench-contact.csv")
    write_csv(bench_path, bench_header, bench_table)
    body = ("The scenes of `examples/scenes/` (a released cloth on a sphere above a floor, on a table top with an "
            "overhang, on a plane tilted by 30° with friction 0.4; a sphere pushed through the hanging cloth), every "
            "method against Newton converging on every step; the smallest distance of any vertex to any obstacle "
            "over every frame, scene and grid (≥ the contact thickness, 1 mm: no penetration).\n\n" +
            markdown_table(header, table) + "\n\nFar obstacles' cost: the benchmark scene with and without a floor "
            "and a sphere far from the cloth, alternated runs, medians.\n\n```\n" +
            command_text([ctx.binary] + bench_args) + "\n```\n\n" + markdown_table(bench_header, bench_table))
    return section("Contact with obstacles", commands, body), [path, bench_path]


GRADCHECK_ROW = re.compile(r"^(\S+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$")
BENCH_ADJOINT_ROW = re.compile(r"^\s*(\d+)\^2\s+(.*)$")


def part_adjoint(ctx, part, plan_):
    """The adjoint's checks and costs, and the inverse problems fnopt answers by it."""
    d = os.path.join(ctx.out, part)
    os.makedirs(d, exist_ok=True)
    files, commands, body = [], [], ""

    def gradcheck(label, extra):
        args = ["gradcheck"] + extra + ["--threads", "1"]
        commands.append(command_text([ctx.binary] + args))
        rows = [m.groups() for m in (GRADCHECK_ROW.match(l) for l in ctx.run(part + " " + label, args).splitlines())
                if m and m.group(1) != "parameter"]
        if not rows:
            raise PartFailed("%s: no rows in gradcheck's output" % part)
        return {r[0]: r[4] for r in rows}

    plain = gradcheck("gradcheck", plan_["gradcheck"])
    contact = gradcheck("gradcheck contact", plan_["contact_gradcheck"] + ["--obstacle", GRADCHECK_OBSTACLE])
    header = ["parameter", "relative error, plain scene", "with a sphere behind the cloth (friction 0.3)"]
    table = [[k, plain[k], contact.get(k, "—")] for k in plain]
    path = os.path.join(d, "gradcheck.csv")
    write_csv(path, header, table)
    files.append(path)
    body += ("The adjoint against central differences of the rollout, a row per parameter kind:\n\n" +
             markdown_table(header, table) + "\n\n")

    bench_args = ["bench", "adjoint"] + plan_["bench"] + ["--threads", "1"]
    commands.append(command_text([ctx.binary] + bench_args))
    text = ctx.run(part + " bench", bench_args)
    head = next((l for l in text.splitlines() if l.strip().startswith("res")), None)
    rows = [[m.group(1) + "²"] + m.group(2).split() for m in (BENCH_ADJOINT_ROW.match(l) for l in text.splitlines()) if m]
    if head is None or not rows:
        raise PartFailed("%s: no table in bench adjoint's output" % part)
    bench_header = ["grid", "forward ms/frame", "backward ms/frame", "backward / forward", "factorisations / step",
                    "solves / step", "record MB", "peak RSS MB", "saddle steps", "status"]
    rows = [r[:len(bench_header)] for r in rows]
    path = os.path.join(d, "bench-adjoint.csv")
    write_csv(path, bench_header, rows)
    files.append(path)
    body += ("Cost of the backward pass against the recorded forward pass it differentiates (Newton to 1e-10 m/s², "
             "exact steps), and the memory the record holds:\n\n" + markdown_table(bench_header, rows) + "\n\n")

    loss_csv = os.path.join(d, "fit-handles.csv")
    fit_args = (["fit-handles"] + plan_["fit_handles"] + ["--threads", "1", "--csv", ctx.runner.rel(loss_csv),
                                                          "--plot", ctx.runner.rel(os.path.join(d, "fit-handles.svg"))])
    commands.append(command_text([ctx.binary] + fit_args))
    said = [l for l in ctx.run(part + " fit-handles", fit_args).splitlines()
            if l.startswith(("scene:", "target:", "path:"))]
    history = {}
    for r in read_csv(loss_csv):
        history.setdefault(r["method"], []).append((int(r["passes"]), fnum(r["loss_m2"])))
    passes = plan_["passes"]
    fit_header = ["method", "start loss m²"] + ["after %d passes" % n for n in passes]
    fit_table = []
    for method, points in history.items():
        best = lambda n: min((loss for k, loss in points if k <= n), default=None)
        fit_table.append([method, fmt(points[0][1])] + [fmt(best(n)) for n in passes])
    path = os.path.join(d, "fit-handles-table.csv")
    write_csv(path, fit_header, fit_table)
    files += [path, loss_csv]
    chart = publish_picture(ctx, os.path.join(d, "fit-handles.svg"), "fit-handles.svg",
                            "the loss against passes, gradient and compass")
    body += ("Handle paths to a target (`fnopt fit-handles`; %s): the best loss after N passes, a gradient "
             "evaluation counting two.\n\n" % "; ".join(said) +
             markdown_table(fit_header, fit_table) + chart + "\n")

    if plan_["fit_material"] and ctx.arcsim_dir:
        start = os.path.join(d, "fit-start.txt")
        write_atomic(start, FIT_START)
        refs = [os.path.join(ctx.arcsim_dir, "arcsim_N32_%s.h5" % m) for m in ("xy_v2", "rot_h0")]
        fit_rows = []
        for method, extra in (("gradient", ["--initial-step", "0.7"]),
                              ("compass", ["--initial-step", "0.7", "--final-step", "0.08"])):
            args = (["fit-material", "--method", method, "--reference"] + refs +
                    ["--start", ctx.runner.rel(start), "--fit", "stretch,shear,damping"] + plan_["fit_material"] +
                    extra + ["--threads", "1", "--out", ctx.runner.rel(os.path.join(d, "fitted-%s.txt" % method))])
            commands.append(command_text([ctx.binary] + args).replace(ctx.arcsim_dir, "ARCSIM_DIR"))
            out = ctx.run(part + " fit-material " + method, args)
            last = [l for l in out.splitlines() if "e_CD x 10^3" in l and ("fitted" in l or "against" in l)]
            fitted = [l for l in out.splitlines() if l.startswith("fitted:")]
            fit_rows.append([method, fitted[-1][len("fitted:"):].strip() if fitted else "—",
                             last[-1].strip() if last else "—"])
        path = os.path.join(d, "fit-material.csv")
        write_csv(path, ["method", "fitted material", "e_CD and rollouts"], fit_rows)
        files.append(path)
        body += ("\ndesign.md §7's fit (32² xy_v2 and rot_h0 against ARCSim, from stretch 300, shear 3, damping "
                 "1), by gradient and by compass:\n\n" +
                 markdown_table(["method", "fitted material", "e_CD and rollouts"], fit_rows) + "\n")
    return section("Gradients through rollouts", commands, body), files


def part_paper(ctx, part):
    """The paper's figures (scripts/data/paper-tables.csv) beside ours, each row saying what differs."""
    paper = [r for r in read_csv(PAPER_CSV) if r["motion"] == "mean"]
    ours = {}
    arcsim_csv = os.path.join(ctx.out, "arcsim", "arcsim.csv")
    if os.path.exists(arcsim_csv):
        for r in read_csv(arcsim_csv):
            ours[(r["grid"].rstrip("²"), r["method"], r["N"])] = r

    def figure(table, quantity, method, grid, n):
        hit = [r for r in paper if (r["table"], r["quantity"], r["method"], r["resolution"], r["N"]) ==
               (table, quantity, method, grid, n)]
        return "%s ± %s" % (hit[0]["value"], hit[0]["sd"]) if hit else "—"

    def mine(grid, method, n, column):
        r = ours.get((grid, method, n))
        return r[column] if r else "—"

    differs = {"32": "the same fifteen motions", "64": "ours: 3 of the 15 motions (ARCSim's 64² runs)",
               "100": "ours: xy_v2 only (ARCSim's one 100² run); the paper's xy_v2 at N = 10: 4.2"}
    header = ["paper table", "grid", "N", "paper e_CD × 10³", "ours e_CD × 10³: fnopt / fnopt-ss",
              "paper ms/frame (A100)", "ours ms/frame (CPU): fnopt / fnopt-ss", "what differs"]
    table = []
    for grid in ("32", "64", "100"):
        for n in ("5", "10", "20"):
            table.append(["6.7 (6.1 at N = 10)", grid + "²", n, figure("6.7", "e_CD x 1e3", "FNOPT", grid, n),
                          "%s / %s" % (mine(grid, "fnopt", n, "e_CD × 10³ vs ARCSim"),
                                       mine(grid, "fnopt-ss", n, "e_CD × 10³ vs ARCSim")),
                          figure("6.7", "ms per frame (A100)", "FNOPT", grid, n),
                          "%s / %s" % (mine(grid, "fnopt", n, "ms/frame (CPU)"),
                                       mine(grid, "fnopt-ss", n, "ms/frame (CPU)")),
                          differs[grid]])
    table.append(["6.3, L-BFGS (step 1)", "100²", "120", figure("6.3", "e_CD x 1e3", "L-BFGS (step 1)", "100", "120"),
                  "lbfgs: %s" % mine("100", "lbfgs", "120", "e_CD × 10³ vs ARCSim"), "—",
                  "lbfgs: %s" % mine("100", "lbfgs", "120", "ms/frame (CPU)"),
                  "paper: L-BFGS with step 1; ours: lbfgs (fixed step 1, mass-metric start); ours: xy_v2 only"])
    path = os.path.join(ctx.out, part, "paper.csv")
    write_csv(path, header, table)
    note = ("The paper's figures are `scripts/data/paper-tables.csv` (the FNOPT thesis, chapter 6; means ± standard "
            "deviation over the fifteen motions, against the paper's ARCSim runs). Ours: the ARCSim part's means "
            "against ARCSim%s. What differs on every row: the paper runs its model per protocol on an A100 with the "
            "material held in grid units across resolutions; ours runs on one CPU thread with the physical material "
            "fitted to ARCSim; our fnopt is the FNO update with pqn's direction in its subspace (32² model), our "
            "fnopt-ss the paper's method on the multi-resolution model. The last column says what differs besides."
            "\n\n" % ("" if ours else " (not run: no `--arcsim-dir`, so our columns are empty)"))
    return section("The paper's tables beside ours", [], note + markdown_table(header, table)), [path]


# ---------------------------------------------------------------------------------------------
# The run: parts in order, progress, state for --resume, the assembled results.md.


class Context:
    def __init__(self, args):
        self.binary = os.path.abspath(args.binary)
        self.out = os.path.abspath(args.out)
        self.quick = args.quick
        self.resume = args.resume
        self.arcsim_dir = os.path.abspath(args.arcsim_dir) if args.arcsim_dir else None
        self.note = args.note
        self.plan = plan(args)
        self.runner = Runner(self.binary, self.out)

    def run(self, part, args):
        return self.runner.run(part, args)


def make_parts(ctx):
    p = ctx.plan
    parts = []
    for grid, motions, frames, budgets in p["frontier"]:
        parts.append(Part("frontier-%d" % grid, "frontier %d²" % grid, part_frontier, grid, motions, frames,
                          budgets))
    parts.append(Part("newton-cost", "Newton's cost", part_newton_cost, p["bench"]))
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


def hms(seconds):
    seconds = int(seconds)
    return "%d:%02d:%02d" % (seconds // 3600, seconds % 3600 // 60, seconds % 60)


def progress(parts, index, done, elapsed, estimates, measured):
    """One line: the part starting, the parts done and left, the time so far and the ETA. The ETA is the
    estimates of the parts left, scaled by measured/estimated over the parts this run has finished."""
    left = [p.name for p in parts[index + 1:]]
    scale = 1.0
    est_done = sum(estimates.get(name, 0) for name in measured)
    if est_done > 0:
        scale = sum(measured.values()) / est_done
    remaining = scale * sum(estimates.get(p.name, 0) for p in parts[index:] if p.name not in measured)
    print("[%d/%d] %s: running; done: %s; left: %s; elapsed %s, ETA ~%s" %
          (index + 1, len(parts), parts[index].name, ", ".join(done) or "none", ", ".join(left) or "none",
           hms(elapsed), hms(remaining)), flush=True)


CONVENTIONS = (
    "**Conventions.** Release build, one thread per run. ms/frame is CPU time (wall time × the CPU share the "
    "process got), so compare ratios within one table rather than ms/frame across tables. e_CD × 10³ and "
    "e_3D × 10² are against the converged Newton reference of the same scene (design.md §6, §8) unless marked "
    "\"vs ARCSim\"; per-step error is the energy fraction left after N iterations from the reference's sampled "
    "states (design.md §8). A run marked diverged passed 300 % edge strain or went non-finite. The scene: the "
    "default cloth (design.md §7), corner handles, 390 frames at dt = 1/60 unless a table says otherwise. "
    "`ARCSIM_DIR` holds the ARCSim runs (`arcsim_N{res}_{motion}.h5`), which the repository does not ship.")


def assemble(ctx, sections):
    """OUT/results.md: a header (what made it, on what, the conventions), the parts' sections, and a pointer to
    history. It is docs/results.md as it stands, with the pictures the parts copied beside it."""
    version = run_capture([ctx.binary, "--version"]).strip() or "unknown"
    header = ("# Results\n\nThe current release's tables, generated by `scripts/release-results.py%s` with %s "
              "(`fnopt --version`: %s) on %s, %d CPU cores. Each table is headed by the command that made it "
              "(output directories relative to `--out`); `scripts/release-results.py --help` says how to run it.\n"
              % (" --quick" if ctx.quick else "", os.path.basename(ctx.binary), version,
                 time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), os.cpu_count() or 0))
    if ctx.note:
        header += "\n" + ctx.note + "\n"
    header += "\n" + CONVENTIONS + "\n"
    if ctx.quick:
        header += ("\n**Smoke pass (`--quick`)**: tiny grids and a few frames; the numbers check that every "
                   "part runs, they measure nothing.\n")
    body = "\n".join(sections)
    footer = ("\n## History\n\nEarlier releases' tables, this release's development and every experiment set "
              "aside: [history/](history/README.md).\n")
    write_atomic(os.path.join(ctx.out, "results.md"), header + "\n" + body + footer)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] + " Writes OUT/<part>/ and OUT/results.md.",
        epilog="Parts: frontier-32/64/100, newton-cost, superres, offcorner-32/64, arcsim, stability, contact, adjoint, "
               "paper "
               "(--quick: frontier-12/16, offcorner-12). Example: scripts/release-results.py --binary "
               "build/fnopt --out out/release --arcsim-dir /data/arcsim --resume")
    parser.add_argument("--binary", default="build/fnopt", help="the fnopt executable (default: build/fnopt)")
    parser.add_argument("--out", required=True, help="output directory (created)")
    parser.add_argument("--quick", action="store_true",
                        help="smoke pass: tiny grids, a few frames, two motions, every part (a minute or two)")
    parser.add_argument("--resume", action="store_true",
                        help="keep finished parts; compare and stability keep their finished rows")
    parser.add_argument("--arcsim-dir", help="directory of the ARCSim runs (arcsim_N{res}_{motion}.h5); "
                                             "without it the ARCSim part is skipped with a note")
    parser.add_argument("--repeat", type=int, default=5, help="newton-cost: timed runs per grid (default 5)")
    parser.add_argument("--note", help="a paragraph for results.md's header, e.g. how the machine was shared "
                                       "while the parts ran")
    parser.add_argument("--only", help="run only these parts, comma-separated; the other parts' finished sections are "
                                       "kept in results.md (with --resume, compare keeps the parts' finished rows)")
    args = parser.parse_args(argv)
    # A terminated run stops the fnopt run it waits for too (Runner kills its child on the exception),
    # so that --resume finds no stray process still writing the part's files.
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))

    if not os.access(args.binary, os.X_OK):
        print("release-results: no executable fnopt at %s (--binary)" % args.binary, file=sys.stderr)
        return 2
    if args.arcsim_dir and not os.path.isdir(args.arcsim_dir):
        print("release-results: --arcsim-dir %s is not a directory" % args.arcsim_dir, file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    ctx = Context(args)
    parts = make_parts(ctx)
    only = set(args.only.split(",")) if args.only else None
    if only and not only <= {p.name for p in parts}:
        print("release-results: unknown part in --only: %s" % ", ".join(sorted(only - {p.name for p in parts})),
              file=sys.stderr)
        return 2

    state_path = os.path.join(ctx.out, "state.json")
    state = {}
    if (args.resume or only) and os.path.exists(state_path):
        with open(state_path, encoding="utf-8") as f:
            state = json.load(f)
        if state.get("_quick") != ctx.quick:
            state = {}
    state["_quick"] = ctx.quick
    start = time.time()
    done = []
    measured = {}  # seconds of the parts this run finished
    for i, part in enumerate(parts):
        if only and part.name not in only:
            if part.name in state:
                done.append(part.name + " (kept)")
            continue
        # Kept with --resume: a finished part, but not one skipped for want of --arcsim-dir when it is given
        # now, nor the paper's table, which is assembled from the others' outputs.
        kept = (args.resume and not only and part.name in state and part.name != "paper" and
                not (state[part.name].get("skipped") and ctx.arcsim_dir))
        if kept:
            done.append(part.name + " (kept)")
            continue
        progress(parts, i, done, time.time() - start, ctx.plan["estimate_s"], measured)
        t0 = time.time()
        try:
            text, files = part.func(ctx, part.name, *part.fargs)
        except PartFailed as e:
            print("release-results: part %s failed: %s" % (part.name, e), file=sys.stderr, flush=True)
            return 1
        except (OSError, KeyError, ValueError, IndexError) as e:
            print("release-results: part %s failed: %s: %s" % (part.name, type(e).__name__, e), file=sys.stderr,
                  flush=True)
            return 1
        state[part.name] = {"section": text, "files": [os.path.relpath(f, ctx.out) for f in files or []],
                            "skipped": files is None, "seconds": round(time.time() - t0, 1)}
        write_atomic(state_path, json.dumps(state, indent=1))
        done.append(part.name)
        measured[part.name] = time.time() - t0
        print("    %s finished in %s" % (part.name, hms(time.time() - t0)), flush=True)
    sections = [state[p.name]["section"] for p in parts if p.name in state]
    assemble(ctx, sections)
    print("wrote %s (%d parts, %s)" % (os.path.join(ctx.out, "results.md"), len(sections),
                                        hms(time.time() - start)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
