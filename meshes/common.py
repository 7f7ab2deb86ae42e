"""Shared pieces of the mesh builders: the returned dataclass, tag numbers, input checks,
structured quadrilateral grids and the conversion of point/cell arrays into a checked
DOLFINx mesh with cell and facet tags.

Conventions (README "Conventions", CONTRIBUTING.md): units mm; plane strain in the x-z plane
stored as (x, y) with x the sliding direction and z up. Every body carries facet tags

    1 = contact face, 2 = the face opposite to it, 3 = left (x = x_min), 4 = right (x = x_max)

so for the rubber block 1 is the bottom and 2 the top, for the road body 1 is the top and
2 the bottom. Cells are first-order quadrilaterals only (one cell type, as DOLFINx needs).
Cell vertex order is the DOLFINx/basix tensor order (0,0), (1,0), (0,1), (1,1) of the
reference square; every builder makes the map from the reference square orientation
preserving (det J > 0 everywhere) and checks it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from mpi4py import MPI

import dolfinx
import dolfinx.cpp.mesh
import dolfinx.mesh
import ufl

CONTACT = 1
OPPOSITE = 2
LEFT = 3
RIGHT = 4

# Coordinates closer than this (relative to the body size) to a face count as lying on it.
GEOMETRY_TOL = 1e-9

# Vertex order: around the cell (gmsh, VTK) -> DOLFINx tensor order. Kept here rather than
# taken from dolfinx.io.gmshio, whose import imports gmsh and so resets the SIGINT handler.
_AROUND_TO_DOLFINX = [0, 1, 3, 2]

FacetRule = tuple[int, Callable[[np.ndarray], np.ndarray]]


@dataclass(frozen=True)
class BodyMesh:
    """A meshed body: DOLFINx mesh, cell tags (layers, 1..n from the contact face),
    facet tags (see module docstring) and `info`, a dict of plain Python numbers, strings and
    lists describing what was built (element counts, sizes at the contact face, grading,
    parameters). Keys are documented by each builder."""

    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTagsMetaClass
    facet_tags: dolfinx.mesh.MeshTagsMetaClass
    info: dict = field(default_factory=dict)


# --------------------------------------------------------------------------- input checks
def require_positive(name: str, value: float) -> float:
    """Return `value` as float if it is finite and > 0, else raise a ValueError naming it."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number (mm), got {value!r}")
    return v


def require_ratio(name: str, value: float) -> float:
    """Growth ratios are finite numbers >= 1 (1 = uniform)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number >= 1, got {value!r}") from None
    if not math.isfinite(v) or v < 1.0:
        raise ValueError(f"{name} must be a finite growth ratio >= 1 (1 = uniform), got {value!r}")
    return v


def require_count(name: str, value: int) -> int:
    """Element counts are integers >= 1."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def contact_divisions(length: float, nx_contact: int | None, h_contact: float | None,
                      *, names: tuple[str, str] = ("nx_contact", "h_contact")) -> int:
    """Number of equal elements along a straight contact face of `length`.

    Exactly one of `nx_contact` and `h_contact` must be given. A size is turned into the
    smallest count whose spacing length/n does not exceed it (so the face is never coarser
    than asked); the spacing actually used is length/n.
    """
    if (nx_contact is None) == (h_contact is None):
        raise ValueError(f"give exactly one of {names[0]} and {names[1]} "
                         f"(got {names[0]}={nx_contact!r}, {names[1]}={h_contact!r})")
    if nx_contact is not None:
        return require_count(names[0], nx_contact)
    h = require_positive(names[1], h_contact)
    return max(1, math.ceil(length / h * (1.0 - 1e-12)))


# --------------------------------------------------------------------------- grids
def tensor_grid(xs: np.ndarray, zs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points (N, 2) and quadrilateral cells (M, 4) of the tensor-product grid xs x zs.

    xs and zs must be strictly increasing. Node (i, j) at (xs[i], zs[j]) has index
    j * len(xs) + i; cell vertices are in DOLFINx order, so det J > 0.
    """
    xs = np.asarray(xs, dtype=float)
    zs = np.asarray(zs, dtype=float)
    X, Z = np.meshgrid(xs, zs)  # shape (len(zs), len(xs))
    points = np.column_stack([X.ravel(), Z.ravel()])
    idx = np.arange(len(xs) * len(zs)).reshape(len(zs), len(xs))
    return points, quads_from_index_grid(idx)


def quads_from_index_grid(idx: np.ndarray) -> np.ndarray:
    """Cells of a logically structured block whose node indices are idx[j, i]
    (i along the first tangential direction, j along the second; right-handed)."""
    return np.column_stack([idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(),
                            idx[1:, :-1].ravel(), idx[1:, 1:].ravel()])


def orient_and_reorder_gmsh_quads(points: np.ndarray, quads_ccw: np.ndarray) -> np.ndarray:
    """Turn gmsh quadrilaterals (vertices around the cell) into counter-clockwise cells in
    DOLFINx vertex order."""
    p = points[quads_ccw]
    signed = 0.5 * sum(p[:, k, 0] * p[:, (k + 1) % 4, 1] - p[:, (k + 1) % 4, 0] * p[:, k, 1]
                       for k in range(4))
    q = quads_ccw.copy()
    q[signed < 0] = q[signed < 0][:, ::-1]
    return q[:, _AROUND_TO_DOLFINX]


def mirror_x(points: np.ndarray, cells: np.ndarray,
             length: float) -> tuple[np.ndarray, np.ndarray]:
    """Mirror x -> length - x, keeping det J > 0 by swapping the reference xi direction."""
    p = points.copy()
    p[:, 0] = length - p[:, 0]
    return p, cells[:, [1, 0, 3, 2]]


# --------------------------------------------------------------------------- quality
def corner_jacobians(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """det J and the scaled Jacobian det J / (|dX/dxi| |dX/deta|) of the bilinear map at the
    four corners of every cell (cells in DOLFINx order). For a bilinear quadrilateral det J is
    affine in (xi, eta), so positive corner values mean det J > 0 in the whole cell, in
    particular at every quadrature point."""
    p0, p1, p2, p3 = (points[cells[:, k]] for k in range(4))
    dets, scaled = [], []
    for xi, eta in ((0, 0), (1, 0), (0, 1), (1, 1)):
        a = (1 - eta) * (p1 - p0) + eta * (p3 - p2)
        b = (1 - xi) * (p2 - p0) + xi * (p3 - p1)
        det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        dets.append(det)
        scaled.append(det / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)))
    return np.min(dets, axis=0), np.min(scaled, axis=0)


def check_quadrilateral_mesh(mesh: dolfinx.mesh.Mesh) -> float:
    """Assert the DOLFINx mesh is a single-type first-order quadrilateral mesh whose cells all
    have det J > 0; return the smallest scaled Jacobian (global over the communicator)."""
    if mesh.topology.cell_type != dolfinx.mesh.CellType.quadrilateral:
        raise RuntimeError(f"mesh cell type is {mesh.topology.cell_type}, expected quadrilateral")
    dofmap = mesh.geometry.dofmap
    cells = np.array([dofmap.links(c) for c in range(dofmap.num_nodes)], dtype=np.int64)
    cells = cells.reshape(-1, 4)
    det, scaled = corner_jacobians(mesh.geometry.x[:, :2], cells)
    local_min = float(scaled.min()) if len(scaled) else 1.0
    local_det = float(det.min()) if len(det) else 1.0
    if mesh.comm.allreduce(local_det, op=MPI.MIN) <= 0.0:
        raise RuntimeError("mesh has cells with a non-positive Jacobian (inverted or degenerate)")
    return mesh.comm.allreduce(local_min, op=MPI.MIN)


# --------------------------------------------------------------------------- DOLFINx
def build_body_mesh(comm: MPI.Comm, points: np.ndarray, cells: np.ndarray,
                    facet_rules: Sequence[FacetRule], layer_levels: Sequence[float] = (),
                    info: dict | None = None) -> BodyMesh:
    """Create the DOLFINx mesh from points (N, 2) and cells (M, 4, DOLFINx order) given on
    rank 0 of `comm`, tag cells and exterior facets, check the cells and fill `info`.

    facet_rules: (tag, predicate) pairs; an exterior facet gets `tag` when the predicate holds
    for both of its end points. Every exterior facet must match exactly one rule.
    layer_levels: increasing z-levels; a cell gets tag k + 1 where k is the number of levels
    below its centroid (tag 1 = the layer at the contact face for a body above z = 0).
    """
    if points.ndim != 2 or points.shape[1] != 2 or cells.ndim != 2 or cells.shape[1] != 4:
        raise ValueError("points must be (N, 2) and cells (M, 4)")
    det, _ = corner_jacobians(points, cells)
    if len(det) and det.min() <= 0.0:
        raise RuntimeError("internal error: built cells with non-positive Jacobian")
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", ufl.Cell("quadrilateral",
                                                             geometric_dimension=2), 1))
    if comm.rank == 0:
        c, x = cells.astype(np.int64), np.ascontiguousarray(points, dtype=float)
    else:
        c, x = np.empty((0, 4), dtype=np.int64), np.empty((0, 2), dtype=float)
    mesh = dolfinx.mesh.create_mesh(comm, c, x, domain)
    cell_tags = _tag_cells(mesh, layer_levels)
    facet_tags = _tag_exterior_facets(mesh, facet_rules)
    out = dict(info or {})
    out["num_cells"] = mesh.topology.index_map(2).size_global
    out["num_vertices"] = mesh.topology.index_map(0).size_global
    out["min_scaled_jacobian"] = check_quadrilateral_mesh(mesh)
    out.update(_facet_length_stats(mesh, facet_tags, CONTACT, "contact"))
    return BodyMesh(mesh=mesh, cell_tags=cell_tags, facet_tags=facet_tags, info=out)


def _tag_cells(mesh: dolfinx.mesh.Mesh, levels: Sequence[float]) -> dolfinx.mesh.MeshTagsMetaClass:
    imap = mesh.topology.index_map(2)
    cells = np.arange(imap.size_local + imap.num_ghosts, dtype=np.int32)
    z = dolfinx.mesh.compute_midpoints(mesh, 2, cells)[:, 1]
    values = 1 + np.searchsorted(np.asarray(levels, dtype=float), z).astype(np.int32)
    return dolfinx.mesh.meshtags(mesh, 2, cells, values.astype(np.int32))


def _facet_points(mesh: dolfinx.mesh.Mesh, facets: np.ndarray) -> np.ndarray:
    """(F, 2, 2) end point coordinates of the given facets."""
    geo = dolfinx.cpp.mesh.entities_to_geometry(mesh._mesh, 1, facets, False)
    return mesh.geometry.x[geo][:, :, :2]


def _tag_exterior_facets(mesh: dolfinx.mesh.Mesh,
                         rules: Sequence[FacetRule]) -> dolfinx.mesh.MeshTagsMetaClass:
    mesh.topology.create_connectivity(1, 2)
    facets = np.sort(dolfinx.mesh.exterior_facet_indices(mesh.topology)).astype(np.int32)
    pts = _facet_points(mesh, facets)
    values = np.zeros(len(facets), dtype=np.int32)
    hits = np.zeros(len(facets), dtype=np.int32)
    for tag, predicate in rules:
        ok = predicate(pts[:, 0, :]) & predicate(pts[:, 1, :])
        values[ok] = tag
        hits += ok
    if np.any(hits != 1):
        bad = pts[hits != 1][0]
        raise RuntimeError(f"exterior facet {bad.tolist()} matches {int(hits[hits != 1][0])} "
                           "boundary rules (expected exactly one)")
    return dolfinx.mesh.meshtags(mesh, 1, facets, values)


def _facet_length_stats(mesh: dolfinx.mesh.Mesh, facet_tags: dolfinx.mesh.MeshTagsMetaClass,
                        tag: int, name: str) -> dict:
    """Count, min and max length of the facets with `tag` (owned facets only, global)."""
    n_owned = mesh.topology.index_map(1).size_local
    facets = facet_tags.indices[(facet_tags.values == tag) & (facet_tags.indices < n_owned)]
    pts = _facet_points(mesh, facets.astype(np.int32))
    lengths = np.linalg.norm(pts[:, 1] - pts[:, 0], axis=1)
    comm = mesh.comm
    return {
        f"num_{name}_facets": comm.allreduce(len(lengths), op=MPI.SUM),
        f"{name}_size_min": comm.allreduce(float(lengths.min()) if len(lengths) else math.inf,
                                           op=MPI.MIN),
        f"{name}_size_max": comm.allreduce(float(lengths.max()) if len(lengths) else 0.0,
                                           op=MPI.MAX),
    }


def rectangle_rules(x0: float, x1: float, z0: float, z1: float, *, contact: str) -> list[FacetRule]:
    """Facet rules of an axis-parallel rectangle; `contact` is 'bottom' or 'top' and names the
    face that gets tag 1 (the opposite face gets 2); left is 3, right is 4."""
    tol = GEOMETRY_TOL * max(x1 - x0, z1 - z0)
    bottom = (lambda p: np.abs(p[:, 1] - z0) <= tol)
    top = (lambda p: np.abs(p[:, 1] - z1) <= tol)
    left = (lambda p: np.abs(p[:, 0] - x0) <= tol)
    right = (lambda p: np.abs(p[:, 0] - x1) <= tol)
    if contact == "bottom":
        return [(CONTACT, bottom), (OPPOSITE, top), (LEFT, left), (RIGHT, right)]
    if contact == "top":
        return [(CONTACT, top), (OPPOSITE, bottom), (LEFT, left), (RIGHT, right)]
    raise ValueError(f"contact must be 'bottom' or 'top', got {contact!r}")
