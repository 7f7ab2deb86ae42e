"""The macro temperature profile handed to the lower scales (thesis 8.3.3, eq. 8.1, fig. 8.3).

At a homogenisation point the rubber temperature below every active contact node x_k (where
the macro contact pressure is positive) is a column T(x_k, z) of the macro mesh; their mean over
the n_a active nodes,

    T_mean(z) = 1/n_a sum_k T(x_k, z)                                   (8.1)

with its standard deviation, is the profile every lower-scale block sees.  It is handed down as
n_p partitions of constant temperature over the depth below the contact face: the partition
bounds are levels of the macro mesh (its z resolution) and each partition's value is the mean of
the macro field over its depth range (8.3.3: "the boundary values of each partition are
averaged" -- the same number where a partition is one macro element, the linear field's mean
where it spans several).

Below the partitions every lower-scale block takes the macro field over ITS height (8.3.3: the
relaxation times are modified "over block height on all lower scales"): :meth:`Partitions.block`
adds partitions that double in thickness from the deepest one down to the block's height, each
at the macro field's mean over its range, the field beyond the macro profile's depth at the
profile's deepest value (the macro block's top, held at T0).  A block of height H thus has at
most n_p + ceil(log2(H / partition_depth)) regions.  The bounds depend on the block height only,
never on the temperatures: they are mesh lines of the lower-scale blocks, and the isothermal
cascade and every homogenisation point must mesh a block alike (warm starts continue a run's
state on the same mesh).  The result is what ``SlidingSpec.temperature_layers`` takes.
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


#: thickness ratio of consecutive partitions below ``partition_depth`` (:meth:`Partitions.block`)
DEEP_RATIO = 2.0


@dataclass(frozen=True)
class Partitions:
    """Stepwise constant representation: ((thickness mm, T K), ...) from the contact face down,
    the temperature below them, and the bounds (depths) they were taken at; ``profile``: the
    macro profile they came from (None: the layers are the whole setup, as the hot layer's)."""

    layers: tuple[tuple[float, float], ...]
    background: float
    bounds: np.ndarray
    profile: TemperatureProfile | None = None

    def block(self, height: float) -> tuple[tuple[tuple[float, float], ...], float]:
        """(layers, background) of a lower-scale block of ``height`` mm: the partitions, and
        below them (module doc) partitions down to the block's height whose thickness doubles
        (``DEEP_RATIO``) from the deepest partition's depth d: bounds d 2^k < height, the last
        dropped when the layer above it would be thinner than half the one below; each at the
        macro field's mean over its range (:func:`profile_mean`).  The background is the field
        at the block's height (no cell lies above it).  Without a profile, or for a block no
        taller than d: the partitions and background as they are."""
        height = V.positive("height", height, "mm")
        d = float(self.bounds[-1])
        if self.profile is None or height <= d * (1.0 + 1e-12):
            return self.layers, self.background
        deep = [d]
        while deep[-1] * DEEP_RATIO < height * (1.0 - 1e-12):
            deep.append(deep[-1] * DEEP_RATIO)
        if len(deep) > 1 and height - deep[-1] < 0.5 * (deep[-1] - deep[-2]):
            deep.pop()
        edges = [*deep, height]
        extra = tuple((float(b - a), profile_mean(self.profile, a, b))
                      for a, b in zip(edges[:-1], edges[1:]))
        return self.layers + extra, profile_mean(self.profile, height, height)


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


def profile_mean(profile: TemperatureProfile, a: float, b: float) -> float:
    """The mean over depths [a, b] (mm, 0 <= a <= b) of the macro field: linear between the levels
    of ``profile`` (the macro elements' linear shape functions, 8.3.3), at its deepest value
    beyond them; for a = b its value there.  Exact: the trapezoid rule on the levels inside."""
    z, T = profile.z, profile.mean
    if not 0.0 <= a <= b:
        raise ValueError(f"profile_mean: expected 0 <= a <= b, got [{a!r}, {b!r}]")
    if b - a <= 1e-14 * max(1.0, b):
        return float(np.interp(a, z, T))
    nodes = np.concatenate([[a], z[(z > a) & (z < b)], [b]])
    dev = np.interp(nodes, z, T) - T[0]  # constant beyond z[-1]; about T[0]: a uniform field
    return float(T[0] + np.sum(0.5 * (dev[1:] + dev[:-1]) * np.diff(nodes)) / (b - a))  # exactly


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
    macro grading: fine at the face); each partition's value is the macro field's mean over its
    range (:func:`profile_mean`; the mean of its two bound values where it is one macro element).
    ``Partitions.block`` continues them down a lower-scale block's height; a given
    ``background`` holds below them in every block instead (no profile is kept).  ValueError
    when n_p exceeds the m macro intervals available (the macro mesh cannot resolve finer
    partitions).
    """
    z, T = profile.z, profile.mean
    idx = partition_indices(z, n_p, depth)
    bounds = z[idx]
    layers = tuple((float(b - a), profile_mean(profile, a, b))
                   for a, b in zip(bounds[:-1], bounds[1:]))
    below = float(T[idx[-1]]) if background is None else float(background)
    return Partitions(layers, below, bounds.copy(), profile if background is None else None)
