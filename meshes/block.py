"""Rubber block meshes (the slave body), thesis 6.2.2, 6.5.1, 8.3.3 and 8.4.1.

The block is the rectangle [0, l] x [0, h] with its contact face at z = 0. Mesh layout:

* along the contact face: equal elements of size h_contact (a regular slave surface, thesis
  6.5.1), same x-columns through the whole height (structured quadrilaterals);
* in z: graded from the contact face (geometric progression, see
  :mod:`rubberfriction.meshes.grading`): first element height `first_layer` (default
  h_contact, i.e. square cells at the contact face), each element at most `grading` times
  the one below. The left and right faces carry identical z-nodes, as the periodic conditions
  x_r - x_l = X_r - X_l of eq. (6.5) on the lower scales need;
* optional horizontal partitions (thesis 8.3.3 / 8.4.2: the thermal loop gives each partition
  its own WLF-shifted material): z-levels that are mesh lines; cell tag k (1..n) is the k-th
  layer counted from the contact face;
* optional rounded leading edge of radius r (thesis 6.5.1 and 8.5: the macroscopic sample has
  a rounded front from the run-in procedure). The block slides in +x relative to the road
  (x = sliding direction), so its front face is the right face x = l and the edge that meets
  new road first is the bottom-right corner; `leading_edge="right"` (default) rounds that
  corner. `leading_edge="left"` mirrors the block for runs that slide in -x. The arc belongs
  to the contact face (facet tag 1).

Facet tags: 1 bottom/contact (incl. the arc), 2 top, 3 left, 4 right. Cell tags: layers.

Area: exact (round-off) without rounding. With a rounded edge the arc is a polygon through
nodes on the circle; its 2 n_h elements of arc length s = (pi/2) r / (2 n_h) <= h_contact
each cut off a circular segment <= s**3 / (12 r), so the mesh area is below the exact
l h - (1 - pi/4) r**2 by at most (pi / 24) s**2, decreasing quadratically with h_contact.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from mpi4py import MPI

from rubberfriction.meshes.common import (
    CONTACT, GEOMETRY_TOL, LEFT, OPPOSITE, RIGHT, BodyMesh, build_body_mesh, contact_divisions,
    mirror_x, quads_from_index_grid, rectangle_rules, require_positive, require_ratio,
    tensor_grid)
from rubberfriction.meshes.grading import graded_nodes, growth_range

#: Thesis 6.5.1: the shortest wavelength "has to be resolved with at least a few elements";
#: the quoted ~1000 master elements for 20 mm with lambda_min = 0.2 mm are 10 per wavelength.
DEFAULT_ELEMENTS_PER_WAVELENGTH = 10
#: Thesis 6.5.1: for the slave (rubber) surface "at least twice more elements" than the master.
DEFAULT_SLAVE_TO_MASTER_RATIO = 2.0

# The corner band of a rounded edge ends at a mesh line z = t with t in this window of r
# (the inner corner (l - t, t) must lie well inside the arc: t > (1 - 1/sqrt 2) r).
_BAND_WINDOW = (0.4, 0.8)


def contact_element_size(shortest_wavelength: float,
                         elements_per_wavelength: float = DEFAULT_ELEMENTS_PER_WAVELENGTH,
                         master_segment_length: float | None = None,
                         slave_to_master_ratio: float = DEFAULT_SLAVE_TO_MASTER_RATIO) -> float:
    """Element size along the rubber contact face for a scale whose shortest surface wavelength
    is `shortest_wavelength` (mm), thesis 6.5.1.

    Rule: the master (road) segment length is `master_segment_length` when the road polyline
    is given, else shortest_wavelength / elements_per_wavelength (default 10 segments per
    wavelength); the slave is refined relative to the master:
    h_contact = master / slave_to_master_ratio (default 2, "at least twice more elements").
    """
    lam = require_positive("shortest_wavelength", shortest_wavelength)
    epw = require_positive("elements_per_wavelength", elements_per_wavelength)
    ratio = require_positive("slave_to_master_ratio", slave_to_master_ratio)
    if master_segment_length is None:
        master = lam / epw
    else:
        master = require_positive("master_segment_length", master_segment_length)
    return master / ratio


def polyline_element_size(x: np.ndarray, h: np.ndarray, period: float,
                          elements_per_wavelength: float) -> float:
    """Contact-face element size for a road polyline (x, h), mm: its shortest resolved
    wavelength / elements_per_wavelength.

    The shortest wavelength is estimated from the zero crossings of the slope (twice the mean
    spacing of slope sign changes), bounded below by 4 segments; ``period`` > 0 closes the
    polyline periodically, 0 leaves it open.  One rule for the sliding run and the scene's specs.
    """
    x, h = np.asarray(x), np.asarray(h)
    dx = np.diff(x).mean()
    L = period if period > 0 else x[-1] - x[0]
    if period > 0:  # close the period so the wrap-around slope change counts
        x, h = np.append(x, x[0] + L), np.append(h, h[0])
    slope = np.sign(np.diff(h) / np.diff(x))
    slope = slope[slope != 0]
    turns = slope[1:] != slope[:-1]
    changes = np.count_nonzero(turns) + (period > 0 and slope.size > 0 and slope[0] != slope[-1])
    lam = 2.0 * L / max(changes, 1)
    lam = max(lam, 4.0 * dx)
    return lam / elements_per_wavelength


def rubber_block(length: float, height: float, *, nx_contact: int | None = None,
                 h_contact: float | None = None, grading: float = 1.1,
                 first_layer: float | None = None, partitions: Sequence[float] | None = None,
                 leading_edge_radius: float = 0.0, leading_edge: str = "right",
                 comm: MPI.Comm = MPI.COMM_SELF) -> BodyMesh:
    """Mesh of the rubber block [0, length] x [0, height] (mm), contact face at z = 0.

    Give exactly one of `nx_contact` (elements along the contact face) and `h_contact`
    (largest allowed element size there; the count is rounded up so l/n <= h_contact).
    On the lower scales the thesis uses height = length (6.2.2).

    grading: largest ratio of consecutive element heights (>= 1; 1 = uniform).
    first_layer: height of the element row at the contact face (default: the contact
        spacing). Exact to round-off on the straight faces.
    partitions: increasing z-levels in (0, height); the cells between them get cell tags
        1..n+1 from the contact face up. Default: one layer, tag 1. With a rounded edge all
        levels must be >= leading_edge_radius.
    leading_edge_radius: r >= 0, r < height and r < length; 0 = sharp corners. With r > 0 the
        flat part of the contact face [0, l - r] keeps equal elements (count rounded up, size
        <= h_contact), the quarter arc is divided uniformly in angle into elements of arc
        length <= h_contact, z = r is a mesh line, and the rows between z = t ~ r/2 and r are
        uniform (see _rounded_grid). The left and right z-nodes then differ (the macroscopic
        block is not periodic). Needs r large enough for a graded mesh line in [0.4 r, 0.8 r]
        (roughly r >= 3 first_layer), else ValueError.
    leading_edge: 'right' (bottom-right corner, the front when sliding in +x) or 'left'.

    info keys: body, length, height, h_contact (spacing of the flat contact part),
    first_layer, grading, growth_min/growth_max (extreme ratios of consecutive element heights
    along z_nodes), z_nodes (z of the nodes on a straight vertical face: both faces if r = 0,
    else the face away from the arc), partitions,
    layers ([z_lo, z_hi] per cell tag), leading_edge_radius, leading_edge, periodic
    (left/right z-nodes identical), facet_tags, area_exact, num_cells, num_vertices,
    num_contact_facets, contact_size_min/max (facet lengths on tag 1, arc included),
    min_scaled_jacobian, and corner_band_thickness and arc_elements when r > 0.
    """
    L = require_positive("length", length)
    h = require_positive("height", height)
    g = require_ratio("grading", grading)
    r = _check_radius(leading_edge_radius, L, h)
    n = contact_divisions(L, nx_contact, h_contact)
    dx = L / n if h_contact is None or r == 0.0 else float(h_contact)
    first = dx if first_layer is None else require_positive("first_layer", first_layer)
    levels = _check_levels(partitions, h, r)
    if leading_edge not in ("right", "left"):
        raise ValueError(f"leading_edge must be 'right' or 'left', got {leading_edge!r}")

    info = {"body": "rubber_block", "length": L, "height": h, "grading": g,
            "partitions": list(levels), "leading_edge_radius": r, "leading_edge": leading_edge,
            "facet_tags": {"contact": CONTACT, "top": OPPOSITE, "left": LEFT, "right": RIGHT},
            "area_exact": L * h - (1.0 - math.pi / 4.0) * r * r, "periodic": r == 0.0}
    if r == 0.0:
        zs, _ = graded_nodes(h, first, g, levels)
        points, cells = tensor_grid(np.linspace(0.0, L, n + 1), zs)
        info["h_contact"] = L / n
    else:
        points, cells, zs, extra = _rounded_grid(L, h, r, dx, first, g, levels)
        info.update(extra)
    if leading_edge == "left":
        points, cells = mirror_x(points, cells, L)
    info.update(first_layer=float(zs[1] - zs[0]), z_nodes=zs.tolist(), **growth_range(zs),
                layers=[[a, b] for a, b in zip([0.0, *levels], [*levels, h])])
    rules = rectangle_rules(0.0, L, 0.0, h, contact="bottom")
    if r > 0.0:
        rules.append((CONTACT, _arc_predicate(L, r, leading_edge)))
    return build_body_mesh(comm, points, cells, rules, levels, info)


def _check_radius(radius: float, length: float, height: float) -> float:
    try:
        r = float(radius)
    except (TypeError, ValueError):
        raise ValueError(f"leading_edge_radius must be a number >= 0, got {radius!r}") from None
    if not math.isfinite(r) or r < 0.0:
        raise ValueError(f"leading_edge_radius must be a finite number >= 0, got {radius!r}")
    if r >= height or r >= length:
        raise ValueError(f"leading_edge_radius={radius} must be smaller than height={height} "
                         f"and length={length}")
    return r


def _check_levels(partitions: Sequence[float] | None, height: float,
                  radius: float) -> list[float]:
    if partitions is None:
        return []
    try:
        levels = [float(v) for v in partitions]
    except (TypeError, ValueError):
        raise ValueError(f"partitions must be a sequence of z-levels, got {partitions!r}") from None
    if any(not math.isfinite(v) or v <= 0.0 or v >= height for v in levels) or any(
            b <= a for a, b in zip(levels[:-1], levels[1:])):
        raise ValueError(f"partitions must be strictly increasing z-levels inside (0, "
                         f"height={height}), got {list(partitions)!r}")
    if radius > 0.0 and levels and levels[0] < radius:
        raise ValueError(f"partitions={list(partitions)!r}: with a rounded leading edge every "
                         f"level must be >= leading_edge_radius={radius}")
    return levels


def _arc_predicate(length: float, radius: float, side: str):
    """Points on the quarter arc of the rounded bottom corner."""
    cx = length - radius if side == "right" else radius
    tol = GEOMETRY_TOL * length

    def on_arc(p: np.ndarray) -> np.ndarray:
        d = np.hypot(p[:, 0] - cx, p[:, 1] - radius)
        beyond = p[:, 0] >= cx - tol if side == "right" else p[:, 0] <= cx + tol
        return (np.abs(d - radius) <= tol) & beyond & (p[:, 1] <= radius + tol)

    return on_arc


def _rounded_grid(L: float, h: float, r: float, dx: float, first: float, g: float,
                  levels: list[float]):
    """Multi-block structured grid of the block with its bottom-right corner rounded.

    Blocks: (1) the core rectangle [0, l - t] x [t, h]; (2) a band of thickness t along the
    contact face (flat part and quarter arc) whose rows are the graded layers z_0..z_k = t; in
    the corner its outer edge is the L-shaped core corner and each arc node is joined to a
    node of that L; (3) a band of the same layers along the right face above the arc. The core
    corner (l - t, t) is the one interior node with three cells, which turns the rows around
    the corner without degenerate cells.

    z-nodes: graded from the contact face up to t (a node of the graded division of [0, r]
    near r/2); [t, r] is divided uniformly into n_h rows; above r grading resumes. The arc is
    divided uniformly in angle into 2 n_h elements, n_h = ceil((pi/4) r / h_contact), so its
    elements are no larger than h_contact.
    """
    try:
        lower, _ = graded_nodes(r, first, g)
    except ValueError as err:
        raise ValueError(f"leading_edge_radius={r} is too small for first_layer={first} and "
                         f"grading={g}: {err}") from None
    window = [j for j in range(1, len(lower) - 1)
              if _BAND_WINDOW[0] * r <= lower[j] <= _BAND_WINDOW[1] * r]
    if not window:
        raise ValueError(
            f"leading_edge_radius={r} is too small for the element heights at the contact face "
            f"(first_layer={first}, grading={g}): the corner needs a mesh line between "
            f"{_BAND_WINDOW[0]} r and {_BAND_WINDOW[1]} r; use a larger radius or a smaller "
            "first_layer")
    k_t = min(window, key=lambda j: abs(lower[j] - 0.5 * r))
    t = float(lower[k_t])
    n_h = max(1, math.ceil(0.25 * math.pi * r / dx * (1.0 - 1e-12)))
    mid = np.linspace(t, r, n_h + 1)
    mid[-1] = r
    upper, _ = graded_nodes(h - r, (r - t) / n_h * g, g, [v - r for v in levels if v > r],
                            exact_first=False)
    zs = np.concatenate([lower[:k_t], mid, r + upper[1:]])
    zs[-1] = h
    xa = L - r
    n1 = max(1, math.ceil(xa / dx * (1.0 - 1e-12)))
    xs_core = np.concatenate([np.linspace(0.0, xa, n1 + 1),
                              xa + (r - t) * np.arange(1, n_h + 1) / n_h])
    zs_core = zs[k_t:]
    points, core_cells = tensor_grid(xs_core, zs_core)
    cidx = np.arange(len(points)).reshape(len(zs_core), len(xs_core))
    pts = [points]
    count = len(points)

    # band along the contact face: columns 0..n1 on the flat part, then 2 n_h arc columns
    theta = 0.25 * math.pi * np.arange(1, 2 * n_h + 1) / n_h
    inner = np.concatenate([
        np.column_stack([xs_core[:n1 + 1], np.zeros(n1 + 1)]),
        np.column_stack([xa + r * np.sin(theta), r - r * np.cos(theta)])])
    inner[-1] = (L, r)
    outer_idx = np.concatenate([cidx[0, :n1 + n_h + 1], cidx[1:n_h + 1, -1]])
    outer = points[outer_idx]
    ncol = len(inner)
    eta = zs[:k_t] / t
    band = inner[None, :, :] + eta[:, None, None] * (outer - inner)[None, :, :]
    band[:, :n1 + 1, 1] = zs[:k_t, None]               # flat part: exact graded rows
    band[:, -1, 0] = L - zs[:k_t]                        # arc end: exact layers at z = r
    band[:, -1, 1] = r
    bidx = np.vstack([count + np.arange(k_t * ncol).reshape(k_t, ncol), outer_idx[None, :]])
    pts.append(band.reshape(-1, 2))
    count += k_t * ncol
    band_cells = quads_from_index_grid(bidx)

    # band along the right face above the arc: rows z in [r, h], layers x = l - z_j
    rows = zs_core[n_h:]
    ridx = np.empty((k_t + 1, len(rows)), dtype=np.int64)
    ridx[:, 0] = bidx[:, -1]
    ridx[k_t, 1:] = cidx[n_h + 1:, -1]
    new = np.column_stack([np.repeat(L - zs[:k_t], len(rows) - 1), np.tile(rows[1:], k_t)])
    ridx[:k_t, 1:] = count + np.arange(k_t * (len(rows) - 1)).reshape(k_t, len(rows) - 1)
    pts.append(new)
    right_cells = quads_from_index_grid(ridx)

    all_points = np.vstack(pts)
    cells = np.vstack([core_cells, band_cells, right_cells])
    extra = {"h_contact": xa / n1, "corner_band_thickness": t, "arc_elements": 2 * n_h}
    return all_points, cells, zs, extra
