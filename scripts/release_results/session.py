"""One run of the release script: the parts in order, each announced by a progress line (done, left, ETA);
OUT/state.json records every finished part's section, so that --resume keeps them and --only reruns some
parts among the others' kept sections; results.md is assembled at the end, or, with --splice, made from an
earlier page with this run's sections put in."""

import json
import os
import sys
import time

from .assemble import assemble, splice
from .files import write_atomic
from .runner import PartFailed


def hms(seconds):
    """Seconds as H:MM:SS."""
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


def load_state(path, use, quick):
    """The finished parts recorded in state.json when use (--resume or --only) and it was written by a run of
    the same kind (--quick or not); otherwise none."""
    state = {}
    if use and os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            state = json.load(f)
        if state.get("_quick") != quick:
            state = {}
    state["_quick"] = quick
    return state


def kept(ctx, part, state, only):
    """Whether --resume keeps part's finished section: not one skipped for want of --arcsim-dir when it is
    given now, nor the paper's table, which is assembled from the others' outputs."""
    return (ctx.resume and not only and part.name in state and part.name != "paper" and
            not (state[part.name].get("skipped") and ctx.arcsim_dir))


def run_part(ctx, part):
    """Runs one part: (its section, its files); None, after one line naming it, when it failed."""
    try:
        return part.func(ctx, part.name, *part.fargs)
    except PartFailed as e:
        print("release-results: part %s failed: %s" % (part.name, e), file=sys.stderr, flush=True)
    except (OSError, KeyError, ValueError, IndexError) as e:
        print("release-results: part %s failed: %s: %s" % (part.name, type(e).__name__, e), file=sys.stderr,
              flush=True)
    return None


def run_parts(ctx, parts, only):
    """Runs the parts (only those named in only, when given), recording each in state.json as it finishes,
    then assembles results.md from every recorded section. Returns the exit status: 0, or 1 when a part
    failed (the run stops there)."""
    state_path = os.path.join(ctx.out, "state.json")
    state = load_state(state_path, ctx.resume or only, ctx.quick)
    start = time.time()
    done = []
    made = []  # the sections of the parts this run ran, for --splice
    measured = {}  # seconds of the parts this run finished
    for i, part in enumerate(parts):
        if (only and part.name not in only) or kept(ctx, part, state, only):
            if part.name in state:
                done.append(part.name + " (kept)")
            continue
        progress(parts, i, done, time.time() - start, ctx.plan["estimate_s"], measured)
        t0 = time.time()
        result = run_part(ctx, part)
        if result is None:
            return 1
        text, files = result
        state[part.name] = {"section": text, "files": [os.path.relpath(f, ctx.out) for f in files or []],
                            "skipped": files is None, "seconds": round(time.time() - t0, 1)}
        write_atomic(state_path, json.dumps(state, indent=1))
        done.append(part.name)
        made.append(text)
        measured[part.name] = time.time() - t0
        print("    %s finished in %s" % (part.name, hms(time.time() - t0)), flush=True)
    sections = [state[p.name]["section"] for p in parts if p.name in state]
    if ctx.splice:
        splice(ctx, ctx.splice, made)
        print("wrote %s (%s with %d sections of this run, %s)" % (os.path.join(ctx.out, "results.md"), ctx.splice,
                                                                   len(made), hms(time.time() - start)), flush=True)
        return 0
    assemble(ctx, sections)
    print("wrote %s (%d parts, %s)" % (os.path.join(ctx.out, "results.md"), len(sections),
                                        hms(time.time() - start)), flush=True)
    return 0
