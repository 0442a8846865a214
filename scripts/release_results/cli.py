"""The command line of scripts/release-results.py: its arguments, the checks of its inputs before anything runs
(the binary, --arcsim-dir, that the binary is the release's version, --only's part names), SIGTERM, and main()."""

import argparse
import os
import re
import signal
import sys

from . import REPOSITORY
from .parts import Context, make_parts
from .runner import binary_version
from .session import run_parts

CMAKELISTS = os.path.join(REPOSITORY, "CMakeLists.txt")
PROJECT_VERSION = re.compile(r"^\s*project\s*\(\s*fnopt\s+VERSION\s+(\S+?)[\s)]", re.M)


def build_parser(doc):
    """The argument parser; doc is the launcher's docstring, whose first paragraph describes the command."""
    parser = argparse.ArgumentParser(
        description=doc.split("\n\n")[0] + " Writes OUT/<part>/ and OUT/results.md.",
        epilog="Parts: frontier-32/64/100, newton-cost, speed, superres, offcorner-32/64, arcsim, stability, "
               "contact, adjoint, paper "
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
    parser.add_argument("--jobs", type=int, default=1,
                        help="the contact part's scenes run this many at a time, each on one thread (default 1); at "
                             "most the machine's idle cores, or the timings share a core")
    parser.add_argument("--splice", metavar="PAGE",
                        help="write OUT/results.md as PAGE (an earlier results.md, e.g. docs/results.md) with the "
                             "sections of the parts this run ran in place of theirs (a new one before History); "
                             "PAGE's header and other sections stay as they are (--note is not used: edit that header)")
    parser.add_argument("--note", help="a paragraph for results.md's header, e.g. how the machine was shared "
                                       "while the parts ran")
    parser.add_argument("--only", help="run only these parts, comma-separated; the other parts' finished sections are "
                                       "kept in results.md (with --resume, compare keeps the parts' finished rows)")
    return parser


def release_version():
    """The release's version: the project(fnopt VERSION x.y.z ...) line of the repository's CMakeLists.txt; None
    when it cannot be read."""
    try:
        with open(CMAKELISTS, encoding="utf-8") as f:
            m = PROJECT_VERSION.search(f.read())
    except OSError:
        return None
    return m.group(1) if m else None


def version_mismatch(binary):
    """None when the binary's `fnopt --version` is the release's (results.md prints it as the release's);
    otherwise a line saying how they differ."""
    release = release_version()
    if release is None:
        return "no project(fnopt VERSION ...) line in %s to check %s's version against" % (CMAKELISTS, binary)
    try:
        built = binary_version(binary)
    except OSError as e:
        built = "nothing (%s)" % e
    if built == release:
        return None
    return ("`fnopt --version` of %s is %s, the release's (project() in CMakeLists.txt) %s: results.md would "
            "print a version that is not the release's; build the release's fnopt (--binary)"
            % (binary, built or "nothing", release))


def input_problem(args):
    """The first problem with the inputs that stops the run before anything runs, or None. A version mismatch
    stops a full run; --quick, a smoke pass, only warns of it."""
    if args.jobs < 1:
        return "--jobs %d: must be at least 1" % args.jobs
    if args.splice and not os.path.isfile(args.splice):
        return "--splice %s: no such file" % args.splice
    if not os.access(args.binary, os.X_OK):
        return "no executable fnopt at %s (--binary)" % args.binary
    if args.arcsim_dir and not os.path.isdir(args.arcsim_dir):
        return "--arcsim-dir %s is not a directory" % args.arcsim_dir
    mismatch = version_mismatch(args.binary)
    if mismatch and not args.quick:
        return mismatch
    if mismatch:
        print("release-results: warning (--quick goes on): " + mismatch, file=sys.stderr, flush=True)
    return None


def main(doc, argv=None):
    """Runs the release script with argv (default: the command line); doc is its --help description. Returns
    the exit status: 0 done, 1 a part failed, 2 bad inputs."""
    args = build_parser(doc).parse_args(argv)
    # A terminated run stops the fnopt run it waits for too (Runner kills its child on the exception),
    # so that --resume finds no stray process still writing the part's files.
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))

    problem = input_problem(args)
    if problem:
        print("release-results: " + problem, file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    ctx = Context(args)
    parts = make_parts(ctx)
    only = set(args.only.split(",")) if args.only else None
    if only and not only <= {p.name for p in parts}:
        print("release-results: unknown part in --only: %s" % ", ".join(sorted(only - {p.name for p in parts})),
              file=sys.stderr)
        return 2
    return run_parts(ctx, parts, only)
