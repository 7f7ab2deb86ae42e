"""The multiscale road a scene's ``[surface]`` names, cut by its lowest-scale rule.

A scene states its scale edges and a cut-off rule (:mod:`rubberfriction.driver.surfaces.cutoff`);
:func:`resolve_road` builds the road (the default road, the four-scale road or measured
profiles; its heights times the scene's ``height_scale``), applies the rule and returns the road
with the kept edges and the rule's report.
:func:`tip_rows` says per scale how the sharpest asperity tip of its samples compares with the
scale's contact element size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from rubberfriction.driver.surfaces import default_road, load_profile, multiscale_from_measurements
from rubberfriction.driver.surfaces.cutoff import CutoffReport, CutoffRule, apply_cutoff
from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.four_scale import four_scale_road
from rubberfriction.driver.surfaces.multiscale import MultiScaleSurface

__all__ = ["ROAD_SOURCES", "road_builder", "resolve_road", "TipRow", "smallest_tip_radius",
           "tip_rows"]

#: [surface] sources that are band-pass decompositions of a road (not sine waves)
ROAD_SOURCES = ("default_road", "four_scale", "files")


def road_builder(source: str, files: Sequence[Path], names: Sequence[str],
                 block_lengths: Sequence[float], title: str = "", height_scale: float = 1.0
                 ) -> Callable[[tuple[float, ...]], MultiScaleSurface]:
    """``build(edges)`` for a road source; the scales keep the stated ``names`` and
    ``block_lengths`` (empty: the bands' long edges) whatever edges the cut-off leaves.

    ``height_scale`` (scene ``[surface] height_scale``, thesis 6.5.2: a rougher road) multiplies
    every band profile and carrier.  The band split is linear, so this is the road's heights
    multiplied before the bands are cut; band rms heights and slopes scale by the factor, and a
    slope cut-off rule sees the steeper bands.  1 leaves the road exactly as built."""
    k = float(height_scale)
    if not k > 0:
        raise SurfaceError(f"height_scale = {height_scale!r}: expected a factor > 0")
    profiles = [load_profile(p) for p in files] if source == "files" else []

    def build(edges: tuple[float, ...]) -> MultiScaleSurface:
        n = len(edges) - 1
        if source == "default_road":
            road = default_road(edges=edges)
        elif source == "four_scale":
            road = four_scale_road(edges)
        else:
            road = multiscale_from_measurements(profiles, edges, name=title)
        for i, sc in enumerate(road.scales):
            sc.name = names[i]
            if block_lengths:
                sc.block_length = float(block_lengths[i])
            if k != 1.0:
                sc.profile = sc.profile.with_h(k * sc.profile.h)
                if sc.carrier is not None:
                    sc.carrier = sc.carrier.with_h(k * sc.carrier.h)
        if k != 1.0:
            road.provenance["height_scale"] = k
        assert len(road.scales) == n
        return road

    return build


def resolve_road(source: str, files: Sequence[Path], edges: Sequence[float],
                 names: Sequence[str], block_lengths: Sequence[float], rule: CutoffRule,
                 title: str = "", height_scale: float = 1.0
                 ) -> tuple[MultiScaleSurface, CutoffReport]:
    """The road of a scene's ``[surface]`` with its cut-off applied (SurfaceError if impossible);
    the rule sees the bands of the road with its heights times ``height_scale``."""
    build = road_builder(source, files, names, block_lengths, title, height_scale)
    return apply_cutoff(build, edges, rule, names)


@dataclass(frozen=True)
class TipRow:
    """The sharpest tip of a scale's samples against its contact element size."""

    scale: str
    tip_radius: float  #: smallest radius of curvature at a local maximum (mm)
    element_size: float  #: lambda_short / elements_per_wavelength (mm)

    @property
    def ratio(self) -> float:
        return self.tip_radius / self.element_size

    def line(self) -> str:
        return (f"  {self.scale:<8} sharpest tip radius {self.tip_radius * 1e3:.3g} um, contact "
                f"element {self.element_size * 1e3:.3g} um (ratio {self.ratio:.2g})")


def smallest_tip_radius(x: np.ndarray, h: np.ndarray) -> float:
    """Smallest radius of curvature 1 / |h''| at the local maxima of a periodic sample
    (x uniform, h[-1] == h[0]); central differences."""
    y = np.asarray(h, dtype=float)[:-1]
    dx = float(x[1] - x[0])
    left, right = np.roll(y, 1), np.roll(y, -1)
    tops = (y > left) & (y >= right)
    if not np.any(tops):
        return math.inf
    curv = np.abs(left[tops] - 2 * y[tops] + right[tops]) / dx**2
    return float(1.0 / np.max(curv)) if np.max(curv) > 0 else math.inf


def tip_rows(sets: Sequence[Any], elements_per_wavelength: Callable[[str], int]) -> list[TipRow]:
    """One :class:`TipRow` per scale set (name, band, samples); ``elements_per_wavelength(name)``
    gives the scale's mesh setting."""
    rows = []
    for s in sets:
        r = min((smallest_tip_radius(sm.x, sm.h) for sm in s.samples), default=math.inf)
        rows.append(TipRow(s.name, r, s.band[1] / elements_per_wavelength(s.name)))
    return rows
