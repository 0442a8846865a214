"""The code of scripts/release-results.py, whose docstring says what it does and how to run it.

One module per results-page part, each with its part_* function and its own constants:
frontier, newton_cost, speed, superres, offcorner, arcsim, stability, contact, adjoint, paper.
The pieces they share, one idea a module:
  plan       what each part runs, in full and in --quick (frontier_runs, CONTACT_SCENES, plan())
  runner     running fnopt: logs, the progress echo, PartFailed, the command as docs show it
  files      atomic writes, CSV files
  tables     numbers as the tables show them, markdown tables, fnopt bench's printed tables
  compare    fnopt compare's flags and compare.csv: rows, per-method groups, the frontier summary
  assemble   results.md: a part's section, its pictures, the header and the page
  parts      the context every part gets, and the parts in order
  session    one run: the parts in order, --resume's state, the progress line per part
  cli        the command line: arguments, input checks (the binary's version too), SIGTERM, main()

Python 3 standard library only.
"""

import os

# The repository this package belongs to (scripts/release_results/ is two levels below it).
REPOSITORY = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
