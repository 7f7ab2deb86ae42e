"""Period bookkeeping of a sliding run over a periodic cell (thesis 6.2.2, 6.4).

With the converged window rule or the steady-state jump, sliding steps end on every period
boundary.  At each step the state at its phase is kept (the "period" Newton start of
``driver.sliding.steps``); at each period end the converged-window rule of
``driver.sliding.window`` is tested, a run that cannot pass it in its budget or before its
wall-time limit is stopped, and the steady-state history jump (``steady_state``) is taken.
"""

from __future__ import annotations

import math
import time

import numpy as np

from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.sliding.steps import WallLimit
from rubberfriction.driver.sliding.slowmode import CREEP_ELEMENTS
from rubberfriction.driver.sliding.window import (
    MU_FLOOR,
    ONE_PERIOD_TOL,
    WINDOW_QUANTITIES,
    converged_window,
    earliest_convergence,
    period_means,
)

#: an extrapolation must move mu or the contact fraction by at least this part of the window
#: rule's tolerance (predicted: omega times the last period's relative change)
EXTRAPOLATION_WORTH = 0.5


def whole_periods(spec: SlidingSpec) -> bool:
    """Whether sliding steps end on every period boundary (a periodic cell under the converged
    window rule or the steady-state jump)."""
    return spec.period > 0 and (spec.converge_tol > 0 or spec.steady_state)


def sliding_step(spec: SlidingSpec, L: float, step_len: float) -> float:
    """The sliding step length: ``step_len``, or with whole periods the nearest length that
    divides the period L."""
    if whole_periods(spec):
        return L / max(1, round(L / step_len))
    return step_len


class Periods:
    """The periods of one attempt's sliding phase: per-phase states, the window rule's verdict
    (``converged``, ``window_used``), the steady-state history jump and the pace per period.

    One-period windows (``spec.window_periods = 1``) are compared at ONE_PERIOD_TOL of the
    tolerance (``window.converged_window``) and only where the contact face (``face``, a
    ``slowmode.FaceCreep``) crept by at most CREEP_ELEMENTS contact elements over the last
    period; otherwise the window needs two periods or more."""

    def __init__(self, spec: SlidingSpec, L: float, step_len: float, nsteps: int, history,
                 warm: bool, wall_limit: float, slow_mode=None, equilibrate=None, face=None):
        self.slow_mode = slow_mode  # SlowModeExtrapolation after each jump, or None
        # the contact face's mean x-displacement in contact elements (slowmode.FaceCreep), or
        # None; at the period start and its change over the last period
        self.face = face
        self.face_start = face() if face is not None else math.nan
        self.face_creep = math.nan
        self.equilibrate = equilibrate  # equilibrate(road shift) -> converged, for slow_mode
        self.road_shift = 0.0  # the road's offset moved with the extrapolated contact face
        self.spec, self.L, self.nsteps, self.wall_limit = spec, L, nsteps, wall_limit
        self.per_period = round(L / step_len) if whole_periods(spec) else 0
        # converged states of the last period by phase (the "period" Newton start) and the
        # change of the state since one period earlier at the last step
        self.phase_x: list[np.ndarray | None] = [None] * self.per_period
        self.drift: np.ndarray | None = None
        self.history = history if spec.steady_state else None
        self.start = self.history.snapshot() if self.history is not None else None
        self.converged = math.nan  # converged window rule: 1 stationary, 0 not (yet)
        self.window_used = 0  # periods averaged once stationary (driver.sliding.window)
        self.run_in = 0 if warm else 1  # periods from rest the window rule leaves out
        self.out_of_reach = ""  # why the window rule cannot pass within the budget
        self.period_wall = time.perf_counter()  # wall clock at the last period end

    def guess(self, k: int) -> np.ndarray | None:
        """The "period" Newton start of sliding step k: the state one period earlier at the same
        phase plus the drift between the periods at the step before (None before it exists)."""
        if not self.per_period:
            return None
        slot = k % self.per_period
        if self.phase_x[slot] is None or self.drift is None:
            return None
        return self.phase_x[slot] + self.drift

    def record(self, k: int, x_now: np.ndarray) -> None:
        """The converged state of step k at its phase, and its change since one period earlier."""
        if not self.per_period:
            return
        slot = k % self.per_period
        self.drift = None if self.phase_x[slot] is None else x_now - self.phase_x[slot]
        self.phase_x[slot] = x_now.copy()

    def end_of_step(self, k: int, rows: list, t: float, deadline: float) -> bool:
        """After sliding step k (``rows`` the series so far): at a period end, the window rule,
        the projection of the wall time and the steady-state jump.  True: sliding stops here
        (stationary, or the window out of reach: ``out_of_reach`` says why)."""
        if not (self.per_period and k % self.per_period == 0):
            return False
        s = self.spec
        if self.face is not None:
            self.face_creep = self.face() - self.face_start
        if s.converge_tol > 0:
            stationary, earliest = self._window_test(rows)
            if stationary:
                return True
            if earliest > self.nsteps // self.per_period:
                self.out_of_reach = self._out_of_reach(k, earliest)
                return True
            self._project_wall_time(k // self.per_period, earliest, t, deadline)
        if self.history is not None and k < self.nsteps:
            self.history.extrapolate_periodic(self.start)
            if self.slow_mode is not None:
                self._extrapolate(k, rows)
            self.start = self.history.snapshot()
        if self.face is not None:  # the next period's start (after an extrapolation)
            self.face_start = self.face()
        return False

    def _extrapolate(self, k: int, rows: list) -> None:
        """The slow-mode extrapolation of the period start (``driver.sliding.slowmode``), where
        it is worth it: omega times the last period's change of mu or the contact fraction at
        least half the window rule's tolerance (``EXTRAPOLATION_WORTH``; else the run is about
        stationary and an extrapolation would only restart its window).  The states one period
        earlier by phase move with it, and the window rule compares only the periods after it
        (it changes the state without work), so none is made where the budget has no room
        for a window after it."""
        done, budget = k // self.per_period, self.nsteps // self.per_period
        if budget - done < 2 * max(self.spec.window_periods, 1):
            return
        change, tol = self._last_change(rows), self.spec.converge_tol

        def worth(omega: float) -> bool:
            return omega * change >= EXTRAPOLATION_WORTH * tol

        moved = self.slow_mode.after_jump(self.equilibrate, worth)
        if moved is None:
            return
        dx, shift = moved
        self.road_shift += shift
        for x in self.phase_x:
            if x is not None:
                x += dx
        self.run_in = done

    def _last_change(self, rows: list) -> float:
        """The larger relative change of the period means of mu and of the contact fraction
        from the period before the last to the last (0 before two periods)."""
        if len(rows) < 2:
            return 0.0
        slid, q = self._series(rows)
        out = 0.0
        for quantity in q.values():
            m = period_means(slid, quantity, self.L)
            if len(m) >= 2 and np.all(np.isfinite(m[-2:])):
                out = max(out, abs(m[-1] - m[-2]) / max(abs(m[-1]), MU_FLOOR))
        return float(out)

    def exclude(self, seconds: float) -> None:
        """Time spent outside the run's own work does not count in a period's pace."""
        self.period_wall += max(float(seconds), 0.0)

    def _series(self, rows: list) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """The distance slid and the quantities the window rule can wait for, per step."""
        arr = np.array([r[1:5] for r in rows])  # s, Fx, Fz, contact length
        with np.errstate(divide="ignore", invalid="ignore"):  # no load: mu is NaN
            q = {"mu_force": -arr[:, 1] / arr[:, 2], "contact_fraction": arr[:, 3] / self.L}
        return arr[:, 0], q

    def _window_test(self, rows: list) -> tuple[bool, int]:
        """The converged-window rule on the period means so far: whether the run is stationary,
        and else the earliest period after which the rule can pass."""
        s, L = self.spec, self.L
        slid, q = self._series(rows)
        names = WINDOW_QUANTITIES[s.window_quantity]
        means = [period_means(slid, q[name], L) for name in names]
        halves = [period_means(slid, q[name], 0.5 * L) for name in names]
        # a creeping face is not periodic: then two periods or more
        fewest = max(s.window_periods, 2) if abs(self.face_creep) > CREEP_ELEMENTS \
            else s.window_periods
        self.window_used = converged_window(means, s.converge_tol, fewest, halves, self.run_in,
                                            one_period=ONE_PERIOD_TOL)
        self.converged = float(self.window_used > 0)
        if self.converged:
            return True, 0
        return False, earliest_convergence(means, s.window_periods, self.run_in)

    def _out_of_reach(self, k: int, earliest: int) -> str:
        after = "the run-in and " if self.run_in else ""
        return (f"no stationary window within the sliding budget: after period "
                f"{k // self.per_period} the window rule cannot pass before period {earliest} "
                f"of {self.nsteps // self.per_period} (it compares {2 * self.spec.window_periods}"
                f" periods after {after}after any period without a finite mean: no load on the "
                f"contact)")

    def _project_wall_time(self, done: int, earliest: int, t: float, deadline: float) -> None:
        """Stop a run that cannot reach a converged window before its wall-time limit: after
        ``done`` >= 2 whole periods (the run-in is not a pace), the periods still needed before
        the window rule can first pass (``earliest``, at least the next one) at the pace of the
        period that just ended take longer than the time left.  Such a run would be stopped by
        the limit anyway, later (a "timeout": recomputed on the next run of the scene)."""
        now = time.perf_counter()
        pace, self.period_wall = now - self.period_wall, now
        if self.wall_limit <= 0.0 or done < 2:
            return
        need = max(earliest, done + 1) - done
        left = deadline - now
        if need * pace > left:
            raise WallLimit(t, f"projected after period {done}: {need} more period(s) before "
                               f"a converged window is possible, at {pace:.0f} s per period, "
                               f"with {max(left, 0.0):.0f} s left")
