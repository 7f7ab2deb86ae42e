"""Temperature of a sliding block: uniform, or stepwise constant layers over its height.

The thermal multiscale loop (thesis 8.3.2, 8.3.3) hands every lower-scale block the macro
temperature profile below the contact face as a few partitions of constant temperature (fig.
8.3 b): the block's relaxation times are shifted by WLF (eqs. 3.33, 3.37) partition by partition.
A layer is (thickness mm, temperature K), counted from the contact face upwards; the block above
the last layer is at the spec's ``temperature`` (the background T0; None: the WLF reference).
The layer bounds inside the block are mesh lines (``layer_levels``, passed to the block mesh), so
every cell lies in one layer and takes its temperature (the Prony histories carry one relaxation
time per term and cell): the FE block represents the layers exactly.
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


def layer_levels(layers: Layers, height: float) -> list[float]:
    """Heights of the layer bounds above the contact face that lie inside a block of ``height``
    (bounds closer than 1e-9 height to the top or to each other are dropped)."""
    tol = 1e-9 * height
    out: list[float] = []
    for z in np.cumsum([d for d, _ in layers]):
        if z < height - tol and (not out or z > out[-1] + tol):
            out.append(float(z))
    return out
