"""Progress output for long campaigns: runs done / total, the runs in flight, time left.

One status line, e.g. (one line; wrapped here)::

    [14/42]  33%  computed 9  reused 5  failed 1  elapsed 2m05s  left ~41m  | c/p=0.3/v=100 up
      micro1 1  | running: micro2 up #0 v=100: 0.42/1.2 mm, step 84/240, 3 cut-backs, ~2m10s

and on a terminal, redrawn in place, times and runs in flight first::

    [14/42]  33%  2m05s, left ~41m  | micro2 up #0 v=100: 0.42/1.2 mm, step 84/240, 3
      cut-backs, ~2m10s  | computed 9, reused 5, failed 1

The line moves when a run finishes and while runs are in flight: a runner that reports
(``driver.sliding.progress.StepReporter`` through
:class:`~rubberfriction.driver.runtime.farm.RunReports`, also from MPI worker ranks) says after
each sliding step how far it is, and :meth:`Progress.running` keeps the latest report per run.

Terminal output (:func:`terminal`): on a TTY the line is redrawn in place (carriage return, cut
to the terminal width) at most every ``min_interval`` seconds, and a failed run leaves a line of
its own; into a file or pipe (and under mpirun, unless ``RF_PROGRESS=tty``) plain lines are
printed, one per finished run (at most one every ``min_interval`` seconds, plus the last) and,
while nothing finishes, one every ``plain_interval`` seconds.  ``quiet=True`` prints nothing
(scripts); the campaign still writes its report.

Time left (:meth:`Progress.eta`).  With the planner's plan (its stages, :class:`Stage`) each run
still to do is costed by :class:`CostEstimate` from the finished runs of the same group (branch
and scale), else of the same scale, else from its model weight (``sliding.spec.cost_model``)
relative to all finished runs; a run in flight by its expected cost less the time it has run,
blended with its own report (distance left at its rate so far) by the fraction of the distance
done.  The estimate is the larger of (work left) / workers and the longest chain of stages
still to run one after another (the cascade of one point: scale i+1 needs all samples of scale
i), so a few expensive lower-scale runs that cannot run side by side are not spread over idle
workers.  Without a plan: runs left x mean computed wall time / workers.  Reused runs cost
nothing; runs the store will answer are not known in advance, so a resumed campaign's first
estimate is high.  "?" until a run was computed.
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import time
from dataclasses import dataclass
from typing import Any, Callable, Mapping, TextIO


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


# ----------------------------------------------------------------------------------------------
# the plan and the cost estimate
# ----------------------------------------------------------------------------------------------


def stage_key(label: Mapping[str, Any]) -> tuple:
    """Which stage a task belongs to, from its label: (point, branch, scale)."""
    return (label.get("point"), label.get("branch"), label.get("scale"))


@dataclass(frozen=True)
class Stage:
    """Runs a planner hands out together (its ``plan()``; for the time estimate only).

    ``chain``: stages of one chain run one after the other (the stages of one point), chains run
    side by side.  ``key``: :func:`stage_key` of the stage's task labels.  ``group``: (branch,
    scale name), runs of one group are expected to cost alike.  ``runs``: how many.  ``weight``:
    model cost of one run, any unit shared by the whole plan (1 when unknown).
    """

    chain: str
    key: tuple
    group: tuple[str, str]
    runs: int
    weight: float = 1.0


class CostEstimate:
    """Expected wall time of a run from the runs finished so far.

    :meth:`expect` answers, in order: the mean wall time of finished runs of the same group
    (branch, scale); of the same scale (the other branch); the run's weight times (sum of wall
    times / sum of weights) of all finished runs.  NaN before the first observation.
    """

    def __init__(self) -> None:
        # ("group", (branch, scale)) and ("scale", scale) -> [sum of wall times, runs]
        self._sums: dict[tuple, list[float]] = {}
        self._wall = self._weight = 0.0

    @staticmethod
    def _keys(group: tuple[str, str]) -> tuple[tuple, tuple]:
        return ("group", group), ("scale", group[1])

    def observe(self, group: tuple[str, str], weight: float, wall: float) -> None:
        """A run of ``group`` and model ``weight`` finished after ``wall`` seconds."""
        for key in self._keys(group):
            acc = self._sums.setdefault(key, [0.0, 0.0])
            acc[0] += wall
            acc[1] += 1.0
        if weight > 0:
            self._wall += wall
            self._weight += weight

    def expect(self, group: tuple[str, str], weight: float) -> float:
        """Expected wall seconds of one run of ``group`` with model ``weight``."""
        for key in self._keys(group):
            if key in self._sums:
                wall, runs = self._sums[key]
                return wall / runs
        if self._weight > 0 and weight > 0:
            return weight * self._wall / self._weight
        return math.nan


@dataclass
class _InFlight:
    task: Any
    info: dict
    started: float  # clock of the first report
    seen: float  # clock of the latest report


def time_left(stages: list[Stage], left: Mapping[tuple, int], running: list[_InFlight],
              estimate: CostEstimate, workers: int, now: float) -> float:
    """Estimated seconds until the runs of ``stages`` still ``left`` are done (module docstring):
    max(work / workers, longest chain).  NaN while a stage cannot be costed yet."""
    live: dict[tuple, list[_InFlight]] = {}
    for r in running:
        live.setdefault(stage_key(r.task.label), []).append(r)
    work, chains = 0.0, {}
    for st in stages:
        n = left.get(st.key, 0)
        if n <= 0:
            continue
        cost = estimate.expect(st.group, st.weight)
        if math.isnan(cost):
            return math.nan
        rest = [_rest(r, cost, now) for r in live.get(st.key, [])[:n]]
        queued = n - len(rest)
        work += sum(rest) + queued * cost
        chains[st.chain] = chains.get(st.chain, 0.0) + max(rest + ([cost] if queued else []))
    return max(work / max(workers, 1), max(chains.values(), default=0.0))


def _rest(r: _InFlight, cost: float, now: float) -> float:
    """Seconds left of a run in flight: the expected cost less the time it has run, blended with
    the run's own estimate (aged since it came) by the fraction of the distance done -- a run's
    rate over its first steps says little (compression, run-in), over most of the distance a lot.
    """
    expected = max(cost - (now - r.started), 0.0) if math.isfinite(cost) else math.nan
    own = r.info.get("left", math.nan)
    if not (isinstance(own, (int, float)) and math.isfinite(own)):
        return expected
    own = max(float(own) - (now - r.seen), 0.0)
    if math.isnan(expected):
        return own
    total = float(r.info.get("slide_distance", 0.0) or 0.0)
    done = min(max(float(r.info.get("distance", 0.0)) / total, 0.0), 1.0) if total > 0 else 1.0
    return done * own + (1.0 - done) * expected


# ----------------------------------------------------------------------------------------------
# the status line
# ----------------------------------------------------------------------------------------------


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def run_name(label: Mapping[str, Any]) -> str:
    """Short name of a run in flight: 'micro2 up #0 v=100' (v: the run's own velocity, e.g. of a
    micro grid run of the separated variant, else its point's)."""
    parts = [str(label[k]) for k in ("scale_name", "branch") if k in label]
    if "sample" in label:
        parts.append(f"#{label['sample']}")
    v = label.get("velocity_in", label.get("velocity"))
    if v is not None:
        parts.append(f"v={v:g}")
    return " ".join(parts) or "run"


def describe(label: Mapping[str, Any], info: Mapping[str, Any], left: float) -> str:
    """One run in flight: where it is and its time left."""
    text = f"{run_name(label)}: "
    if info.get("phase") == "sliding":
        text += (f"{info.get('distance', 0.0):.3g}/{info.get('slide_distance', 0.0):.3g} mm, "
                 f"step {info.get('step', 0)}/{info.get('steps', 0)}, "
                 f"{_count(int(info.get('cutbacks', 0)), 'cut-back')}, "
                 + (f"{int(info['stabilised'])} stabilised, " if info.get("stabilised") else "")
                 + f"~{format_seconds(left)}")
    else:
        text += str(info.get("phase") or "set-up")
    if info.get("after"):
        text += f" (after {info['after']} failed)"
    return text


#: environment variables set in processes an MPI launcher started
MPI_LAUNCHED = ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK")


def terminal(stream: TextIO) -> bool:
    """Whether to redraw the status line in place on ``stream``.

    ``RF_PROGRESS=tty`` or ``plain`` decides; otherwise a TTY stream, except under an MPI
    launcher: Open MPI hands its processes a pseudo-terminal whatever mpirun's output goes to
    (``scripts/run.sh`` sets RF_PROGRESS from its own output and COLUMNS for the width).
    """
    choice = os.environ.get("RF_PROGRESS", "").strip().lower()
    if choice in ("tty", "plain"):
        return choice == "tty"
    if any(v in os.environ for v in MPI_LAUNCHED):
        return False
    isatty = getattr(stream, "isatty", None)
    return bool(isatty()) if callable(isatty) else False


class Progress:
    """Counts finished runs, follows runs in flight and prints the status line (module
    docstring).  All methods are called from one thread (the farm's dispatcher on rank 0)."""

    #: runs in flight shown on one line (more: "+N more")
    SHOW_RUNNING = 4

    def __init__(self, quiet: bool = False, stream: TextIO | None = None, min_interval: float = 1.0,
                 clock: Callable[[], float] = time.monotonic, tty: bool | None = None,
                 plain_interval: float = 30.0, title: str = "campaign",
                 unusable: Callable[[Any], str] | None = None):
        self.quiet = quiet
        # why a successful run does not enter the averages ("" if it does; the campaign's
        # statistics.why_unusable): counted and named like a failure, because it is a failed
        # sample to its point (an unconverged or over-stabilised run)
        self.unusable = unusable
        self.title = title  # what the start and end lines call the runs' set
        self.stream = stream if stream is not None else sys.stdout
        self.min_interval = min_interval
        self.plain_interval = plain_interval
        self.clock = clock
        self.tty = terminal(self.stream) if tty is None else tty
        self.total = 0
        self.workers = 1
        self.done = self.computed = self.reused = self.failed = self.timed_out = 0
        self.left_out = 0  # successful runs that the ``unusable`` predicate leaves out
        self.compute_time = 0.0
        self.t0 = clock()
        self._last = -1e30
        self._open_line = False  # a TTY line waits for its newline
        self.stages: dict[tuple, Stage] | None = None
        self.left: dict[tuple, int] = {}
        self.estimate = CostEstimate()
        self.in_flight: dict[str, _InFlight] = {}

    # --- farm interface --------------------------------------------------------------------
    def start(self, total: int, workers: int, plan: list[Stage] | None = None) -> None:
        self.total, self.workers = int(total), max(1, int(workers))
        self.t0 = self.clock()
        if plan is not None:
            self.stages = {st.key: st for st in plan}
            self.left = {st.key: st.runs for st in plan}
        if not self.quiet:
            self._print(f"{self.title}: {self.total} single-scale runs on {self.workers} worker(s)")

    def running(self, task: Any, info: Mapping[str, Any]) -> None:
        """The latest report of a run in flight (a dict, see ``driver.sliding.progress``)."""
        now = self.clock()
        r = self.in_flight.get(task.key)
        if r is None:
            self.in_flight[task.key] = _InFlight(task, dict(info), now, now)
        else:
            r.info, r.seen = dict(info), now
        if self.quiet:
            return
        if now - self._last >= (self.min_interval if self.tty else self.plain_interval):
            self._show(None, now)

    def update(self, task: Any, outcome: Any) -> None:
        """A run finished (or was answered by the store)."""
        self.done += 1
        self.in_flight.pop(getattr(task, "key", None), None)
        label = getattr(task, "label", None) or {}
        stage = self.stages.get(stage_key(label)) if self.stages is not None else None
        if stage is not None:
            self.left[stage.key] -= 1
        if getattr(outcome, "reused", False):
            self.reused += 1
        else:
            wall = float(getattr(outcome, "wall_time", 0.0))
            self.computed += 1
            self.compute_time += wall
            if stage is not None:
                self.estimate.observe(stage.group, stage.weight, wall)
        ok = getattr(outcome, "status", "ok") == "ok"
        why = self.unusable(outcome) if ok and self.unusable is not None else ""
        if not ok:
            self.failed += 1
            self.timed_out += getattr(outcome, "failure", "") == "timeout"
        elif why:
            self.left_out += 1
        if self.quiet:
            return
        # a failure or a left-out run gets a line of its own, then the status again
        force = (not ok or bool(why)) and self.tty
        if force:
            reason = (getattr(outcome, "reason", "") or "").splitlines()
            self._print(f"failed: {run_name(label)}: {reason[0] if reason else ''}" if not ok
                        else f"left out: {run_name(label)}: {why}")
        now = self.clock()
        if now - self._last < self.min_interval and self.done < self.total and not force:
            return
        self._show(task, now)

    def finish(self) -> None:
        if self.quiet:
            return
        stopped = f", {self.timed_out} stopped by the wall clock" if self.timed_out else ""
        left_out = (f", {self.left_out} left out (unconverged or over-stabilised)"
                    if self.left_out else "")
        not_run = (f"; {self.total - self.done} of {self.total} planned runs not needed (their "
                   f"point stopped at a failed scale)" if self.done < self.total else "")
        self._print(f"{self.title} done: {self.done} runs ({self.computed} computed, {self.reused} "
                    f"reused, {self.failed} failed{stopped}{left_out}) in "
                    f"{format_seconds(self.clock() - self.t0)}{not_run}")

    # --- estimate and text -----------------------------------------------------------------
    def eta(self) -> float:
        """Estimated seconds left (NaN before the first computed run)."""
        if self.done >= self.total and not self.in_flight:
            return 0.0
        if self.stages is not None:
            return time_left(list(self.stages.values()), self.left, list(self.in_flight.values()),
                             self.estimate, self.workers, self.clock())
        if self.computed == 0:
            return float("nan")
        left = max(self.total - self.done, 0)
        return left * (self.compute_time / self.computed) / self.workers

    def line(self, task: Any = None) -> str:
        """The plain status line; ``task``: the run that just finished."""
        text = f"{self._head()}  computed {self.computed}  reused {self.reused}  failed " \
               f"{self.failed}{self._left_out_text('  ')}  elapsed " \
               f"{format_seconds(self.clock() - self.t0)}  left ~{format_seconds(self.eta())}"
        label = getattr(task, "label", None)
        if label:
            text += "  | " + " ".join(str(label[k]) for k in ("point", "branch", "scale_name",
                                                              "sample")
                                      if k in label)
        if self.in_flight:
            text += "  | running: " + self._running_text()
        return text

    def tty_line(self) -> str:
        """The line redrawn on a terminal: times and the runs in flight first (a narrow terminal
        cuts the end), the counts last."""
        text = (f"{self._head()}  {format_seconds(self.clock() - self.t0)}, left "
                f"~{format_seconds(self.eta())}")
        if self.in_flight:
            text += "  | " + self._running_text()
        return text + (f"  | computed {self.computed}, reused {self.reused}, failed {self.failed}"
                       f"{self._left_out_text(', ')}")

    def _left_out_text(self, sep: str) -> str:
        """The left-out count for the status lines (nothing while there is none)."""
        return f"{sep}left out {self.left_out}" if self.left_out else ""

    def _head(self) -> str:
        w = len(str(max(self.total, 1)))
        pct = 100.0 * self.done / self.total if self.total else 100.0
        return f"[{self.done:>{w}}/{self.total:>{w}}] {pct:4.0f}%"

    def _running_text(self) -> str:
        now = self.clock()
        runs = sorted(self.in_flight.values(), key=lambda r: r.started)
        parts = []
        for r in runs[:self.SHOW_RUNNING]:
            stage = self.stages.get(stage_key(r.task.label)) if self.stages else None
            cost = self.estimate.expect(stage.group, stage.weight) if stage else math.nan
            parts.append(describe(r.task.label, r.info, _rest(r, cost, now)))
        if len(runs) > self.SHOW_RUNNING:
            parts.append(f"+{len(runs) - self.SHOW_RUNNING} more")
        return "; ".join(parts)

    # --- output ------------------------------------------------------------------------------
    def _show(self, task: Any, now: float) -> None:
        self._last = now
        if self.tty:
            width = shutil.get_terminal_size((100, 24)).columns
            self.stream.write("\r" + self.tty_line()[:max(width - 1, 20)] + "\x1b[K")
            self.stream.flush()
            self._open_line = True
        else:
            print(self.line(task), file=self.stream, flush=True)

    def _print(self, text: str) -> None:
        """A line of its own (ends a TTY status line first; the next update redraws it)."""
        if self._open_line:
            self.stream.write("\r\x1b[K")
            self._open_line = False
        print(text, file=self.stream, flush=True)
