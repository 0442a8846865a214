#!/usr/bin/python3
"""Regenerate the release's result tables (docs/results.md) from a built fnopt.

Runs every measurement the release reports, one part at a time, and writes each part's
outputs (the fnopt run's directory, a CSV of its table, a report section) under --out, then
assembles OUT/results.md: the current tables only, each headed by the exact command that made it.

Parts, in order:
  frontier-R   the error-time frontier at R^2 (fnopt compare, every current method and budget)
  newton-cost  the Newton reference's cost (fnopt bench newton --repeat N)
  speed        every method's cost with 1 and 2 threads beside fnopt 1.0's (fnopt bench speed)
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
exercised: a minute or two on 2 cores). The full run takes many hours on one thread per run (--jobs J runs the
contact part's scenes J at a time, each on its own thread, so give it J idle cores);
--resume keeps the parts already finished and passes --resume to compare and stability, which keep their finished
rows. --splice PAGE writes OUT/results.md as PAGE (the published docs/results.md) with the sections of the parts
this run ran put in place of PAGE's, its header and other sections as they were. A line per part says what is done
and left, with the run's ETA; under it, the part's fnopt runs print their progress (a line per 10 %, with their
own ETA); OUT/logs/ has their whole output. A part
that fails stops the run: exit status 1 and one line naming it. A full run refuses to start (exit status 2) when
the binary's `fnopt --version` is not the release's (project() in CMakeLists.txt), since results.md prints it as
the release's; --quick only warns.

The code is the package scripts/release_results/ beside this launcher, one module per part (its __init__.py
lists them). Python 3 standard library only.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from release_results.cli import main  # noqa: E402  (the package is found through the path above)

if __name__ == "__main__":
    sys.exit(main(__doc__))
