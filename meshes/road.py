"""Road body mesh for the thermomechanical macro scale (thesis 8.3, 8.4.1).

The road is the rectangle [0, l] x [-d, 0] under the contact plane z = 0. Only thermal
macro runs need it (model only what a scene requires: a rigid road is a polyline). Thesis
8.4.1: both bodies are "refined equally in z-direction", the reference mesh has its first node
at z = 0.01 mm, so the element heights grow geometrically downward from `first_layer` (default
0.01 mm) with ratio at most `grading` (:mod:`rubberfriction.meshes.grading`); along x the
elements are equal (h_surface; the road is the master body and may be coarser in x than the
rubber).

Facet tags: 1 top (z = 0, the contact face), 2 bottom (z = -d), 3 left, 4 right. Left and
right faces carry identical z-nodes. One cell tag, 1.
"""

from __future__ import annotations

import numpy as np
from mpi4py import MPI

from rubberfriction.meshes.common import (
    CONTACT, LEFT, OPPOSITE, RIGHT, BodyMesh, build_body_mesh, contact_divisions, rectangle_rules,
    require_positive, require_ratio, tensor_grid)
from rubberfriction.meshes.grading import graded_nodes, growth_range

#: Thesis 8.4.1: position of the first macroscopic node below/above the interface (mm).
DEFAULT_FIRST_LAYER = 0.01


def road_body(length: float, depth: float, *, h_surface: float | None = None,
              nx_surface: int | None = None, first_layer: float = DEFAULT_FIRST_LAYER,
              grading: float = 1.2, comm: MPI.Comm = MPI.COMM_SELF) -> BodyMesh:
    """Mesh of the road body [0, length] x [-depth, 0] (mm), contact face at z = 0.

    Give exactly one of h_surface (largest element size along x; the count is rounded up)
    and nx_surface. first_layer: height of the element row at z = 0 (exact to round-off).
    grading: largest ratio of consecutive element heights (>= 1).

    info keys: body, length, depth, h_surface (spacing used), first_layer, grading,
    growth_min/max, z_nodes (0 down to -depth), facet_tags, area_exact, num_cells,
    num_vertices, num_contact_facets, contact_size_min/max, min_scaled_jacobian, periodic.
    """
    L = require_positive("length", length)
    d = require_positive("depth", depth)
    g = require_ratio("grading", grading)
    n = contact_divisions(L, nx_surface, h_surface, names=("nx_surface", "h_surface"))
    first = require_positive("first_layer", first_layer)
    down, _ = graded_nodes(d, first, g, name="depth")
    zs = -down[::-1]
    zs[-1] = 0.0
    points, cells = tensor_grid(np.linspace(0.0, L, n + 1), zs)
    info = {"body": "road_body", "length": L, "depth": d, "h_surface": L / n,
            "first_layer": float(down[1]), "grading": g, **growth_range(down),
            "z_nodes": (-down).tolist(), "area_exact": L * d, "periodic": True,
            "facet_tags": {"contact": CONTACT, "bottom": OPPOSITE, "left": LEFT, "right": RIGHT}}
    rules = rectangle_rules(0.0, L, -d, 0.0, contact="top")
    return build_body_mesh(comm, points, cells, rules, (), info)
