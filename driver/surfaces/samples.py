"""Periodic surface samples of one scale (thesis ch. 6.3.2 step A, ch. 6.4.2 and 6.5.1).

Each scale of the multiscale method is represented by a few cutouts of its band profile, one
rubber block long (ten per scale in the thesis, ch. 6.4.2 shows that ten already bring the
spread of the averaged friction coefficient down from +-0.047 to +-0.015).  The cutouts are
taken where the rubber actually touches: "the contact of the rubber block with the rough
surface is assumed on the top asperities ... therefore the upper parts of the rough surface
measurement are evaluated for the choice of surface samples" (ch. 6.5.1).  Here that means the
centre of every cutout lies where the *carrier* of the scale, the surface the block rides on
(all wavelengths longer than the scale's band,
:func:`~rubberfriction.driver.surfaces.bands.lowpass`),
is within its top ``top_fraction`` of heights.  Windows with many interpolated (repaired) points
are avoided, and so are the first and last block length of a non-periodic record, where the
band filter rings slightly.  Positions are drawn at random from a seeded generator, without
overlap when the record allows it, so a seed reproduces the same samples.

Each cutout is closed into a periodic sample by the connecting spline of
:mod:`~rubberfriction.driver.surfaces.closure` and stretched onto an exact grid of the block
length (the stretch is below dx / (2 l), reported).  A :class:`SurfaceSample` is what the FE
master surface of a scale is built from: a periodic rigid polyline with period P.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction.driver.surfaces.closure import Closure, close_periodic
from rubberfriction.driver.surfaces.errors import BandError
from rubberfriction.driver.surfaces.profile import Profile

__all__ = ["SurfaceSample", "extract_samples", "samples_table", "provenance_kind",
           "refine_periodic"]


@dataclass
class SurfaceSample:
    """A periodic closed polyline of one scale.

    ``x`` is uniform from 0 to ``period`` inclusive and ``h[-1] == h[0]``: the closed polyline
    (x_j, h_j) is one period of the master surface; repeat it with shift ``period``.
    """

    x: np.ndarray  #: positions 0 .. period (mm), uniform, endpoint included
    h: np.ndarray  #: heights (mm), h[-1] == h[0]
    period: float  #: period P = block length (mm)
    rms_height: float  #: rms of h about its mean over one period (mm)
    rms_slope: float  #: rms of dh/dx over one period (-)
    closure_length: float  #: length replaced by the connecting spline (mm)
    source: str  #: "measured" or "generated"
    band: tuple[float, float] = (math.nan, math.nan)  #: (lambda_long, lambda_short) mm
    start: float = 0.0  #: position of the cutout in the band profile (mm)
    band_rms_height: float = math.nan  #: rms height of the whole band profile (mm)
    band_rms_slope: float = math.nan  #: rms slope of the whole band profile (-)
    scale: int = 0  #: scale index (0 = coarsest)
    seed: int | None = None
    origin: str = ""  #: the profile the band came from
    closure: Closure | None = None
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def dx(self) -> float:
        return float(self.x[1] - self.x[0])

    @property
    def height_ratio(self) -> float:
        """rms height of the sample / rms height of its band."""
        return self.rms_height / self.band_rms_height

    @property
    def slope_ratio(self) -> float:
        """rms slope of the sample / rms slope of its band."""
        return self.rms_slope / self.band_rms_slope

    def polyline(self) -> np.ndarray:
        """(N, 2) array of (x, h) vertices, first and last vertex one period apart."""
        return np.column_stack([self.x, self.h])

    def summary(self) -> dict[str, Any]:
        """Scalar description (JSON-ready)."""
        return {
            "scale": self.scale,
            "band_mm": list(self.band),
            "source": self.source,
            "origin": self.origin,
            "start_mm": self.start,
            "period_mm": self.period,
            "n_points": int(self.x.size),
            "dx_mm": self.dx,
            "rms_height_mm": self.rms_height,
            "rms_slope": self.rms_slope,
            "band_rms_height_mm": self.band_rms_height,
            "band_rms_slope": self.band_rms_slope,
            "height_ratio": self.height_ratio,
            "slope_ratio": self.slope_ratio,
            "closure_length_mm": self.closure_length,
            "closure_within_slope_cap": (None if self.closure is None
                                         else self.closure.within_slope_cap),
            "seed": self.seed,
            **{k: v for k, v in self.meta.items() if isinstance(v, (int, float, str, bool))},
        }

    def to_csv(self, path: str | Path) -> Path:
        """Write the closed polyline as ``x, h`` (mm) with a comment header."""
        path = Path(path)
        head = "\n".join(f"{k}: {v}" for k, v in self.summary().items())
        np.savetxt(path, self.polyline(), delimiter=",", fmt="%.9g",
                   header=head + "\ncolumns: x (mm), h (mm); periodic, last row = first + period")
        return path


def provenance_kind(profile: Profile) -> str:
    """"measured" or "generated" from ``meta["provenance"]["kind"]`` ("unknown" if absent)."""
    prov = profile.meta.get("provenance") or {}
    return str(prov.get("kind", "unknown"))


def _rms_slope(h: np.ndarray, dx: float) -> float:
    d = np.diff(h) / dx
    return float(np.sqrt(np.mean(d * d)))


def extract_samples(
    band_profile: Profile,
    block_length: float,
    n: int,
    seed: int | None = 0,
    *,
    carrier: Profile | np.ndarray | None = None,
    top_fraction: float = 0.2,
    max_repaired_fraction: float = 0.02,
    allow_overlap: bool = False,
    closure_min_fraction: float = 0.02,
    closure_max_fraction: float = 0.25,
    scale: int | None = None,
) -> list[SurfaceSample]:
    """Cut ``n`` periodic samples of length ``block_length`` (mm) from a band profile.

    Parameters
    ----------
    band_profile:
        A band of :func:`~rubberfriction.driver.surfaces.bands.band_split` (uniform, no NaN).
    carrier:
        Heights (same grid) of the surface the block of this scale rides on, used to find the
        top asperities; default: the band profile itself.
    top_fraction:
        Cutout centres lie where the carrier is within its top ``top_fraction`` of heights
        (thesis ch. 6.5.1); 1.0 allows any position.
    max_repaired_fraction:
        Cutouts with more interpolated points than this fraction are avoided.
    allow_overlap:
        If False, samples do not overlap; when the record is too short for ``n`` separate
        cutouts, overlapping ones are taken and every sample's ``meta["overlap"]`` says so.
    """
    if n < 1:
        raise BandError(f"number of samples must be >= 1, got {n}")
    if not np.all(np.isfinite(band_profile.h)) or not band_profile.is_uniform():
        raise BandError("band profile must be uniform and free of NaN (clean and split it first)")
    if not 0 < top_fraction <= 1:
        raise BandError(f"top_fraction must lie in (0, 1], got {top_fraction}")
    dx = band_profile.dx
    m = int(round(block_length / dx))
    N = band_profile.n
    if m < 8:
        raise BandError(
            f"block length {block_length:g} mm is only {m} grid steps of {dx:.4g} mm; a sample "
            "needs at least 8 (use a finer measurement)"
        )
    if m + 3 > N:
        raise BandError(
            f"{band_profile.source or 'profile'} ({band_profile.length:.4g} mm) is too short for "
            f"samples of {block_length:g} mm"
        )
    h = band_profile.h
    if carrier is None:
        c = h
    else:
        c = carrier.h if isinstance(carrier, Profile) else np.asarray(carrier, dtype=float)
        if c.shape != h.shape:
            raise BandError("carrier must be on the grid of the band profile")
    # margin: one point for central differences; for non-periodic records also one block length
    # at each end, where the mirrored filter leaves a little ringing (bands module), if possible
    edge = m if (not band_profile.periodic and N - 2 * m - m - 2 >= m) else 1
    starts = np.arange(edge, N - m - edge)
    thr = np.quantile(c, 1.0 - top_fraction) if top_fraction < 1 else -np.inf
    valid = c[starts + m // 2] >= thr
    rep = band_profile.repaired_mask()
    if rep.any():
        cs = np.concatenate(([0], np.cumsum(rep)))
        frac = (cs[starts + m + 1] - cs[starts]) / (m + 1)
        valid &= frac <= max_repaired_fraction
    cand = starts[valid]
    if cand.size == 0:
        raise BandError(
            f"no {block_length:g} mm window of {band_profile.source or 'profile'} lies in the top "
            f"{100 * top_fraction:g} % of the carrier with <= {100 * max_repaired_fraction:g} % "
            "interpolated points; relax top_fraction or max_repaired_fraction"
        )
    rng = np.random.default_rng(seed)
    order = rng.permutation(cand)
    chosen: list[int] = []
    overlap = allow_overlap
    if not allow_overlap:
        acc = np.empty(0, dtype=np.int64)
        for s in order[: max(64 * n, 4096)]:  # loop over candidate windows, stops at n
            if acc.size == 0 or np.min(np.abs(acc - s)) > m:
                acc = np.append(acc, s)
                if acc.size == n:
                    break
        chosen = [int(v) for v in acc]
        if len(chosen) < n:
            overlap = True
            taken = set(chosen)
            for s in order:
                if len(chosen) == n:
                    break
                if int(s) not in taken:
                    chosen.append(int(s))
                    taken.add(int(s))
    else:
        chosen = [int(v) for v in order[:n]]
    if len(chosen) < n:
        raise BandError(f"only {len(chosen)} admissible windows for {n} samples")
    chosen.sort()
    slopes_full = np.empty(N)
    slopes_full[1:-1] = (h[2:] - h[:-2]) / (2 * dx)
    slopes_full[0] = (h[1] - h[0]) / dx
    slopes_full[-1] = (h[-1] - h[-2]) / dx
    band_rms_h = band_profile.rms_height()
    band_rms_s = _rms_slope(h, dx)
    kind = provenance_kind(band_profile)
    band = tuple(band_profile.meta.get("band", (math.nan, math.nan)))
    scale_idx = int(band_profile.meta.get("band_index", 0)) if scale is None else scale
    x_s = np.linspace(0.0, block_length, m + 1)
    stretch = block_length / (m * dx) - 1.0
    out = []
    for s in chosen:  # n samples
        cut = h[s:s + m + 1]
        hc, clo = close_periodic(cut, dx, slopes=slopes_full[s:s + m + 1],
                                 min_fraction=closure_min_fraction,
                                 max_fraction=closure_max_fraction)
        dxs = block_length / m
        out.append(SurfaceSample(
            x=x_s.copy(),
            h=hc,
            period=float(block_length),
            rms_height=float(np.std(hc[:-1])),
            rms_slope=_rms_slope(hc, dxs),
            closure_length=float(clo.length * (1 + stretch)),
            source=kind,
            band=(float(band[0]), float(band[1])),
            start=float(band_profile.x[s]),
            band_rms_height=band_rms_h,
            band_rms_slope=band_rms_s,
            scale=scale_idx,
            seed=seed,
            origin=str(band_profile.meta.get("parent", band_profile.source)),
            closure=clo,
            meta={"stretch": stretch, "overlap": overlap, "top_fraction": top_fraction,
                  "carrier_threshold_mm": float(thr)},
        ))
    return out


def samples_table(samples: list[SurfaceSample]) -> str:
    """Plain-text table: each sample's rms height and slope against its band's statistics."""
    rows = [f"{'scale':>5} {'band (mm)':>14} {'start (mm)':>11} {'rms h (mm)':>11} {'/band':>6} "
            f"{'rms slope':>9} {'/band':>6} {'closure (mm)':>12} source"]
    for s in samples:
        rows.append(
            f"{s.scale:>5} {s.band[0]:>6.3g}-{s.band[1]:<7.3g} {s.start:>11.4g} "
            f"{s.rms_height:>11.4g} "
            f"{s.height_ratio:>6.2f} {s.rms_slope:>9.4g} {s.slope_ratio:>6.2f} "
            f"{s.closure_length:>12.4g} {s.source}"
        )
    return "\n".join(rows)


def refine_periodic(h: np.ndarray, factor: int) -> np.ndarray:
    """Heights of a periodic, uniformly spaced sample at ``factor`` times more points.

    Trigonometric (band-limited) interpolation: zero-padding of the discrete Fourier series,
    so the refined sample passes through every original point and adds no wavelength shorter
    than the original grid resolves.  This is the continuous profile a band-pass filtered
    sample stands for; the straight polyline through the original points is not (at 6 points
    per shortest wavelength it has a kink of tens of degrees at every point of a steep band,
    which the rigid master surface passes on to the contact as a jumping normal).
    """
    h = np.asarray(h, dtype=float)
    if factor < 1 or int(factor) != factor:
        raise ValueError(f"refine_periodic: factor must be a whole number >= 1, got {factor!r}")
    n = h.size
    if factor == 1 or n < 2:
        return h.copy()
    spec = np.fft.rfft(h)
    if n % 2 == 0:
        spec[-1] *= 0.5  # the Nyquist term is shared by +-n/2 once it is no longer the last bin
    return np.fft.irfft(spec, n * int(factor)) * factor
