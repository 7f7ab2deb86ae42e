"""Body pair for the contact patch test (thesis 5.3: a mortar element must transmit a
constant pressure exactly across non-matching meshes).

Two stacked rectangles of the same length: the upper body [0, l] x [gap, gap + h_upper] with
n_upper equal elements along its contact face (bottom), the lower body [0, l] x [-h_lower, 0]
with n_lower along its contact face (top). With n_upper != n_lower the interface meshes do
not match (the default 7 against 5 puts no interior node of one face on a node of the other).
Uniform structured quadrilaterals, no grading.

Facet tags, upper body: 1 bottom (contact), 2 top, 3 left, 4 right.
Facet tags, lower body: 1 top (contact), 2 bottom, 3 left, 4 right. One cell tag, 1.
"""

from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from rubberfriction.meshes.common import (
    CONTACT, LEFT, OPPOSITE, RIGHT, BodyMesh, build_body_mesh, rectangle_rules, require_count,
    require_positive, tensor_grid)


def patch_test_pair(length: float = 1.0, height_upper: float = 0.5, height_lower: float = 0.5,
                    *, n_upper: int = 7, n_lower: int = 5, ny_upper: int | None = None,
                    ny_lower: int | None = None, gap: float = 0.0,
                    comm: MPI.Comm = MPI.COMM_SELF) -> tuple[BodyMesh, BodyMesh]:
    """(upper, lower) meshes for the patch test, see module docstring.

    ny_upper / ny_lower: element rows (default: about square cells, at least 1).
    gap: initial normal gap between the faces (upper body bottom at z = gap; negative =
    penetration).

    info keys per body: body ('patch_upper' / 'patch_lower'), length, height, nx, ny, z0, z1
    (bottom and top z), h_contact, facet_tags, area_exact, num_cells, num_vertices,
    num_contact_facets, contact_size_min/max, min_scaled_jacobian.
    """
    L = require_positive("length", length)
    hu = require_positive("height_upper", height_upper)
    hl = require_positive("height_lower", height_lower)
    nu = require_count("n_upper", n_upper)
    nl = require_count("n_lower", n_lower)
    g = float(gap)
    if not math.isfinite(g) or g <= -hl:
        raise ValueError(f"gap must be a finite number > -height_lower={hl}, got {gap!r}")
    mu = _rows("ny_upper", ny_upper, hu, L / nu)
    ml = _rows("ny_lower", ny_lower, hl, L / nl)
    upper = _body("patch_upper", L, g, g + hu, nu, mu, "bottom", comm)
    lower = _body("patch_lower", L, -hl, 0.0, nl, ml, "top", comm)
    return upper, lower


def _rows(name: str, value: int | None, height: float, dx: float) -> int:
    if value is None:
        return max(1, round(height / dx))
    return require_count(name, value)


def _body(kind: str, L: float, z0: float, z1: float, nx: int, ny: int, contact: str,
          comm: MPI.Comm) -> BodyMesh:
    zs = np.linspace(z0, z1, ny + 1)
    zs[0], zs[-1] = z0, z1
    points, cells = tensor_grid(np.linspace(0.0, L, nx + 1), zs)
    opposite = "top" if contact == "bottom" else "bottom"
    info = {"body": kind, "length": L, "height": z1 - z0, "nx": nx, "ny": ny, "z0": z0, "z1": z1,
            "h_contact": L / nx, "area_exact": L * (z1 - z0),
            "facet_tags": {"contact": CONTACT, opposite: OPPOSITE, "left": LEFT, "right": RIGHT}}
    return build_body_mesh(comm, points, cells, rectangle_rules(0.0, L, z0, z1, contact=contact),
                           (), info)
