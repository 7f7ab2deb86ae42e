"""The command line as 0.27.0 ran sliding cells, for side-by-side comparisons (developer tool).

Leaves out the "column" Newton start (``driver.sliding.steps.ColumnShift``) and keeps a
campaign's h_contact as computed instead of the mesh's column width (so the step is half the
nominal element, not half a column).  Everything else is the installed code.

    /usr/bin/python3 scripts/without_column_start.py run four_scale --samples 1 1 --no-theory \
        --out DIR --fresh

docs/performance.md ("The column start") has the comparison this reproduces.
"""

from __future__ import annotations

import sys

from rubberfriction.driver.cli.main import main
from rubberfriction.driver.multiscale import specs
from rubberfriction.driver.sliding.run import SlidingRun

SlidingRun.START_CANDIDATES = tuple(c for c in SlidingRun.START_CANDIDATES if c != "column")
specs.contact_divisions = lambda period, _count, h_contact: period / h_contact

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
