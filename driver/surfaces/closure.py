"""Periodic closure of a surface cutout with a connecting spline (thesis ch. 6.3.1, fig. 6.6 b).

A cutout of a long rough profile is not periodic: its ends differ in height and slope.  The
thesis manipulates "the samples at the ends by introducing a smooth spline function that
enforces a periodic surface sample".  Here the last part of the cutout, of length d (the
*closure length*, the modified length that is reported), is replaced by a cubic Hermite spline
that starts with the height and slope of the cutout at x = P - d and ends with the height and
slope of the cutout at x = 0, shifted by the period P.  The closed sample h_c therefore has

    h_c(P) = h_c(0)   and   h_c'(P) = h_c'(0),

i.e. its periodic extension is C1 across the period, and the period equals the cutout length
(the block length of the scale).

Choice of d: the shortest length (at least ``min_fraction`` of P and two points) for which the
spline is nowhere steeper than the steepest part of the cutout itself, so the closure does not
create a flank the real surface does not have; if no length up to ``max_fraction`` of P
achieves that, the length with the least steep spline is taken and ``within_slope_cap`` is
False.  A cutout that is already periodic (ends matching to 1e-9 of its rms) is left as it is.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from rubberfriction.driver.surfaces.errors import SurfaceError

__all__ = ["Closure", "close_periodic", "hermite", "hermite_slope", "hermite_max_slope"]


def hermite(t: np.ndarray, p0: float, p1: float, m0: float, m1: float, d: float) -> np.ndarray:
    """Cubic Hermite spline on [0, d] at t = (x - x0) / d: values p0, p1, slopes m0, m1 (per x)."""
    t = np.asarray(t, dtype=float)
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * d * m0
            + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * d * m1)


def hermite_slope(t: np.ndarray, p0: float, p1: float, m0: float, m1: float,
                  d: float) -> np.ndarray:
    """dh/dx of :func:`hermite` at t."""
    t = np.asarray(t, dtype=float)
    a = 6 * (p0 - p1) + 3 * d * (m0 + m1)
    b = -6 * (p0 - p1) - d * (4 * m0 + 2 * m1)
    return (a * t * t + b * t + d * m0) / d


def hermite_max_slope(p0: np.ndarray, p1: np.ndarray, m0: np.ndarray, m1: np.ndarray,
                      d: np.ndarray) -> np.ndarray:
    """max |dh/dx| of the Hermite spline over [0, d], vectorised over arrays of splines.

    dh/dt = a t^2 + b t + c is a parabola: its extreme on [0, 1] is at an end or at the vertex.
    """
    p0, p1, m0, m1, d = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (p0, p1, m0, m1, d))
    )
    a = 6 * (p0 - p1) + 3 * d * (m0 + m1)
    b = -6 * (p0 - p1) - d * (4 * m0 + 2 * m1)
    c = d * m0
    ends = np.maximum(np.abs(c), np.abs(a + b + c))
    with np.errstate(divide="ignore", invalid="ignore"):
        tv = -b / (2 * a)
        vertex = np.where((a != 0) & (tv > 0) & (tv < 1), np.abs(c - b * b / (4 * a)), 0.0)
    return np.maximum(ends, vertex) / d


@dataclass
class Closure:
    """The connecting spline of a closed sample (positions in the sample's own x, 0 .. P)."""

    x_start: float  #: where the spline starts, P - d (mm)
    length: float  #: closure length d, the modified part of the cutout (mm)
    n_points: int  #: grid points replaced by the spline
    h_start: float  #: spline value at x_start
    h_end: float  #: spline value at P (= h(0))
    slope_start: float  #: spline slope at x_start
    slope_end: float  #: spline slope at P (= h'(0))
    max_slope: float  #: max |dh/dx| of the spline
    slope_cap: float  #: max |dh/dx| of the cutout
    within_slope_cap: bool
    mismatch_height: float  #: |h(P) - h(0)| of the raw cutout (mm)
    mismatch_slope: float  #: |h'(P) - h'(0)| of the raw cutout

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Spline heights at x in [x_start, x_start + length]."""
        if self.length == 0:
            return np.full_like(np.asarray(x, dtype=float), self.h_end)
        t = (np.asarray(x, dtype=float) - self.x_start) / self.length
        return hermite(t, self.h_start, self.h_end, self.slope_start, self.slope_end, self.length)

    def slope(self, x: np.ndarray) -> np.ndarray:
        """Spline slopes dh/dx at x in [x_start, x_start + length]."""
        if self.length == 0:
            return np.full_like(np.asarray(x, dtype=float), self.slope_end)
        t = (np.asarray(x, dtype=float) - self.x_start) / self.length
        return hermite_slope(t, self.h_start, self.h_end, self.slope_start, self.slope_end,
                             self.length)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def close_periodic(
    h: np.ndarray,
    dx: float,
    *,
    slopes: np.ndarray | None = None,
    closure_length: float | None = None,
    min_fraction: float = 0.02,
    max_fraction: float = 0.25,
    slope_cap: float | None = None,
) -> tuple[np.ndarray, Closure]:
    """Close a cutout h[0..m] (x_j = j dx, period P = m dx) into a C1-periodic sample.

    Returns ``(h_closed, closure)`` with h_closed[m] == h_closed[0] exactly.  ``slopes`` are
    dh/dx at the cutout points (default: second-order finite differences of h; pass central
    differences from the parent profile for better end slopes).  ``closure_length`` fixes d
    (rounded to whole grid steps); otherwise it is chosen as described in the module docstring.
    """
    h = np.asarray(h, dtype=float)
    m = h.size - 1
    if m < 8:
        raise SurfaceError(f"a cutout needs at least 9 points to be closed, got {h.size}")
    if not dx > 0:
        raise SurfaceError("dx must be positive")
    s = np.gradient(h, dx, edge_order=2) if slopes is None else np.asarray(slopes, dtype=float)
    if s.shape != h.shape:
        raise SurfaceError("slopes must have the shape of h")
    rms = float(np.std(h)) or 1.0
    mis_h = abs(h[m] - h[0])
    mis_s = abs(s[m] - s[0])
    cap = float(np.max(np.abs(s))) if slope_cap is None else float(slope_cap)
    if closure_length is None and mis_h <= 1e-9 * rms and mis_s * m * dx <= 1e-9 * rms:
        out = h.copy()
        out[m] = out[0]
        return out, Closure(m * dx, 0.0, 0, h[0], h[0], s[0], s[0], abs(s[0]), cap, True,
                            mis_h, mis_s)
    if closure_length is not None:
        k = int(np.clip(round(closure_length / dx), 1, m - 1))
    else:
        k_min = max(2, int(np.ceil(min_fraction * m)))
        k_max = max(k_min, int(np.floor(max_fraction * m)))
        ks = np.arange(k_min, k_max + 1)
        ms = hermite_max_slope(h[m - ks], h[0], s[m - ks], s[0], ks * dx)
        ok = ms <= cap * (1 + 1e-12)
        k = int(ks[np.argmax(ok)]) if np.any(ok) else int(ks[np.argmin(ms)])
    d = k * dx
    j = np.arange(m - k, m + 1)
    p0, m0, p1, m1 = h[m - k], s[m - k], h[0], s[0]
    out = h.copy()
    out[j] = hermite((j - (m - k)) / k, p0, p1, m0, m1, d)
    out[m] = out[0]  # exact, not just to round-off
    ms = float(hermite_max_slope(p0, p1, m0, m1, d))
    return out, Closure((m - k) * dx, d, k, p0, p1, m0, m1, ms, cap, ms <= cap * (1 + 1e-12),
                        mis_h, mis_s)
