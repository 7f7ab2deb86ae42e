"""Time homogenisation of a sliding run, eq. (6.2): which part of mu(t) is averaged, and whether
that part is stationary.

Two rules:

* fixed (thesis 6.2.3): the window is the sliding distance after ``window_start`` of a fixed
  distance (the thesis includes the micro run-in on purpose in its two-sine case);
* converged (periodic cells): the run slides whole periods of the cell (length L) and stops when
  the mean mu of the window's periods (the last ``window_periods``) and of the period before
  them differ by at most a relative tolerance; the window is averaged.  A run that does not get there within its distance budget is
  marked unconverged and never averaged silently.

Whatever the rule, every result says how stationary its window is: the window drift, the mean of
the window's second half minus that of its first half over the window mean (distance-weighted),
and an estimate of the averaging error of the window mean against the steady value.
"""

from __future__ import annotations

import math

import numpy as np


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


def window_drift(s: np.ndarray, mu: np.ndarray, lo: float, hi: float) -> float:
    """(mean of the window's second half - mean of its first half) / window mean."""
    mid = 0.5 * (lo + hi)
    mean = weighted_mean(s, mu, lo, hi)
    second, first = weighted_mean(s, mu, mid, hi), weighted_mean(s, mu, lo, mid)
    return (second - first) / abs(mean) if mean else math.nan


#: below this |mu| the convergence test is absolute (tol * MU_FLOOR): an elastic, frictionless
#: run has mu ~ 0 and round-off noise in its period means
MU_FLOOR = 1e-5


def is_converged(means: np.ndarray, tol: float, window_periods: int) -> bool:
    """The means of the window's ``window_periods`` periods and of the period before it differ
    by at most ``tol`` relative to their mean (or to MU_FLOOR).

    Two agreeing periods are not enough: micro runs rise to a plateau of two periods after the
    run-in and then fall by a factor of two or three (default road, micro2 at 10 mm/s: period
    means 0.48, 1.047, 1.055, then falling; 0.33, 0.762, 0.748, 0.28, ...), which the former
    two-period rule took for a steady state."""
    n = max(window_periods, 1) + 1
    if means.size < n:
        return False
    last = means[-n:]
    return bool(np.ptp(last) <= tol * max(abs(float(np.mean(last))), MU_FLOOR))


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
    return err / abs(window_mean) if window_mean else math.nan
