"""Polished road: the asperity tops of a periodic sample truncated (thesis 6.5.3).

Polishing a road wears its microscopic asperities flat (thesis 6.5.3, fig. 6.26 and 6.28:
"flattening of asperities"); the thesis finds lower friction and a larger real contact area on
the polished road.  :func:`truncate_tips` models it on one periodic sample: the heights above the
level that a fraction ``f`` of the sample's points exceed are set to that level, so the tops
become flat plateaus covering about ``f`` of the period and everything below stays as it was.
:func:`polish_sample` applies it to a sample and recomputes its rms height and slope.  The scene
keys ``[surface] polish_fraction`` and ``polish_scales`` choose ``f`` and the scales
(``driver/multiscale/scales.py``, ``build_scales``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from rubberfriction.driver.surfaces.errors import SurfaceError

__all__ = ["truncate_tips", "polish_sample"]


def truncate_tips(h: np.ndarray, fraction: float) -> np.ndarray:
    """Heights of a closed periodic sample (one period, ``h[-1] == h[0]``) with its tops cut flat.

    The level c is the (1 - fraction) quantile of the period's points ``h[:-1]`` (linear
    interpolation between order statistics): a fraction ``fraction`` of them lies above c, to
    within one point.  Heights above c become c, the others are unchanged; ``min`` keeps
    ``h[-1] == h[0]``.  ``fraction = 0`` returns the heights unchanged (c is the maximum).
    """
    f = float(fraction)
    if not 0.0 <= f < 1.0:
        raise SurfaceError(f"truncate_tips: fraction = {fraction!r}: expected 0 <= fraction < 1")
    y = np.asarray(h, dtype=float)
    if y.ndim != 1 or y.size < 2:
        raise SurfaceError(f"truncate_tips: expected a closed period of at least two heights, got "
                           f"shape {y.shape}")
    if f == 0.0:
        return y.copy()
    level = float(np.quantile(y[:-1], 1.0 - f))
    return np.minimum(y, level)


def polish_sample(sample: Any, fraction: float) -> Any:
    """A copy of a periodic sample (a dataclass with ``x``, ``h``; e.g.
    :class:`~rubberfriction.driver.surfaces.samples.SurfaceSample`) with its tips truncated by
    :func:`truncate_tips`; stored ``rms_height`` / ``rms_slope`` fields are recomputed (same
    definitions as :func:`~rubberfriction.driver.surfaces.samples.extract_samples`) and a
    ``meta`` dict gets ``polish_fraction``.  ``fraction = 0`` returns the sample itself."""
    if float(fraction) == 0.0:
        return sample
    h = truncate_tips(sample.h, fraction)
    names = {f.name for f in dataclasses.fields(sample)}
    changes: dict[str, Any] = {"h": h}
    if "rms_height" in names:
        changes["rms_height"] = float(np.std(h[:-1]))
    if "rms_slope" in names:
        d = np.diff(h) / np.diff(np.asarray(sample.x, dtype=float))
        changes["rms_slope"] = float(np.sqrt(np.mean(d * d)))
    if "meta" in names:
        changes["meta"] = {**sample.meta, "polish_fraction": float(fraction)}
    return dataclasses.replace(sample, **changes)
