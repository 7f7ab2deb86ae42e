"""Time homogenisation of a sliding run, eq. (6.2): which part of mu(t) is averaged, and whether
that part is stationary.

Two rules:

* fixed (thesis 6.2.3): the window is the sliding distance after ``window_start`` of a fixed
  distance (the thesis includes the micro run-in on purpose in its two-sine case);
* converged (periodic cells): the run slides whole periods of the cell (length L) and stops when
  the mean mu of its last w periods and that of the w before differ by at most a relative
  tolerance and the last w periods' own drift (second half against first half) is within twice
  it (:func:`converged_window`, w >= ``window_periods``, as small as passes); the last w
  periods are averaged.  A run that does not get there within its distance budget is
  marked unconverged and never averaged silently.

Whatever the rule, every result says how stationary its window is: the window drift, the mean of
the window's second half minus that of its first half over the window mean (distance-weighted),
and an estimate of the averaging error of the window mean against the steady value; for mu and for
the contact fraction.

What the converged rule waits for is what the run hands on (``WINDOW_QUANTITIES``): mu for the
friction branch, the contact fraction for the pressure branch.  A pressure-branch run passes the
pooled pressure of eq. (6.11) down, sum_t p_t A_t / sum_t A_t = p l / mean(A_t) with the load p l
held every step, so its window is stationary when the mean contact length is.  On the default
scene the two differ: mu of a frictionless micro1 run at 10 mm/s is steady after 5 periods (0.4885,
0.4908, 0.4872) while its contact fraction still falls 5 % per period (0.265, 0.242, 0.230) from
the larger contact the compression left.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


#: what the converged rule waits for -> the per-step series it tests (run.py's series names);
#: "both" where a friction-branch run's contact fraction is handed on too (the real contact area
#: A_r of eq. 7.5 of a scene with adhesion)
WINDOW_QUANTITIES = {"mu": ("mu_force",), "contact": ("contact_fraction",),
                     "both": ("mu_force", "contact_fraction")}


def step_lengths(s: np.ndarray) -> np.ndarray:
    """Sliding distance of each step from the cumulative distances ``s`` (first step from 0)."""
    return np.diff(np.concatenate([[0.0], np.asarray(s, dtype=float)]))


def weighted_mean(s: np.ndarray, mu: np.ndarray, lo: float, hi: float) -> float:
    """Distance-weighted mean of mu over the steps ending in (lo, hi] (eq. 6.2 as a sum)."""
    s, mu = np.asarray(s, dtype=float), np.asarray(mu, dtype=float)
    tol = 1e-9 * max(abs(hi), 1.0)
    m = (s > lo + tol) & (s <= hi + tol)
    ds = step_lengths(s)[m]
    return float(np.sum(mu[m] * ds) / ds.sum()) if ds.sum() > 0 else math.nan


def period_means(s: np.ndarray, mu: np.ndarray, period: float) -> np.ndarray:
    """Mean mu of every whole period (0, L], (L, 2L], ... that the steps cover."""
    n = int(math.floor(float(np.max(s, initial=0.0)) / period + 1e-9))
    return np.array([weighted_mean(s, mu, k * period, (k + 1) * period) for k in range(n)])


def window_drift(s: np.ndarray, mu: np.ndarray, lo: float, hi: float,
                 period: float = 0.0) -> float:
    """(mean of the window's second half - mean of its first half) / window mean.  A window of
    one ``period`` of a periodic cell (period > 0) after at least one period: (its mean - the mean
    of the period before) / its mean, since its halves are different stretches of the road."""
    tol = 1e-9 * max(abs(hi), 1.0)
    if period > 0.0 and abs(hi - lo - period) <= tol and lo >= period - tol:
        mean = weighted_mean(s, mu, lo, hi)
        before = weighted_mean(s, mu, lo - period, lo)
        return (mean - before) / abs(mean) if mean else math.nan
    mid = 0.5 * (lo + hi)
    mean = weighted_mean(s, mu, lo, hi)
    second, first = weighted_mean(s, mu, mid, hi), weighted_mean(s, mu, lo, mid)
    return (second - first) / abs(mean) if mean else math.nan


#: below this |mu| the convergence test is absolute (tol * MU_FLOOR): an elastic, frictionless
#: run has mu ~ 0 and round-off noise in its period means
MU_FLOOR = 1e-5


#: the converged rule's bound on the window drift (second half against first half of the averaged
#: window, relative to its mean), as a multiple of the block tolerance: 2 % at the default 1 %
DRIFT_FACTOR = 2.0


#: periodic cells compare one-period blocks at this part of the tolerance
#: (``converged_window``'s ``one_period``): a linear drift then passes for the same d <= tol / 2
#: per period as two-period blocks at the whole tolerance
ONE_PERIOD_TOL = 0.5


def converged_window(means: np.ndarray, tol: float, window_periods: int,
                     halves: np.ndarray | None = None, run_in: int = 1,
                     one_period: float = 1.0) -> int:
    """The number w of last periods to average, 0 while the period means are not stationary.

    Stationary: the mean of the last w periods and that of the w before them differ by at most
    ``tol`` relative to their mean (or to MU_FLOOR), for the smallest w >= ``window_periods``
    for which the periods after the first hold both blocks.  The first period, the run-in from
    rest, never enters a block: with it, 0.3045, 0.7153 against 0.7437, 0.2732 (a micro2 run's
    first four periods) agree within 0.3 %.  Comparing blocks rather than single periods tells
    noise from a trend: noise averages down as the blocks grow, a trend separates them
    further.  Needed on the default road's micro runs, whose period means scatter by +-3 %
    (stabilised sub-steps, active-set changes) and which rise to a plateau of two periods after
    the run-in before falling by a factor of two or three (micro2 at 10 mm/s: 0.48, 1.047,
    1.055, where the sample slid on settles at 0.24-0.28; 0.33, 0.762, 0.748, 0.28, ...), which
    the former rule (the last two periods within tol) took for a steady state.

    ``halves``, the means of every half period (twice as many as ``means``), adds the window's
    own drift: the mean of the window's second half and that of its first half must agree within
    DRIFT_FACTOR * tol too.  Two blocks can agree by coincidence while the window itself falls:
    0.2605, 0.2347 against 0.2746, 0.2250 (a micro run at 1000 mm/s) agree within 1 % while the
    window drifts by -20 %; a linear trend, by contrast, fails the block test first (its blocks
    differ by twice the window's drift).

    ``means`` of several quantities (one row each, e.g. mu and the contact fraction): the same
    w must pass for every row (and ``halves`` then has a row per quantity too).

    ``run_in``: the first periods that never enter a block; 0 for a run that starts from an
    earlier run's state (``spec.InitialState``) rather than from rest.

    ``window_periods`` = 1 (the thermal loop's warm runs may ask for it, a trade of accuracy for
    time): the last period against the one before; the two halves of one period are different
    stretches of the road, so the drift test compares each half with the same half of the period
    before instead.  A trend of d per period then passes the block test for d <= tol (w = 2:
    d <= tol / 2).  ``one_period`` < 1 compares one-period blocks (and their halves) at that
    part of the tolerance: with ONE_PERIOD_TOL a trend passes w = 1 for the same d <= tol / 2 as
    w = 2, so a run that is stationary after its run-in stops after 3 periods instead of 5 with
    the same bound on its drift (the sliding runs' ``Periods``)."""
    rows = np.atleast_2d(np.asarray(means, dtype=float))
    half = None if halves is None else np.atleast_2d(np.asarray(halves, dtype=float))
    n = rows.shape[1] - run_in  # the run-in periods are not compared
    for w in range(max(window_periods, 1), n // 2 + 1):
        tol_w = tol * one_period if w == 1 else tol
        a, b = rows[:, -w:].mean(axis=1), rows[:, -2 * w:-w].mean(axis=1)
        if not np.all(np.abs(a - b) <= tol_w * np.maximum(np.abs(0.5 * (a + b)), MU_FLOOR)):
            continue
        if half is not None:
            if w == 1:  # one period's halves are different stretches of road: each half
                second, first = half[:, -2:], half[:, -4:-2]  # against the same half before
            else:
                second, first = half[:, -w:].mean(axis=1), half[:, -2 * w:-w].mean(axis=1)
            scale = np.maximum(np.abs(0.5 * (first + second)), MU_FLOOR)
            if not np.all(np.abs(second - first) <= DRIFT_FACTOR * tol_w * scale):
                continue
        return w
    return 0


def earliest_convergence(means: np.ndarray, window_periods: int, run_in: int = 1) -> int:
    """The fewest whole periods after which :func:`converged_window` can pass, given the period
    means so far.  A period without a finite mean (a step whose contact carries no load: mu is
    undefined) cannot lie in either block, so at least 2 ``window_periods`` periods must follow
    the last such period, as they must follow the run-in.  A run whose budget ends sooner can
    stop at once: sliding on cannot converge (the default scene's micro2 run at 63 MPa had
    such periods 3 to 11 of 12).  ``run_in`` as in :func:`converged_window`."""
    rows = np.atleast_2d(np.asarray(means, dtype=float))
    bad = np.nonzero(~np.all(np.isfinite(rows[:, run_in:]), axis=0))[0]
    # the last period that cannot be compared (1-based)
    last = int(bad[-1]) + 1 + run_in if bad.size else run_in
    return last + 2 * max(int(window_periods), 1)


def error_estimate(means: np.ndarray, window_periods: int) -> float:
    """Estimated |window mean - steady value| / |window mean| for a run of whole periods.

    The period means approach the steady value geometrically with the ratio r of their last two
    differences (bounded by 0.9 where it cannot be measured or does not contract); the window
    mean lies about half the last difference behind the last period, which itself is
    r / (1 - r) times the last difference from the limit."""
    if means.size < 2:
        return math.nan
    d = means[-1] - means[-2]
    r = 0.9
    if means.size >= 3 and means[-2] != means[-3]:
        r = min(abs(d / (means[-2] - means[-3])), 0.9)
    window_mean = float(np.mean(means[-window_periods:]))
    lag = 0.5 * (window_periods - 1)  # periods between the window's centre and its last period
    err = abs(d) * (lag + r / (1.0 - r))
    return err / abs(window_mean) if window_mean and math.isfinite(err) else math.nan


#: the stationary mean's default: blocks of the slide compared by the converged rule
STATIONARY_BLOCKS = 10


@dataclass(frozen=True)
class StationaryMean:
    """The time average of a series over its stationary part (:func:`stationary_mean`): the mean
    over (lo, hi] of the sliding distance, that window's drift (second half against first half
    over the mean), the blocks averaged, and whether the converged rule passed (False: the mean
    is over the last half of the slide and is NOT a stationary value)."""

    mean: float
    lo: float
    hi: float
    drift: float
    blocks: int
    stationary: bool

    def describe(self) -> str:
        """One line for logs and notes."""
        what = "stationary" if self.stationary else "NOT stationary (no window passed; last half)"
        return (f"mean over s = {self.lo:.4g}-{self.hi:.4g} mm ({self.blocks} blocks), drift "
                f"{100 * self.drift:+.2g} %, {what}")


def stationary_mean(s: np.ndarray, y: np.ndarray, blocks: int = STATIONARY_BLOCKS,
                    tol: float = 0.01, window_blocks: int = 1) -> StationaryMean:
    """Time average of ``y`` (one value per step ending at sliding distance ``s``) over the
    stationary part of a slide (thesis 8.5.3: time homogenisation after the macro mu became
    stationary), by the converged rule of the periodic runs (:func:`converged_window`) on
    ``blocks`` equal blocks of the slide (0, s_end] in place of periods: the first block is the
    run-in; the last w blocks are averaged for the smallest w >= ``window_blocks`` whose mean
    agrees with the w blocks before within ``tol`` (relative) and whose halves agree within
    DRIFT_FACTOR * tol.  None passing: the mean of the last half of the slide, marked not
    stationary (so always with fewer than 4 blocks: a run-in and two blocks to compare).  A series
    that drifts linearly by d per block passes only for d <= tol (w = 1)."""
    s, y = np.asarray(s, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(y)
    if s.size == 0 or not keep.any():
        return StationaryMean(math.nan, math.nan, math.nan, math.nan, 0, False)
    end = float(s[-1])
    length = end / blocks
    means = period_means(s, y, length)[:blocks]
    halves = period_means(s, y, 0.5 * length)[:2 * blocks]
    w = converged_window(means, tol, window_blocks, halves) if means.size == blocks else 0
    stationary = w > 0 and bool(np.all(np.isfinite(means[-2 * w:])))
    if not stationary:
        w = max(blocks // 2, 1)
    lo = end - w * length
    return StationaryMean(weighted_mean(s, y, lo, end), lo, end, window_drift(s, y, lo, end), w,
                          stationary)
