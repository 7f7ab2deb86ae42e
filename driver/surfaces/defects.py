"""Real-world defects of line scans: dropouts, laser outliers, gaps and non-uniform spacing.

Laser profilometers lose the signal in deep, dark or steep spots (dropouts, written as NaN or a
sentinel number), produce isolated spikes (laser outliers) and, like the CAPTIF stationary laser
profiler, may scan a reference plate that lies far above the road.  Spectral analysis and band
filtering (thesis ch. 6.3.1, eq. (6.10)) need a uniform, gap-free record, so this module

1. puts the scan on a uniform grid (:func:`resample_uniform`): positions printed with rounding are
   snapped to their grid (nothing is interpolated), a truly non-uniform scan is linearly
   interpolated onto the grid;
2. finds dropouts (NaN, +-inf, sentinel values) and outliers (:func:`find_outliers`);
3. interpolates linearly over short gaps and either rejects the record with a clear
   :class:`DefectError` or keeps the longest stretch between long gaps (:func:`clean_profile`).

Everything found is written to a :class:`DefectReport` (``profile.meta["defects"]``), and the
interpolated points are flagged in ``profile.repaired`` so that sample extraction can avoid them.
Linear interpolation over dropouts follows common road-texture practice (e.g. ISO 13473-1
processing as in captif-slp); it removes the wavelengths shorter than about twice the gap there.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.ndimage import median_filter

from rubberfriction.driver.surfaces.errors import DefectError
from rubberfriction.driver.surfaces.profile import UNIFORM_RTOL, Profile

#: Heights equal to one of these are dropouts (common "no data" codes of profilometers).
DEFAULT_SENTINELS: tuple[float, ...] = (-9999.0, 9999.0, -99999.0, 99999.0, -999999.0, 999999.0)

#: Positions within this fraction of dx of a uniform grid are treated as rounded grid positions.
SNAP_TOLERANCE = 0.05

_MAD_TO_SIGMA = 1.482602218505602  # 1 / Phi^-1(3/4): MAD of a normal variable -> sigma


@dataclass
class Gap:
    """One run of consecutive bad points (dropouts and/or outliers)."""

    start_x: float  #: position of the first bad point (mm)
    end_x: float  #: position of the last bad point (mm)
    n_points: int  #: number of bad points
    span: float  #: distance between the valid neighbours (mm), the width to bridge
    kind: str  #: "dropout", "outlier" or "dropout+outlier"
    action: str  #: "interpolated", "trimmed (edge)" or "discarded (long gap)"


@dataclass
class DefectReport:
    """What :func:`clean_profile` found and did; ``str(report)`` gives a readable summary."""

    n_points_raw: int
    n_nan: int = 0
    n_sentinel: int = 0
    n_outlier_global: int = 0
    n_outlier_spike: int = 0
    spacing: dict[str, Any] = field(default_factory=dict)
    gaps: list[Gap] = field(default_factory=list)
    max_gap: float = 0.0
    long_gap_policy: str = "longest"
    kept_range: tuple[float, float] = (0.0, 0.0)
    n_points_kept: int = 0
    n_interpolated: int = 0
    notes: list[str] = field(default_factory=list)

    @property
    def n_dropouts(self) -> int:
        """NaN, infinite and sentinel heights together."""
        return self.n_nan + self.n_sentinel

    @property
    def n_outliers(self) -> int:
        """Global and spike outliers together."""
        return self.n_outlier_global + self.n_outlier_spike

    @property
    def interpolated_fraction(self) -> float:
        """Fraction of the kept points whose height was interpolated."""
        return self.n_interpolated / self.n_points_kept if self.n_points_kept else 0.0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (gaps as a list of dicts)."""
        d = asdict(self)
        d["n_dropouts"] = self.n_dropouts
        d["n_outliers"] = self.n_outliers
        d["interpolated_fraction"] = self.interpolated_fraction
        d["kept_range"] = list(self.kept_range)
        return d

    def __str__(self) -> str:
        n_int = sum(g.action == "interpolated" for g in self.gaps)
        n_long = sum(g.action == "discarded (long gap)" for g in self.gaps)
        n_out = sum(g.action == "discarded (outside kept stretch)" for g in self.gaps)
        n_edge = sum(g.action.startswith("trimmed") for g in self.gaps)
        longest = max((g.span for g in self.gaps if g.action == "interpolated"), default=0.0)
        lines = [
            f"points read: {self.n_points_raw}; spacing: {self.spacing.get('method', '?')} "
            f"dx = {self.spacing.get('dx', float('nan')):.6g} mm",
            f"dropouts: {self.n_dropouts} ({self.n_nan} NaN/inf, {self.n_sentinel} sentinel); "
            f"outliers: {self.n_outliers} ({self.n_outlier_global} global, "
            f"{self.n_outlier_spike} spikes)",
            f"gaps: {len(self.gaps)} ({n_int} interpolated, longest {longest:.3g} mm <= max_gap "
            f"{self.max_gap:.3g} mm; {n_long} long gaps discarded; {n_edge} at the edges trimmed; "
            f"{n_out} outside the kept stretch)",
            f"kept: x = {self.kept_range[0]:.6g} .. {self.kept_range[1]:.6g} mm, "
            f"{self.n_points_kept} points, {100 * self.interpolated_fraction:.2f} % interpolated",
        ]
        lines.extend(f"note: {n}" for n in self.notes)
        return "\n".join(lines)


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start indices and (exclusive) end indices of the runs of True in a boolean mask."""
    d = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def find_dropouts(
    h: np.ndarray, sentinels: tuple[float, ...] = DEFAULT_SENTINELS
) -> tuple[np.ndarray, np.ndarray]:
    """Masks of non-finite heights (NaN, +-inf) and of sentinel ("no data") values."""
    h = np.asarray(h, dtype=float)
    nonfinite = ~np.isfinite(h)
    if sentinels:
        sentinel = np.isin(h, np.asarray(sentinels, dtype=float))
    else:
        sentinel = np.zeros_like(nonfinite)
    return nonfinite, sentinel & ~nonfinite


def find_outliers(
    x: np.ndarray,
    h: np.ndarray,
    *,
    global_k: float = 6.0,
    spike_window: int = 11,
    spike_k: float = 10.0,
    spike_floor: float = 0.5,
) -> tuple[np.ndarray, np.ndarray]:
    """Masks of global outliers and of spikes among the finite heights.

    Global outliers (e.g. the CAPTIF reference plate, ~45 mm above the road) deviate from a
    least-squares line through the data by more than ``global_k`` robust standard deviations
    (sigma = 1.4826 * median absolute deviation of the residual).

    Spikes (single laser outliers) deviate from the running median over ``spike_window``
    consecutive valid points by more than ``max(spike_k * s, spike_floor * sigma)``, where s is
    the robust scale of those residuals.  The floor keeps smooth profiles, whose residuals are
    tiny, from flagging real sharp features; the ``spike_k * s`` term keeps rough,
    short-wavelength dominated profiles from flagging their own roughness.
    """
    x = np.asarray(x, dtype=float)
    h = np.asarray(h, dtype=float)
    ok = np.isfinite(h)
    glob = np.zeros(h.size, bool)
    spike = np.zeros(h.size, bool)
    idx = np.flatnonzero(ok)
    if idx.size < 8:
        return glob, spike
    xv, hv = x[idx], h[idx]
    xm = xv.mean()
    res = hv - np.polyval(np.polyfit(xv - xm, hv, 1), xv - xm)
    centre = np.median(res)
    sigma = _MAD_TO_SIGMA * np.median(np.abs(res - centre))
    if sigma == 0.0:
        sigma = float(np.std(res))
    if sigma > 0.0:
        glob[idx] = np.abs(res - centre) > global_k * sigma
    keep = idx[~glob[idx]]
    if keep.size > spike_window and spike_window >= 3:
        hk = h[keep]
        r = hk - median_filter(hk, size=spike_window, mode="nearest")
        s = _MAD_TO_SIGMA * np.median(np.abs(r))
        thr = max(spike_k * s, spike_floor * sigma)
        if thr > 0.0:
            spike[keep] = np.abs(r) > thr
    return glob, spike


#: A uniform grid of more than this many points per row of the file is not a scan with missing
#: rows but a wrong position column (or units): its positions span many spacings.
MAX_GRID_POINTS_PER_ROW = 100


def _check_grid(n: float, x: np.ndarray, dx: float) -> None:
    """Refuse a uniform grid far larger than the scan (it would exhaust memory, or numpy's
    'array is too big'): the positions are not a line scan's positions.  Refuse positions whose
    offset is so large that double precision cannot hold the spacing uniform to UNIFORM_RTOL
    (x ~ 1.7e9 mm in steps of 1e-3 mm): every analysis would fail later with 'spacing is not
    uniform'."""
    if n > MAX_GRID_POINTS_PER_ROW * x.size:
        raise DefectError(
            f"positions x = {x[0]:.6g} .. {x[-1]:.6g} with a spacing of {dx:.3g} would need a "
            f"uniform grid of {float(n):.3g} points for {x.size} rows: expected a position column "
            "of roughly even spacing; check x_col= and units="
        )
    largest = float(max(abs(x[0]), abs(x[-1])))
    if 4.0 * np.spacing(largest) > UNIFORM_RTOL * dx:
        raise DefectError(
            f"positions x = {x[0]:.15g} .. {x[-1]:.15g} with a spacing of {dx:.3g}: the offset is "
            "too large for the spacing in double precision; expected positions from near 0 "
            "(subtract the first one), or check x_col= and units="
        )


def resample_uniform(
    x: np.ndarray,
    h: np.ndarray,
    dx: float | None = None,
    *,
    snap_tolerance: float = SNAP_TOLERANCE,
) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Put a scan on a uniform grid; returns ``(x_uniform, h_uniform, info)``.

    * If every x lies within ``snap_tolerance * dx`` of a grid x0 + i*dx (positions printed with
      rounding, or rows missing from the file), the points are *snapped*: heights are kept as
      they are, dx is the least-squares fit of x against the grid index, and grid points without
      a row become NaN dropouts.  No interpolation happens.
    * Otherwise the scan is truly non-uniform and h is linearly interpolated onto x0 + k*dx,
      k = 0 .. floor((x[-1] - x0) / dx), with dx the median spacing unless given.  A grid point
      whose neighbouring samples include a NaN stays NaN.

    ``info`` records the method, dx and the largest deviation from the grid.
    """
    x = np.asarray(x, dtype=float)
    h = np.asarray(h, dtype=float)
    if x.size < 2:
        raise DefectError("cannot resample fewer than two points")
    d = np.diff(x)
    if np.any(d <= 0):
        k = int(np.flatnonzero(d <= 0)[0])
        raise DefectError(
            f"x must be strictly increasing (x[{k}]={x[k]:.6g}, x[{k + 1}]={x[k + 1]:.6g})"
        )
    med = float(np.median(d))
    dx0 = med if dx is None else float(dx)
    if dx0 <= 0:
        raise DefectError(f"grid spacing must be positive, got {dx0}")
    if dx is None:
        # the mean of the regular spacings is a far better first guess than the median when
        # positions are rounded (CAPTIF: 0.037 and 0.038 for a true 0.0375 mm)
        regular = d[(d > 0.5 * med) & (d < 1.5 * med)]
        guess = float(regular.mean()) if regular.size else med
        i = np.rint((x - x[0]) / guess).astype(np.int64)
        b, a = np.polyfit(i.astype(float), x, 1)  # least-squares grid: x = a + b*i
        i = np.rint((x - a) / b).astype(np.int64)
        dev = float(np.max(np.abs(x - (a + b * i))))
        if np.all(np.diff(i) > 0) and i[0] == 0 and dev <= snap_tolerance * b:
            n = int(i[-1]) + 1
            _check_grid(n, x, b)
            hu = np.full(n, np.nan)
            hu[i] = h
            xu = a + b * np.arange(n)
            info = {"method": "snapped", "dx": float(b), "max_deviation": dev,
                    "missing_rows": int(n - x.size)}
            if n != x.size:
                info["note"] = f"{n - x.size} grid positions had no row; they are dropouts"
            return xu, hu, info
    n = int(np.floor((x[-1] - x[0]) / dx0 + 1e-9)) + 1
    _check_grid(n, x, dx0)
    xu = x[0] + dx0 * np.arange(n)
    hu = np.interp(xu, x, h)
    nan = ~np.isfinite(h)
    if np.any(nan):
        # a grid point is invalid if either bracketing sample is a dropout
        j = np.clip(np.searchsorted(x, xu, side="right") - 1, 0, x.size - 1)
        j1 = np.minimum(j + 1, x.size - 1)
        exact = np.isclose(xu, x[j], rtol=0.0, atol=1e-12 * max(1.0, abs(x[-1])))
        bad = nan[j] | (nan[j1] & ~exact)
        hu[bad] = np.nan
    dev = float(np.max(np.abs(d - dx0)))
    return xu, hu, {"method": "interpolated (linear)", "dx": dx0, "max_deviation": dev,
                    "missing_rows": 0}


def clean_profile(
    profile: Profile,
    *,
    sentinels: tuple[float, ...] = DEFAULT_SENTINELS,
    outliers: bool = True,
    max_gap: float | None = None,
    long_gaps: Literal["longest", "error"] = "longest",
    max_dropout_fraction: float = 0.15,
    dx: float | None = None,
    min_points: int = 16,
) -> Profile:
    """A uniform, gap-free copy of a raw profile; the report is in ``meta["defects"]``.

    Parameters
    ----------
    sentinels:
        Height values that mean "no data".
    outliers:
        Detect global outliers and spikes (:func:`find_outliers`) and treat them as dropouts.
    max_gap:
        Longest gap (mm, distance between the valid neighbours) that is interpolated linearly.
        Default: ``max(0.005 * extent, 4 * dx)`` (9.6 mm for a 1.9 m CAPTIF scan, whose
        interior dropouts are at most ~4.5 mm wide, while the ~40 mm reference-plate gaps are
        long).
    long_gaps:
        What to do with longer interior gaps: ``"error"`` raises :class:`DefectError` listing
        them; ``"longest"`` keeps the longest stretch between long gaps and reports the rest as
        discarded.  Gaps at either end are always trimmed (there is nothing to interpolate
        towards) and reported.
    max_dropout_fraction:
        Raise if more than this fraction of the kept stretch had to be interpolated.
    dx:
        Grid spacing for :func:`resample_uniform` (default: from the data).
    min_points:
        Raise if fewer valid points than this remain.
    """
    if long_gaps not in ("longest", "error"):
        raise DefectError(f"long_gaps must be 'longest' or 'error', got {long_gaps!r}")
    report = DefectReport(n_points_raw=profile.n, long_gap_policy=long_gaps)
    h_raw = profile.h
    nonfinite, sentinel = find_dropouts(h_raw, sentinels)
    report.n_nan = int(nonfinite.sum())
    report.n_sentinel = int(sentinel.sum())
    h = np.where(nonfinite | sentinel, np.nan, h_raw)
    n_valid = int(np.isfinite(h).sum())
    if n_valid == 0:
        raise DefectError(
            f"{profile.source or 'profile'}: all {profile.n} heights are dropouts (NaN, inf or "
            "sentinel values); nothing to analyse"
        )
    if n_valid < min_points:
        raise DefectError(
            f"{profile.source or 'profile'}: only {n_valid} valid heights (need {min_points})"
        )

    # 1. uniform grid (snapping keeps the measured heights untouched)
    if profile.periodic and profile.is_uniform():
        x = profile.x
        report.spacing = {"method": "uniform", "dx": profile.dx, "max_deviation": 0.0,
                          "missing_rows": 0}
    else:
        try:
            x, h, report.spacing = resample_uniform(profile.x, h, dx)
        except DefectError as err:
            raise DefectError(f"{profile.source or 'profile'}: {err}") from None
        if "note" in report.spacing:
            report.notes.append(report.spacing["note"])
    dxu = float(report.spacing["dx"])

    # 2. outliers become dropouts
    kind = np.where(np.isfinite(h), 0, 1).astype(np.int8)  # 1 = dropout, 2 = outlier
    if outliers:
        glob, spike = find_outliers(x, h)
        report.n_outlier_global = int(glob.sum())
        report.n_outlier_spike = int(spike.sum())
        kind[glob | spike] = 2
        h = np.where(glob | spike, np.nan, h)
    bad = ~np.isfinite(h)

    # 3. gaps
    extent = float(x[-1] - x[0])
    report.max_gap = float(max(0.005 * extent, 4 * dxu) if max_gap is None else max_gap)
    starts, ends = _runs(bad)
    n = x.size
    spans = np.where(
        (starts > 0) & (ends < n),
        x[np.minimum(ends, n - 1)] - x[np.maximum(starts - 1, 0)],
        np.inf,
    )
    edge = (starts == 0) | (ends == n)
    long_ = (spans > report.max_gap * (1 + 1e-9)) & ~edge
    if np.any(long_) and long_gaps == "error":
        listing = ", ".join(
            f"{x[s]:.4g}..{x[e - 1]:.4g} mm ({sp:.3g} mm)"
            for s, e, sp in zip(starts[long_][:10], ends[long_][:10], spans[long_][:10])
        )
        raise DefectError(
            f"{profile.source or 'profile'}: {int(long_.sum())} gap(s) longer than max_gap = "
            f"{report.max_gap:.4g} mm cannot be interpolated: {listing}; raise max_gap, or pass "
            "long_gaps='longest' to keep the longest stretch between them"
        )
    # segments between long/edge gaps: choose the longest
    cut = long_ | edge
    seg_start = np.concatenate(([0], ends[cut]))
    seg_end = np.concatenate((starts[cut], [n]))
    seg_len = seg_end - seg_start
    k = int(np.argmax(seg_len))
    s0, s1 = int(seg_start[k]), int(seg_end[k])
    if s1 - s0 < min_points:
        raise DefectError(
            f"{profile.source or 'profile'}: the longest stretch without long gaps has only "
            f"{s1 - s0} points (need {min_points})"
        )
    for s, e, sp, is_edge, is_long in zip(starts, ends, spans, edge, long_):
        kinds = np.unique(kind[s:e])
        label = "+".join(("dropout", "outlier")[int(c) - 1] for c in kinds if c > 0)
        if is_edge:
            action = "trimmed (edge)"
        elif is_long:
            action = "discarded (long gap)"
        elif s >= s0 and e <= s1:
            action = "interpolated"
        else:
            action = "discarded (outside kept stretch)"
        report.gaps.append(Gap(float(x[s]), float(x[e - 1]), int(e - s),
                               float(sp) if np.isfinite(sp) else float("inf"), label, action))
    if np.any(long_):
        report.notes.append(
            f"kept the longest stretch between long gaps: x = {x[s0]:.6g} .. {x[s1 - 1]:.6g} mm "
            f"({s1 - s0} of {n} grid points)"
        )
    xs, hs, bs = x[s0:s1], h[s0:s1], bad[s0:s1]
    if np.any(bs):
        hs = hs.copy()
        hs[bs] = np.interp(xs[bs], xs[~bs], hs[~bs])
    report.kept_range = (float(xs[0]), float(xs[-1]))
    report.n_points_kept = int(xs.size)
    report.n_interpolated = int(bs.sum())
    if report.interpolated_fraction > max_dropout_fraction:
        raise DefectError(
            f"{profile.source or 'profile'}: {100 * report.interpolated_fraction:.1f} % of the "
            f"kept points are dropouts or outliers (limit {100 * max_dropout_fraction:.0f} %); "
            "the record is not reliable"
        )
    meta = dict(profile.meta)
    meta["defects"] = report
    meta["periodic"] = bool(profile.periodic and s0 == 0 and s1 == n and not np.any(bad))
    return Profile(xs, hs, profile.units, profile.source, meta, bs)
