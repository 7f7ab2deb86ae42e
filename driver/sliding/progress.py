"""Where a sliding run is while it goes on, for a campaign's progress line.

:class:`StepReporter` is an observer of :class:`~rubberfriction.driver.sliding.run.SlidingRun`
(``run_sliding(spec, observers=[StepReporter(report)])``, what
``sliding_runner(progress=report)`` passes): after every converged sliding step it calls
``report`` with a small dict of plain values (picklable, a few hundred bytes)::

    phase           "sliding", or "set-up" after a failed attempt (the next one builds)
    step, steps     converged sliding steps of this attempt and their planned number
    distance        sliding distance done (mm) and slide_distance, the whole distance
    cutbacks        step halvings of this attempt so far
    stabilised      sub-steps of this attempt solved with viscous stabilisation so far
    after           the attempt that failed before this one ("" for the first attempt)
    left            estimated wall seconds left of this attempt: its sliding rate so far
                    times the distance left (NaN before the first step)

It calls on every step; the receiver rate-limits (``driver.runtime.farm.RunReports``).  Nothing
here changes the run: an observer that raises is dropped by the run with a warning.
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable


class StepReporter:
    """Observer reporting a sliding run's progress to ``report`` (see the module docstring)."""

    def __init__(self, report: Callable[[dict[str, Any]], None],
                 clock: Callable[[], float] = time.perf_counter):
        self.report = report
        self.clock = clock
        self.after = ""  # label of the last failed attempt of this run
        self._t0 = clock()

    def on_start(self, run: Any) -> None:
        """Sliding begins (run.t_start, run.slide_distance, run.n_slide_steps are set)."""
        self._t0 = self.clock()
        self._send(run, 0, run.t_start)

    def on_step(self, run: Any, k: int, t: float) -> None:
        self._send(run, k, t)

    def on_finish(self, run: Any, result: Any) -> None:
        """A failed attempt is followed by the next fallback unless the wall clock stopped it."""
        stats = getattr(result, "stats", {}) or {}
        if result.ok or stats.get("failure") == "wall_limit":
            return
        self.after = str(stats.get("attempt", ""))
        self.report({"phase": "set-up", "after": self.after,
                     "cutbacks": int(stats.get("cutbacks", 0))})

    def _send(self, run: Any, k: int, t: float) -> None:
        total = float(run.slide_distance)
        distance = float(run.spec.velocity) * (t - run.t_start)
        done = distance / total if total > 0 else 0.0
        elapsed = self.clock() - self._t0
        left = max(elapsed * (1.0 - done) / done, 0.0) if done > 0 else math.nan
        self.report({"phase": "sliding", "step": int(k), "steps": int(run.n_slide_steps),
                     "distance": distance, "slide_distance": total,
                     "cutbacks": int(run.cutbacks),
                     "stabilised": int(getattr(run, "stabilised_steps", 0)),
                     "after": self.after, "left": left})
