"""Progress output for long campaigns: runs done / total, failures, reuse, estimated time left.

One line per finished run (at most one every ``min_interval`` seconds, plus the last), e.g.::

    [ 14/ 42]  33%  computed 9  reused 5  failed 1  elapsed 2m05s  left ~4m10s  | up micro2 #1 v=100

The estimate: remaining runs x mean wall time of the runs *computed* in this campaign (reused
runs cost nothing) / number of workers.  It is rough on the first runs and when scales differ a
lot in cost (macro runs are dearer than micro ones), and says "?" until one run was computed.
``quiet=True`` prints nothing (scripts); the campaign still writes its report.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO


def format_seconds(s: float) -> str:
    """'4m10s', '1h02m', '12s'."""
    if s != s or s < 0:  # NaN
        return "?"
    s = int(round(s))
    if s < 60:
        return f"{s}s"
    if s < 3600:
        return f"{s // 60}m{s % 60:02d}s"
    return f"{s // 3600}h{(s % 3600) // 60:02d}m"


class Progress:
    """Counts finished runs and prints progress lines (see the module docstring)."""

    def __init__(self, quiet: bool = False, stream: TextIO | None = None, min_interval: float = 1.0,
                 clock: Any = time.monotonic):
        self.quiet = quiet
        self.stream = stream if stream is not None else sys.stdout
        self.min_interval = min_interval
        self.clock = clock
        self.total = 0
        self.workers = 1
        self.done = self.computed = self.reused = self.failed = 0
        self.compute_time = 0.0
        self.t0 = clock()
        self._last = -1e30

    def start(self, total: int, workers: int) -> None:
        self.total, self.workers = int(total), max(1, int(workers))
        self.t0 = self.clock()
        if not self.quiet:
            print(f"campaign: {self.total} single-scale runs on {self.workers} worker(s)",
                  file=self.stream,
                  flush=True)

    def eta(self) -> float:
        """Estimated seconds left (NaN before the first computed run)."""
        if self.computed == 0:
            return float("nan") if self.done < self.total else 0.0
        left = max(self.total - self.done, 0)
        return left * (self.compute_time / self.computed) / self.workers

    def update(self, task: Any, outcome: Any) -> None:
        self.done += 1
        if getattr(outcome, "reused", False):
            self.reused += 1
        else:
            self.computed += 1
            self.compute_time += float(getattr(outcome, "wall_time", 0.0))
        if getattr(outcome, "status", "ok") != "ok":
            self.failed += 1
        if self.quiet:
            return
        now = self.clock()
        if now - self._last < self.min_interval and self.done < self.total:
            return
        self._last = now
        print(self.line(task), file=self.stream, flush=True)

    def line(self, task: Any = None) -> str:
        w = len(str(max(self.total, 1)))
        pct = 100.0 * self.done / self.total if self.total else 100.0
        text = (f"[{self.done:>{w}}/{self.total:>{w}}] {pct:4.0f}%  computed {self.computed}  "
                f"reused {self.reused}"
                f"  failed {self.failed}  elapsed {format_seconds(self.clock() - self.t0)}"
                f"  left ~{format_seconds(self.eta())}")
        label = getattr(task, "label", None)
        if label:
            text += "  | " + " ".join(str(label[k]) for k in ("point", "branch", "scale_name",
                                                              "sample")
                                      if k in label)
        return text

    def finish(self) -> None:
        if not self.quiet:
            print(f"campaign done: {self.done} runs ({self.computed} computed, {self.reused} "
                  f"reused, {self.failed} failed) in {format_seconds(self.clock() - self.t0)}",
                  file=self.stream,
                  flush=True)
