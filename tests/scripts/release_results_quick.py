#!/usr/bin/python3
"""ctest release_results_quick: scripts/release-results.py --quick on the built fnopt, then a check that
the assembled results.md has every section, each headed by its command, no empty table, and every picture it
shows beside it; and that the script's output shows the progress of the fnopt runs inside a part. Before it, a
fake fnopt that says the wrong version checks the guard on the release's version: a full run refuses to start
(exit status 2, one line, nothing written), --quick warns and goes on; --jobs 0 is refused the same way. The
quick run itself runs the contact part's scenes two at a time (--jobs 2), and a fake whose table scene fails stops
such a run at once, killing the scenes running beside it. Last, --splice puts the paper's section, rerun, into
an earlier page and leaves the rest of that page as it was."""

import os
import re
import shutil
import subprocess
import sys
import tempfile

SECTIONS = ["The error–time frontier at 12²", "The error–time frontier at 16²", "The Newton reference's cost", "Every method's cost",
            "Zero-shot super-resolution", "Off the corners at 12²", "Against ARCSim", "Stability",
            "Contact with obstacles", "Gradients through rollouts", "The paper's tables beside ours"]


def check_version_guard(script):
    """The failures of the version guard, run with a fake fnopt whose every command prints a wrong version."""
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        fake = os.path.join(tmp, "fnopt")
        with open(fake, "w", encoding="utf-8") as f:
            f.write("#!/bin/sh\necho 0.0.0-not-the-release\n")
        os.chmod(fake, 0o755)
        out = os.path.join(tmp, "out")
        full = subprocess.run([sys.executable, script, "--binary", fake, "--out", out], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)
        lines = full.stderr.splitlines()
        if full.returncode != 2 or len(lines) != 1 or "0.0.0-not-the-release" not in lines[0] or os.path.exists(out):
            failures.append("a full run with the wrong version: exit status %d, %s (expected 2, one line naming it, "
                            "no --out)" % (full.returncode, full.stderr.strip() or "no message"))
        jobs = subprocess.run([sys.executable, script, "--jobs", "0", "--binary", fake, "--out", out],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        if jobs.returncode != 2 or "--jobs 0" not in jobs.stderr or os.path.exists(out):
            failures.append("--jobs 0: exit status %d, %s (expected 2, one line naming it, no --out)"
                            % (jobs.returncode, jobs.stderr.strip() or "no message"))
        # --quick goes on after a warning; its first part then fails on the fake's output.
        quick = subprocess.run([sys.executable, script, "--quick", "--binary", fake, "--out", out],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        if "warning" not in quick.stderr or "0.0.0-not-the-release" not in quick.stderr or \
                "frontier-12: running" not in quick.stdout:
            failures.append("--quick with the wrong version does not warn and go on: %s" % quick.stderr.strip())
    return ["version guard: " + f for f in failures]


def check_jobs_stop(script):
    """The failures of --jobs's stop: with a fake fnopt of the release's version whose table scene fails at once and
    whose other scenes would run for minutes, the contact part run two at a time must fail within seconds, naming
    the table, and leave no fake running."""
    sys.path.insert(0, os.path.join(os.path.dirname(script)))
    from release_results.cli import release_version  # noqa: E402  (the script's package, found through the path)
    with tempfile.TemporaryDirectory() as tmp:
        fake = os.path.join(tmp, "fnopt")
        with open(fake, "w", encoding="utf-8") as f:
            f.write("#!/bin/sh\ncase \"$*\" in --version) echo %s;; *table.scene*) echo broken >&2; exit 1;; "
                    "*) exec sleep 300;; esac\n" % release_version())
        os.chmod(fake, 0o755)
        try:
            r = subprocess.run([sys.executable, script, "--only", "contact", "--jobs", "2", "--binary", fake, "--out",
                                os.path.join(tmp, "out")], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               universal_newlines=True, timeout=60)
        except subprocess.TimeoutExpired:
            return ["--jobs 2: a failed scene did not stop the contact part within a minute"]
        left = subprocess.run(["pgrep", "-f", "sleep 300"], stdout=subprocess.PIPE, universal_newlines=True).stdout
        failures = []
        if r.returncode != 1 or "table.scene" not in r.stderr:
            failures.append("--jobs 2 with a failing scene: exit status %d, %s (expected 1 naming the table)"
                            % (r.returncode, r.stderr.strip().splitlines()[-1:] or "no message"))
        if left.strip():
            failures.append("--jobs 2 with a failing scene left fnopt runs behind: %s" % left.strip())
        return failures


def check_splice(script, binary, out):
    """The failures of --splice on the quick run's OUT: rerunning the paper's part into an earlier page replaces
    that page's paper section, or puts it before the history where the page had none, and keeps the page's
    header and other sections as they were."""
    failures = []
    head, stability, history = "# Results\n\nThe old header.\n\n", "## Stability\n\nold stability\n\n", \
        "## History\n\nold history\n"
    for old_paper in ("## The paper's tables beside ours\n\nold paper\n\n", ""):
        base = os.path.join(out, "base.md")
        with open(base, "w", encoding="utf-8") as f:
            f.write(head + stability + old_paper + history)
        r = subprocess.run([sys.executable, script, "--quick", "--resume", "--only", "paper", "--splice", base,
                            "--binary", binary, "--out", out], stdout=subprocess.PIPE, universal_newlines=True)
        text = open(os.path.join(out, "results.md"), encoding="utf-8").read()
        paper = text[text.find("## The paper's tables"):text.find("## History")]
        if r.returncode != 0 or not text.startswith(head + stability + "## The paper's tables") or \
                "| paper table |" not in paper or "old paper" in text or not text.endswith(history):
            failures.append("--splice into a page %s its paper section: exit %d, page:\n%s"
                            % ("with" if old_paper else "without", r.returncode, text))
    return failures


def main():
    if len(sys.argv) != 3:
        print("usage: release_results_quick.py FNOPT_BINARY OUT_DIR", file=sys.stderr)
        return 2
    binary, out = sys.argv[1], sys.argv[2]
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "release-results.py")
    guard_failures = check_version_guard(script) + check_jobs_stop(script)
    for f in guard_failures:
        print(f)
    shutil.rmtree(out, ignore_errors=True)
    # --jobs 2: the contact part runs its scenes two at a time.
    r = subprocess.run([sys.executable, script, "--quick", "--jobs", "2", "--binary", binary, "--out", out],
                       stdout=subprocess.PIPE, universal_newlines=True)
    print(r.stdout)
    if r.returncode != 0:
        print("release-results.py --quick exited with %d" % r.returncode)
        return 1
    text = open(os.path.join(out, "results.md"), encoding="utf-8").read()
    splice_failures = check_splice(script, binary, out)
    parts = re.split(r"^## ", text, flags=re.M)[1:]
    found = {p.splitlines()[0].strip(): p for p in parts}
    failures = []
    # Each part's fnopt runs show their progress under the part's name.
    if not re.search(r"^    frontier-12: compare .*% elapsed .* ETA ", r.stdout, flags=re.M):
        failures.append("the script's output shows no progress of frontier-12's compare")
    for title in SECTIONS:
        body = found.get(title)
        if body is None:
            failures.append("no section '%s'" % title)
            continue
        if title == "Against ARCSim" and "Skipped" in body:
            continue  # no ARCSim runs in the repository
        if title != "The paper's tables beside ours" and "```\nfnopt " not in body:
            failures.append("section '%s' is not headed by its command" % title)
        rows = [l for l in body.splitlines() if l.startswith("| ")]
        if len(rows) < 2:
            failures.append("section '%s' has no table rows" % title)
        elif any(set(c.strip()) <= {"—", ""} for c in rows[1].strip("|").split("|")[:1]):
            failures.append("section '%s': an empty first cell" % title)
    # The contact section's second table: every method's CPU ms/frame per scene, a number in each cell.
    contact = found.get("Contact with obstacles", "")
    cost_block = contact.split("ms/frame (12²)", 1)[1].split("\n\n", 1)[0] if "ms/frame (12²)" in contact else ""
    cost_rows = [l for l in cost_block.splitlines()[1:] if l.startswith("| ") and "---" not in l]
    if not cost_rows or any(not re.match(r"^[\d.e+-]+$", c.strip()) for l in cost_rows
                            for c in l.strip("|").split("|")[2:]):
        failures.append("section 'Contact with obstacles' has no cost table (ms/frame per scene)")
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    if not pictures:
        failures.append("no pictures")
    failures += ["picture %s is not beside results.md" % p for p in pictures
                 if not os.path.exists(os.path.join(out, p))]
    for f in failures:
        print("results.md: " + f)
    for f in splice_failures:
        print(f)
    return 1 if failures or guard_failures or splice_failures else 0


if __name__ == "__main__":
    sys.exit(main())
