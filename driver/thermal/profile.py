"""The macro temperature profile handed to the lower scales (thesis 8.3.3, eq. 8.1, fig. 8.3).

At a homogenisation point the rubber temperature below every active contact node x_k (where
the macro contact pressure is positive) is a column T(x_k, z) of the macro mesh; their mean over
the n_a active nodes,

    T_mean(z) = 1/n_a sum_k T(x_k, z)                                   (8.1)

with its standard deviation, is the profile every lower-scale block sees.  It is handed down as
n_p partitions of constant temperature over the depth below the contact face: the partition
bounds are levels of the macro mesh (its z resolution) and each partition's value is the mean of
the profile's values at its two bounds (8.3.3).  Below the partitions the lower-scale blocks are
at the profile's value at the deepest bound (continuity), unless the caller gives a background.
The result is what ``SlidingSpec.temperature_layers`` takes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubberfriction import validation as V


@dataclass(frozen=True)
class TemperatureProfile:
    """Eq. (8.1): depth below the contact face z (mm, increasing from 0), mean and standard
    deviation over the active contact nodes (K), and their number."""

    z: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    n_active: int


@dataclass(frozen=True)
class Partitions:
    """Stepwise constant representation: ((thickness mm, T K), ...) from the contact face down,
    the temperature below them, and the bounds (depths) they were taken at."""

    layers: tuple[tuple[float, float], ...]
    background: float
    bounds: np.ndarray


def average_profile(z: np.ndarray, T: np.ndarray, active: np.ndarray) -> TemperatureProfile:
    """Eq. (8.1) from the block's grid temperatures T (n_x, n_z) at depths z (n_z,) and the
    active contact mask (n_x,); ValueError without an active node."""
    z = np.asarray(z, dtype=float)
    T = np.asarray(T, dtype=float)
    active = np.asarray(active, dtype=bool)
    if T.shape != (active.size, z.size):
        raise ValueError(f"average_profile: T has shape {T.shape}, expected "
                         f"({active.size}, {z.size})")
    if not active.any():
        raise ValueError("average_profile: no active contact node (eq. 8.1 averages over them)")
    cols = T[active]
    return TemperatureProfile(z.copy(), cols.mean(axis=0), cols.std(axis=0), int(active.sum()))


def partition_indices(z: np.ndarray, n_p: int, depth: float) -> np.ndarray:
    """Indices into the macro levels z of the n_p + 1 partition bounds (see partition_profile)."""
    n_p = V.integer("n_p", n_p, minimum=1)
    depth = V.positive("depth", depth, "mm")
    m = int(np.searchsorted(z, depth * (1.0 + 1e-12), side="right")) - 1
    if n_p > m:
        raise ValueError(f"n_p = {n_p}: the macro mesh has only {m} element rows above depth "
                         f"{depth:g} mm; use fewer partitions, a larger depth or a finer macro "
                         "mesh (first_layer)")
    return np.rint(np.arange(n_p + 1) * m / n_p).astype(int)


def uniform_partitions(z: np.ndarray, n_p: int, depth: float, T: float) -> Partitions:
    """The partitions of a uniform temperature T on the same bounds as ``partition_profile``
    (the isothermal reference of the thermal loop: same lower-scale meshes, T0 everywhere)."""
    flat = TemperatureProfile(np.asarray(z, float), np.full(len(z), float(T)), np.zeros(len(z)), 0)
    return partition_profile(flat, n_p, depth)


def partition_profile(profile: TemperatureProfile, n_p: int, depth: float,
                      background: float | None = None) -> Partitions:
    """n_p partitions over [0, depth] on the macro mesh levels (8.3.3).

    The bounds are the levels with indices round(j m / n_p), j = 0..n_p, where the levels
    z_0 = 0 < ... < z_m are those of the profile up to ``depth`` (so the partitions follow the
    macro grading: fine at the face); each partition's value is the mean of the profile at its two
    bounds.  ValueError when n_p exceeds the m macro intervals available (the macro mesh cannot
    resolve finer partitions).
    """
    z, T = profile.z, profile.mean
    idx = partition_indices(z, n_p, depth)
    bounds = z[idx]
    values = 0.5 * (T[idx[:-1]] + T[idx[1:]])
    layers = tuple((float(b - a), float(t)) for a, b, t in zip(bounds[:-1], bounds[1:], values))
    below = float(T[idx[-1]]) if background is None else float(background)
    return Partitions(layers, below, bounds.copy())
