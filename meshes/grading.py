"""One-dimensional graded node distributions (pure numpy, exact to round-off).

Used for the element heights of the rubber block (fine at the contact face, thesis 6.5.1 and
8.4.1: the macroscopic mesh is "resolved much finer in z-direction", first node at 0.01 mm)
and of the road body (thesis 8.4.1).

Rule (geometric progression with a capped ratio): a layer of thickness T starting with the
element size `first` is divided into n elements of sizes first * q**i, i = 0..n-1, where n is
the smallest count for which a ratio q <= `max_ratio` reaches T, and q solves
first * (1 + q + ... + q**(n-1)) = T exactly. So the first size is exactly `first`, each
element is at most `max_ratio` times its predecessor, and the layer ends exactly at its top.
When T is not reachable with growing elements (T/first small, or max_ratio = 1 and T/first
not an integer) q comes out slightly below 1, i.e. the elements shrink a little; this is
accepted while the smallest element stays >= first / 2.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from scipy.optimize import brentq

from rubberfriction.meshes.common import require_positive, require_ratio

_TOL = 1e-12


def geometric_sizes(thickness: float, first: float, max_ratio: float) -> tuple[np.ndarray, float]:
    """Element sizes first * q**i summing to `thickness`, and the ratio q (see module rule).

    A layer thinner than (or equal to) `first` is a single element of size `thickness`.
    """
    T = require_positive("thickness", thickness)
    s = require_positive("first", first)
    r = require_ratio("max_ratio", max_ratio)
    if T <= s * (1.0 + _TOL):
        return np.array([T]), 1.0
    if r == 1.0:
        n = math.ceil(T / s * (1.0 - _TOL))
    else:
        n = math.ceil(math.log1p(T * (r - 1.0) / s) / math.log(r) * (1.0 - _TOL))
    n = max(n, 2)

    def excess(q: float) -> float:
        return s * np.polyval(np.ones(n), q) - T

    if excess(r) <= 0.0:  # reached only within round-off
        q = r
    else:
        q = brentq(excess, 0.0, r, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    return s * q ** np.arange(n), float(q)


def layer_nodes(z0: float, z1: float, sizes: np.ndarray) -> np.ndarray:
    """Node coordinates z0, z0 + s0, ... with the last node set exactly to z1."""
    nodes = z0 + np.concatenate([[0.0], np.cumsum(sizes)])
    nodes[-1] = z1
    return nodes


def graded_nodes(length: float, first: float, max_ratio: float,
                 levels: Sequence[float] = (), *, name: str = "height",
                 first_name: str = "first_layer",
                 exact_first: bool = True) -> tuple[np.ndarray, list[float]]:
    """Nodes 0 = z_0 < z_1 < ... = length, graded away from 0, with every value in `levels`
    (strictly inside (0, length), increasing) being a node.

    The layer [0, levels[0]] follows the module rule with the exact first size `first`
    (z_1 = first to round-off). Each further layer [a, b] starts with the last size of the
    layer below times `max_ratio` and follows the same rule; where that would need an element
    smaller than half its first size the layer is divided uniformly instead (nearest count).
    With exact_first=False the lowest layer is treated like the others (no error).
    Returns the nodes and the ratio used in each layer.
    """
    L = require_positive(name, length)
    s = require_positive(first_name, first)
    r = require_ratio("grading", max_ratio)
    if exact_first and s > L * (1.0 + _TOL):
        raise ValueError(f"{first_name}={first} must not exceed {name}={length}")
    bounds = [0.0, *[float(v) for v in levels], L]
    if any(b <= a for a, b in zip(bounds[:-1], bounds[1:])):
        raise ValueError(f"levels must increase strictly inside (0, {name}={length}), got "
                         f"{list(levels)!r}")
    nodes, ratios = [np.array([0.0])], []
    for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        sizes, q = geometric_sizes(b - a, s, r)
        if exact_first and k == 0 and (b - a < s * (1.0 - _TOL) or sizes.min() < 0.5 * s):
            raise ValueError(
                f"the lowest layer (0, {b}) cannot be divided into elements starting with "
                f"{first_name}={first} and growing by at most grading={max_ratio} without an "
                f"element smaller than {first_name}/2; move the level/{name} or change "
                f"{first_name} or grading")
        if (k > 0 or not exact_first) and sizes.min() < 0.5 * s:
            n = max(1, round((b - a) / s))
            sizes, q = np.full(n, (b - a) / n), 1.0
        nodes.append(layer_nodes(a, b, sizes)[1:])
        ratios.append(q)
        s = sizes[-1] * r
    return np.concatenate(nodes), ratios


def growth_range(nodes: np.ndarray) -> dict:
    """Smallest and largest ratio of consecutive element sizes along sorted `nodes`
    (1.0 for fewer than two elements)."""
    sizes = np.abs(np.diff(np.asarray(nodes, dtype=float)))
    if len(sizes) < 2:
        return {"growth_min": 1.0, "growth_max": 1.0}
    q = sizes[1:] / sizes[:-1]
    return {"growth_min": float(q.min()), "growth_max": float(q.max())}
