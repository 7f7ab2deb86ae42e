"""The lowest scale of a road: a stated cut-off rule, never an implicit extrapolation.

A self-affine continuation of a road below its measurement steepens without bound (the rms slope
of a band grows like lambda^(H-1)), so no mesh resolves it.  Persson's practice cuts the spectrum
where the cumulative rms slope of the isotropic surface reaches about 1.3 (Lorenz, Oh, Nam,
Jeon, Persson, J. Chem. Phys. 142, 194701, 2015); the thesis (6.5.1) took its micro scales from a
second, finer measurement.  :func:`apply_cutoff` applies one of three rules to the bands of a
multiscale surface:

* ``"slope"`` (default): bands cut from a measurement (a profile whose provenance does not say
  "generated") are kept down to the measurement's resolution; generated bands are added only
  while the cumulative 2D rms slope stays at or below ``max_slope``; the band that crosses it
  is shortened to the wavelength where the limit is reached (dropped if less than half an
  octave would remain), lower bands are dropped;
* ``"resolution"``: measured bands only;
* a wavelength in mm: the bands down to it (what the thesis did with its edges).

Slopes.  A band's 1D rms slope is the finite-difference rms of dh/dx of its band profile
(:meth:`Profile.rms_slope`).  Bands partition the spectrum, so their mean squares add; for an
isotropic surface measured along a line, <|grad h|^2> = 2 <(dh/dx)^2>, so the cumulative 2D rms
slope down to band i is sqrt(2 sum_{k <= i} s_k^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from rubberfriction.driver.surfaces.bands import band_split
from rubberfriction.driver.surfaces.errors import BandError, SurfaceError
from rubberfriction.driver.surfaces.multiscale import MultiScaleSurface, scale_names

__all__ = ["DEFAULT_MAX_SLOPE", "CutoffRule", "BandRow", "CutoffReport", "apply_cutoff",
           "cumulative_slope_2d", "parse_cutoff"]

#: Cumulative 2D rms slope at which the "slope" rule stops (Lorenz et al. 2015).
DEFAULT_MAX_SLOPE = 1.3
#: Relative slack on max_slope (a surface designed to reach it exactly keeps its last band).
SLOPE_SLACK = 1e-6
#: A band the slope rule would shorten to less than half an octave is dropped instead.
MIN_BAND_RATIO = 2.0**0.5


@dataclass(frozen=True)
class CutoffRule:
    """``kind`` "slope", "resolution" or "wavelength" (then ``wavelength`` in mm)."""

    kind: str = "slope"
    max_slope: float = DEFAULT_MAX_SLOPE
    wavelength: float | None = None

    def __str__(self) -> str:
        if self.kind == "wavelength":
            return f"cutoff = {self.wavelength:g} mm"
        if self.kind == "slope":
            return f"cutoff = \"slope\" (max_slope = {self.max_slope:g})"
        return "cutoff = \"resolution\""


def parse_cutoff(value: Any, max_slope: float = DEFAULT_MAX_SLOPE) -> CutoffRule:
    """The rule from a scene or command-line value: "slope", "resolution" or a wavelength."""
    if isinstance(value, str):
        text = value.strip()
        if text in ("slope", "resolution"):
            return CutoffRule(text, max_slope)
        try:
            value = float(text)
        except ValueError:
            raise SurfaceError(f"cutoff = {value!r}: expected \"slope\", \"resolution\" or a "
                               "wavelength in mm") from None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SurfaceError(f"cutoff = {value!r}: expected \"slope\", \"resolution\" or a "
                           "wavelength in mm")
    if not (math.isfinite(value) and value > 0):
        raise SurfaceError(f"cutoff = {value!r}: expected a positive wavelength in mm")
    return CutoffRule("wavelength", max_slope, float(value))


@dataclass(frozen=True)
class BandRow:
    """One band of the stated edges and what the rule did with it."""

    name: str
    band: tuple[float, float]  #: stated (lambda_long, lambda_short), mm
    kind: str  #: "measured", "generated" or "" (dropped before it was built)
    status: str  #: "kept", "shortened" or "dropped"
    rms_slope: float = math.nan  #: 1D rms slope of the kept band (NaN if dropped)
    cumulative_slope: float = math.nan  #: cumulative 2D rms slope down to this band
    short_edge: float = math.nan  #: kept short edge (mm)
    reason: str = ""


@dataclass(frozen=True)
class CutoffReport:
    """The rule, the stated and kept edges, and one row per stated band."""

    rule: CutoffRule
    stated_edges: tuple[float, ...]
    edges: tuple[float, ...]
    rows: tuple[BandRow, ...] = field(default=())

    @property
    def dropped(self) -> list[str]:
        return [r.name for r in self.rows if r.status == "dropped"]

    @property
    def cumulative_slope(self) -> float:
        """Cumulative 2D rms slope of all kept bands."""
        kept = [r.cumulative_slope for r in self.rows if r.status != "dropped"]
        return kept[-1] if kept else math.nan

    def lines(self) -> list[str]:
        """A table for people: band, kind, 1D slope, cumulative 2D slope, what was done."""
        out = [f"lowest scale: {self.rule}; kept edges "
               + ", ".join(f"{e:.4g}" for e in self.edges) + " mm",
               f"  {'scale':<8} {'band (mm)':<16} {'kind':<10} {'slope 1D':>9} "
               f"{'cum. 2D':>8}  status"]
        for r in self.rows:
            band = f"{r.band[0]:g}-{r.band[1]:g}"
            s1 = f"{r.rms_slope:.3g}" if math.isfinite(r.rms_slope) else "-"
            s2 = f"{r.cumulative_slope:.3g}" if math.isfinite(r.cumulative_slope) else "-"
            what = r.status
            if r.status == "shortened":
                what += f" to {r.band[0]:g}-{r.short_edge:.4g} mm"
            if r.reason:
                what += f": {r.reason}"
            out.append(f"  {r.name:<8} {band:<16} {r.kind or '-':<10} {s1:>9} {s2:>8}  {what}")
        return out

    def to_dict(self) -> dict[str, Any]:
        return {"rule": self.rule.kind, "max_slope": self.rule.max_slope,
                "wavelength_mm": self.rule.wavelength, "stated_edges_mm": list(self.stated_edges),
                "edges_mm": list(self.edges),
                "bands": [{"name": r.name, "band_mm": list(r.band), "kind": r.kind,
                           "status": r.status, "rms_slope_1d": _num(r.rms_slope),
                           "cumulative_slope_2d": _num(r.cumulative_slope),
                           "short_edge_mm": _num(r.short_edge), "reason": r.reason}
                          for r in self.rows]}


def _num(x: float) -> float | None:
    return x if math.isfinite(x) else None


def cumulative_slope_2d(slopes_1d: Sequence[float]) -> np.ndarray:
    """Cumulative 2D rms slope sqrt(2 sum s_k^2) of bands with 1D rms slopes ``slopes_1d``."""
    s = np.asarray(slopes_1d, dtype=float)
    return np.sqrt(2.0 * np.cumsum(s**2))


def _build_resolved(build: Callable[[tuple[float, ...]], MultiScaleSurface],
                    edges: tuple[float, ...], names: Sequence[str], notes: dict[str, str]
                    ) -> MultiScaleSurface:
    """``build(edges)``, dropping the finest band while no measurement resolves it."""
    e = tuple(edges)
    while True:
        try:
            return build(e)
        except BandError as err:
            if len(e) <= 2:
                raise
            notes[names[len(e) - 2]] = f"no measurement resolves it ({err})"
            e = e[:-1]


def _crossing(profile: Any, lam_long: float, lam_short: float, slope_before_sq: float,
              max_slope: float) -> float:
    """Short edge lambda_c in (lam_short, lam_long) at which the cumulative 2D slope of the bands
    above (1D mean square ``slope_before_sq``) plus this band cut at lambda_c is max_slope."""
    target = max_slope**2 / 2.0 - slope_before_sq

    def excess(lam_c: float) -> float:
        sub = band_split(profile, [lam_long, lam_c], allow_unresolved=True)[0]
        return sub.rms_slope() ** 2 - target

    lo, hi = math.log(lam_short), math.log(lam_long)  # excess(lo) > 0 > excess(hi)
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        if excess(math.exp(mid)) > 0:
            lo = mid
        else:
            hi = mid
    return math.exp(hi)


def apply_cutoff(build: Callable[[tuple[float, ...]], MultiScaleSurface],
                 edges: Sequence[float], rule: CutoffRule,
                 names: Sequence[str] | None = None) -> tuple[MultiScaleSurface, CutoffReport]:
    """The multiscale surface the rule keeps of ``build(edges)``, and the report of what it did.

    ``build(e)`` makes the surface for descending edges ``e`` (e.g. ``default_road(edges=e)``)
    and raises :class:`BandError` for a band that no measurement resolves; its scales say whether
    they are measured or generated.  ``names`` label the stated bands (default: the surface's).
    """
    stated = tuple(float(e) for e in edges)
    names = list(names) if names is not None else scale_names(len(stated) - 1)
    notes: dict[str, str] = {}
    if rule.kind == "wavelength":
        lam = float(rule.wavelength)  # type: ignore[arg-type]
        if not stated[-1] * (1 - 1e-9) <= lam < stated[0]:
            raise SurfaceError(f"cutoff = {lam:g} mm: expected a wavelength between the finest "
                               f"edge {stated[-1]:g} mm and the coarsest {stated[0]:g} mm")
        kept = tuple(e for e in stated if e > lam * (1 + 1e-9)) + (lam,)
        road = build(kept)
        return road, _report(rule, stated, road, road, names, {})
    first = road = _build_resolved(build, stated, names, notes)
    n = len(road.scales)
    keep, short = n, None
    if rule.kind == "resolution":
        for i, sc in enumerate(road.scales):
            if sc.kind == "generated":
                keep = i
                break
        for nm in names[keep:n]:
            notes[nm] = "generated, not measured (cutoff = \"resolution\")"
    elif rule.kind == "slope":
        before = 0.0
        for i, sc in enumerate(road.scales):
            s2 = sc.rms_slope**2
            steep = 2.0 * (before + s2) > (rule.max_slope * (1 + SLOPE_SLACK)) ** 2
            if sc.kind == "generated" and steep:
                if 2.0 * before >= rule.max_slope**2:
                    keep = i
                    notes[names[i]] = (f"the bands above reach a cumulative 2D slope of "
                                       f"{math.sqrt(2 * before):.3g} >= max_slope "
                                       f"{rule.max_slope:g}")
                else:
                    keep = i + 1
                    short = _crossing(sc.profile, sc.band[0], sc.band[1], before, rule.max_slope)
                    if sc.band[0] / short < MIN_BAND_RATIO:
                        keep, short = i, None
                        notes[names[i]] = (f"the cumulative 2D slope reaches max_slope "
                                           f"{rule.max_slope:g} within half an octave of its "
                                           "long edge")
                for nm in names[keep:n]:
                    notes.setdefault(nm, f"below the slope cut-off of scale {names[i]}")
                break
            before += s2
    else:
        raise SurfaceError(f"unknown cut-off rule {rule.kind!r}")
    kept_edges = tuple(road.edges[: keep + 1])
    if short is not None:
        kept_edges = kept_edges[:-1] + (short,)
    if kept_edges != tuple(road.edges):
        if len(kept_edges) < 2:
            raise SurfaceError(f"{rule}: no band is left (the first band, {names[0]}, is generated "
                               "and the rule keeps measured bands only)")
        road = build(kept_edges)
    return road, _report(rule, stated, road, first, names, notes)


def _report(rule: CutoffRule, stated: tuple[float, ...], road: MultiScaleSurface,
            first: MultiScaleSurface, names: Sequence[str], notes: dict[str, str]
            ) -> CutoffReport:
    """Rows of the kept bands from ``road``, of the dropped ones from ``first`` (the surface as
    stated, where it was built: their slope and the cumulative slope had they been kept)."""
    slopes = [sc.rms_slope for sc in road.scales]
    cum = cumulative_slope_2d(slopes)
    cum_first = cumulative_slope_2d([sc.rms_slope for sc in first.scales])
    rows = []
    for i, nm in enumerate(names):
        band = (stated[i], stated[i + 1])
        if i < len(road.scales):
            sc = road.scales[i]
            shortened = not math.isclose(sc.band[1], band[1], rel_tol=1e-9)
            reason = ""
            if shortened and rule.kind == "slope":
                reason = (f"the cumulative 2D slope reaches max_slope {rule.max_slope:g} at "
                          f"{sc.band[1]:.4g} mm")
            elif shortened:
                reason = "the stated cut-off"
            rows.append(BandRow(nm, band, sc.kind, "shortened" if shortened else "kept",
                                float(slopes[i]), float(cum[i]), float(sc.band[1]), reason))
        elif i < len(first.scales):
            sc = first.scales[i]
            rows.append(BandRow(nm, band, sc.kind, "dropped", float(sc.rms_slope),
                                float(cum_first[i]), reason=notes.get(nm, "")))
        else:
            reason = notes.get(nm, "below the stated cut-off")
            rows.append(BandRow(nm, band, "", "dropped", reason=reason))
    return CutoffReport(rule, stated, tuple(road.edges), tuple(rows))
