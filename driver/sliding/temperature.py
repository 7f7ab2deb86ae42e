"""Temperature of a sliding block: uniform, or stepwise constant layers over its height.

The thermal multiscale loop (thesis 8.3.2, 8.3.3) hands every lower-scale block the macro
temperature profile below the contact face as a few partitions of constant temperature (fig.
8.3 b): the block's relaxation times are shifted by WLF (eqs. 3.33, 3.37) partition by partition.
A layer is (thickness mm, temperature K), counted from the contact face upwards; the block above
the last layer is at the spec's ``temperature`` (the background T0; None: the WLF reference).
The layer bounds inside the block are mesh lines (``mesh_levels``, passed to the block mesh), so
every cell lies in one layer and takes its temperature (the Prony histories carry one relaxation
time per term and cell): the FE block represents the layers exactly.  Except where a bound would
make an element row thinner than ``MIN_ROW_FRACTION`` of the contact spacing: the thesis' 0.09 mm
partitions on a millimetre scale (the default road's 20-3 mm band, contact elements 0.5 mm) made
rows 22 times flatter than wide, and a run that converges without them carried 13 % of its
friction work in stabilisation.  Such layers are finer than the scale's mesh resolves (thesis
8.3.3: partitions on the resolution of the mesh): the cells they cross take the thickness-weighted
mean temperature over their height (``cell_temperatures``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

Layers = tuple[tuple[float, float], ...]


def check_layers(layers: Any, compound: Any, field: str = "temperature_layers") -> Layers:
    """The layers as a tuple of (thickness, T) floats; ValueError naming ``field`` otherwise.

    Thicknesses must be positive and finite, temperatures above the WLF singularity of the
    compound, and the compound must have WLF data at all.
    """
    try:
        out = tuple((float(d), float(T)) for d, T in layers)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected a sequence of (thickness mm, temperature K) pairs, "
                         f"got {layers!r}") from None
    if not out:
        return out
    wlf = getattr(compound, "wlf", None)
    if wlf is None:
        raise ValueError(f"{field}: compound {getattr(compound, 'name', '?')!r} has no WLF data, "
                         "so its relaxation times cannot follow a temperature")
    for i, (d, T) in enumerate(out):
        if not (np.isfinite(d) and d > 0.0):
            raise ValueError(f"{field}[{i}]: thickness {d!r} mm, expected > 0")
        if not (np.isfinite(T) and T > wlf.T_singular):
            raise ValueError(f"{field}[{i}]: temperature {T!r} K, expected above the WLF "
                             f"singularity T_ref - c2 = {wlf.T_singular:g} K")
    return out


def surface_temperature(layers: Layers, background: float | None) -> float | None:
    """Temperature at the contact face: the first layer's, else the background."""
    return layers[0][1] if layers else background


def layer_temperatures(layers: Layers, background: float, depth: np.ndarray) -> np.ndarray:
    """Temperature at each depth below the contact face (mm, >= 0): the layer containing it
    (a depth on a boundary belongs to the deeper layer), ``background`` below the last."""
    depth = np.asarray(depth, dtype=float)
    T = np.full(depth.shape, float(background))
    if not layers:
        return T
    bounds = np.cumsum([d for d, _ in layers])
    temps = np.array([t for _, t in layers])
    k = np.searchsorted(bounds, depth, side="right")
    inside = k < len(layers)
    T[inside] = temps[k[inside]]
    return T


#: a layer bound becomes a mesh line only where the element rows it bounds stay at least this
#: fraction of the contact spacing thick (aspect ratio at most 4 at the contact face)
MIN_ROW_FRACTION = 0.25


def cell_temperatures(layers: Layers, background: float, lower: np.ndarray,
                      upper: np.ndarray) -> np.ndarray:
    """Temperature of cells spanning depths [lower, upper] below the contact face (mm): a cell
    inside one layer (or below them) gets that temperature exactly; a cell a layer bound crosses
    gets the mean over its span, weighted by thickness (the background below the last layer)."""
    lo = np.asarray(lower, dtype=float)
    hi = np.asarray(upper, dtype=float)
    T = layer_temperatures(layers, background, 0.5 * (lo + hi))
    if not layers:
        return T
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in layers])])
    tol = 1e-9 * max(float(bounds[-1]), float(np.max(hi, initial=0.0)))
    inner = bounds[None, 1:]
    crossed = np.any((inner > lo[:, None] + tol) & (inner < hi[:, None] - tol), axis=1)
    if crossed.any():
        a, b = lo[crossed, None], hi[crossed, None]
        pieces = np.clip(np.minimum(b, inner) - np.maximum(a, bounds[None, :-1]), 0.0, None)
        below = np.clip(b[:, 0] - np.maximum(a[:, 0], bounds[-1]), 0.0, None)
        temps = np.array([t for _, t in layers])
        T[crossed] = (pieces @ temps + background * below) / (pieces.sum(axis=1) + below)
    return T


def mesh_levels(layers: Layers, height: float, min_row: float) -> list[float]:
    """The layer bounds (``layer_levels``) that become mesh lines of a block whose contact face
    is meshed with rows of about ``min_row / MIN_ROW_FRACTION``: those at least ``min_row`` above
    the face and above the last kept bound, and ``min_row`` below the top."""
    out: list[float] = []
    for z in layer_levels(layers, height):
        if z >= min_row and z - (out[-1] if out else 0.0) >= min_row and height - z >= min_row:
            out.append(z)
    return out


def layer_levels(layers: Layers, height: float) -> list[float]:
    """Heights of the layer bounds above the contact face that lie inside a block of ``height``
    (bounds closer than 1e-9 height to the top or to each other are dropped)."""
    tol = 1e-9 * height
    out: list[float] = []
    for z in np.cumsum([d for d, _ in layers]):
        if z < height - tol and (not out or z > out[-1] + tol):
            out.append(float(z))
    return out
