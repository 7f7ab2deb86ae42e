"""The line-scan profile container and the unit and detrending helpers that act on it.

A :class:`Profile` is one height trace h(x) of a rough surface (thesis ch. 2.3.1: the height
profile z(x) behind the HDC eq. (2.4) and the PSD eq. (2.6)).  Inside the package, x and h are
always in millimetres (the project's unit system); readers convert at the input boundary, see
:func:`unit_factor`.  ``x`` must be strictly increasing; it need not be uniform (a raw,
non-uniform scan is resampled by :func:`rubberfriction.driver.surfaces.defects.resample_uniform`
before spectral analysis).  Heights may contain NaN only in raw profiles, before cleaning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction.driver.surfaces.errors import ProfileFormatError, SurfaceError

#: Length units accepted at the input boundary and their factor to millimetres.
UNIT_TO_MM: dict[str, float] = {
    "mm": 1.0,
    "millimetre": 1.0,
    "millimeter": 1.0,
    "m": 1.0e3,
    "cm": 10.0,
    "um": 1.0e-3,
    "µm": 1.0e-3,  # micro sign U+00B5
    "μm": 1.0e-3,  # greek mu U+03BC
    "micron": 1.0e-3,
    "microns": 1.0e-3,
    "nm": 1.0e-6,
    "in": 25.4,
}

#: Relative tolerance below which a spacing is treated as uniform.
UNIFORM_RTOL = 1.0e-6


def unit_factor(unit: str) -> float:
    """Factor that converts a length in ``unit`` to millimetres (``"um"`` -> 1e-3).

    Raises :class:`ProfileFormatError` for an unknown unit name, listing the known ones.
    """
    key = unit.strip().lower().replace("micrometre", "um").replace("micrometer", "um")
    if key in UNIT_TO_MM:
        return UNIT_TO_MM[key]
    raise ProfileFormatError(
        f"unknown length unit {unit!r}; use one of {sorted(set(UNIT_TO_MM))}"
    )


@dataclass
class Profile:
    """A measured or generated height profile h(x), x and h in millimetres.

    Attributes
    ----------
    x:
        Positions along the scan (mm), strictly increasing.
    h:
        Heights (mm), z up.  NaN marks a dropout in a raw profile.
    units:
        Length unit of ``x`` and ``h``; ``"mm"`` for every profile the package produces.
    source:
        Where the data come from: a file path, ``"generated: ..."``, or a band of another profile.
    meta:
        Free-form provenance (header lines of the file, defect report, band edges, periodicity
        flag ``meta["periodic"]`` for exactly periodic generated data, ...).
    repaired:
        Optional boolean mask, True where a height was interpolated over a dropout or outlier.
        Sample extraction avoids windows with many repaired points.
    """

    x: np.ndarray
    h: np.ndarray
    units: str = "mm"
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)
    repaired: np.ndarray | None = None

    def __post_init__(self) -> None:
        x = np.ascontiguousarray(self.x, dtype=float)
        h = np.ascontiguousarray(self.h, dtype=float)
        if x.ndim != 1 or h.ndim != 1:
            raise SurfaceError(
                f"profile x and h must be 1D arrays, got shapes {x.shape}, {h.shape}"
            )
        if x.size != h.size:
            raise SurfaceError(f"profile x and h differ in length: {x.size} vs {h.size}")
        if x.size == 0:
            raise SurfaceError("profile has no data points")
        if not np.all(np.isfinite(x)):
            bad = int(np.flatnonzero(~np.isfinite(x))[0])
            raise SurfaceError(f"profile position x[{bad}] is not finite")
        if x.size > 1:
            dx = np.diff(x)
            if np.any(dx <= 0.0):
                k = int(np.flatnonzero(dx <= 0.0)[0])
                raise SurfaceError(
                    "profile positions must be strictly increasing: "
                    f"x[{k}] = {x[k]:.6g} is followed by x[{k + 1}] = {x[k + 1]:.6g}"
                )
        if self.repaired is not None:
            rep = np.ascontiguousarray(self.repaired, dtype=bool)
            if rep.shape != x.shape:
                raise SurfaceError("repaired mask must have the shape of x")
            self.repaired = rep
        self.x = x
        self.h = h

    # -- geometry -------------------------------------------------------------------------
    @property
    def n(self) -> int:
        """Number of points."""
        return int(self.x.size)

    @property
    def periodic(self) -> bool:
        """True for exactly periodic data (generated profiles), period ``n * dx``."""
        return bool(self.meta.get("periodic", False))

    def is_uniform(self, rtol: float = UNIFORM_RTOL) -> bool:
        """True if all spacings equal their mean within ``rtol`` (relative)."""
        if self.n < 2:
            return False
        d = np.diff(self.x)
        mean = (self.x[-1] - self.x[0]) / (self.n - 1)
        return bool(np.max(np.abs(d - mean)) <= rtol * mean)

    @property
    def dx(self) -> float:
        """Sample spacing (mm): the mean spacing of a uniform profile, the median otherwise."""
        if self.n < 2:
            raise SurfaceError("a single point has no spacing")
        if self.is_uniform():
            return float((self.x[-1] - self.x[0]) / (self.n - 1))
        return float(np.median(np.diff(self.x)))

    @property
    def length(self) -> float:
        """Record length L = n * dx (mm): the period the discrete Fourier transform assumes."""
        return self.n * self.dx

    @property
    def extent(self) -> float:
        """Distance between first and last point, x[-1] - x[0] (mm)."""
        return float(self.x[-1] - self.x[0])

    # -- statistics -----------------------------------------------------------------------
    def rms_height(self) -> float:
        """Root mean square of h about its mean (mm), NaN ignored."""
        h = self.h[np.isfinite(self.h)]
        return float(np.sqrt(np.mean((h - h.mean()) ** 2))) if h.size else math.nan

    def rms_slope(self) -> float:
        """Root mean square of the finite-difference slope dh/dx (-), periodic wrap if periodic."""
        h = self.h
        if self.periodic and self.is_uniform():
            d = np.diff(np.append(h, h[0])) / self.dx
        else:
            d = np.diff(h) / np.diff(self.x)
        d = d[np.isfinite(d)]
        return float(np.sqrt(np.mean(d**2))) if d.size else math.nan

    # -- derived profiles -----------------------------------------------------------------
    def with_h(self, h: np.ndarray, *, source: str | None = None, **meta: Any) -> Profile:
        """A copy on the same x with new heights, optional new source and extra meta entries."""
        new_meta = dict(self.meta)
        new_meta.update(meta)
        return replace(
            self,
            h=np.asarray(h, dtype=float),
            source=self.source if source is None else source,
            meta=new_meta,
        )

    def slice(self, start: int, stop: int) -> Profile:
        """Points ``start:stop`` as a new, non-periodic profile."""
        if stop - start < 1:
            raise SurfaceError(f"empty slice {start}:{stop}")
        meta = dict(self.meta)
        meta["periodic"] = False
        rep = None if self.repaired is None else self.repaired[start:stop]
        return Profile(self.x[start:stop], self.h[start:stop], self.units, self.source, meta, rep)

    def repaired_mask(self) -> np.ndarray:
        """The repaired mask, all False if none was recorded."""
        return np.zeros(self.n, bool) if self.repaired is None else self.repaired

    def to_csv(self, path: str | Path, *, header: str | None = None) -> Path:
        """Write ``x, h`` (mm) as comma-separated text with a ``#`` comment header."""
        path = Path(path)
        lines = [f"source: {self.source}", "columns: x (mm), h (mm)"]
        if header:
            lines.extend(header.splitlines())
        np.savetxt(path, np.column_stack([self.x, self.h]), delimiter=",", fmt="%.9g",
                   header="\n".join(lines))
        return path


def detrend(profile: Profile, kind: str | None = "mean") -> Profile:
    """Remove the mean (``"mean"``) or a least-squares line (``"linear"``) from h.

    Detrending is always explicit in this package: the PSD and the band filters ask for it by
    name.  ``None`` or ``"none"`` returns the profile unchanged.  NaN heights are ignored in the
    fit and stay NaN.
    """
    if kind is None or kind == "none":
        return profile
    ok = np.isfinite(profile.h)
    if not np.any(ok):
        raise SurfaceError("cannot detrend a profile without finite heights")
    if kind == "mean":
        trend = np.full(profile.n, profile.h[ok].mean())
    elif kind == "linear":
        if np.count_nonzero(ok) < 2:
            raise SurfaceError("linear detrending needs at least two finite heights")
        xm = profile.x[ok].mean()
        coef = np.polyfit(profile.x[ok] - xm, profile.h[ok], 1)
        trend = np.polyval(coef, profile.x - xm)
    else:
        raise SurfaceError(f"unknown detrend kind {kind!r}; use 'mean', 'linear' or None")
    return profile.with_h(profile.h - trend, detrended=kind)
