"""Cylinder for the Hertz contact verification case (plane strain, thesis 5.3).

Geometry: the lower half of the disc of radius R centred at (0, R), so the lowest point
(0, 0) touches the plane z = 0; the flat cut z = R is on top (the load is applied there).
With quarter=True only x >= 0 is meshed and x = 0 is a symmetry line.

Mesh: the contact zone |x| <= contact_width of the arc is divided uniformly in angle with
elements of arc length <= h_contact (the lowest point (0, 0) is a node, the first contact
point). Away from it the element size grows linearly with the distance d from the contact
zone, size = min(h_contact + (grading - 1) d, max_size), which is the continuous form of a
geometric progression with ratio `grading`. gmsh (4.8) meshes the disc with
frontal-Delaunay triangles at twice these sizes, recombines them and splits every
cell into quadrilaterals (Mesh.SubdivisionAlgorithm = 1; new boundary nodes are placed on the
circle). Recombination alone leaves triangles whenever a boundary has an odd number of edges,
and the 'full-quad' recombination of gmsh 4.8 aborts on odd transfinite curves, so the
subdivision is what guarantees a single cell type. Checked: only quadrilaterals (else
RuntimeError) and det J > 0 everywhere.

Facet tags: 1 curved boundary (contact), 2 flat top (load), 3 symmetry line x = 0 (quarter
only). One cell tag, 1.

Area: the mesh is the polygon through the boundary nodes, which lie on the circle. A boundary
element of arc length s cuts off a circular segment of area <= s**3 / (12 R), so the mesh area
is smaller than pi R**2 / 2 by at most (pi / 12) s_max**2 (half disc; half of that for the
quarter), s_max the largest boundary element (about max_size); the error decreases
quadratically with max_size.
"""

from __future__ import annotations

import math

import numpy as np
from mpi4py import MPI

from rubberfriction.meshes._gmsh import gmsh_session, quad_mesh_arrays
from rubberfriction.meshes.common import (
    CONTACT, GEOMETRY_TOL, LEFT, OPPOSITE, BodyMesh, build_body_mesh,
    orient_and_reorder_gmsh_quads, require_positive, require_ratio)

#: Default largest element size as a fraction of the radius.
DEFAULT_MAX_SIZE_FRACTION = 1.0 / 8.0


def hertz_cylinder(radius: float, *, h_contact: float, contact_width: float,
                   grading: float = 1.2, max_size: float | None = None, quarter: bool = False,
                   verbose: bool = False, comm: MPI.Comm = MPI.COMM_SELF) -> BodyMesh:
    """Half (or quarter) disc mesh for the Hertz case, see module docstring.

    radius: R (mm). h_contact: largest element arc length in the contact zone.
    contact_width: half-width of the refined zone in x, 0 < contact_width <= R/2 (choose it
    somewhat larger than the expected Hertz half-width a). grading >= 1: growth of the element
    size away from the zone. max_size: largest element size (default R/8; must be >=
    h_contact). verbose: let gmsh print to the terminal.

    info keys: body, radius, h_contact, contact_width, grading, max_size, quarter,
    contact_zone_half_angle, contact_zone_elements (elements on the refined arc),
    contact_zone_size (their chord length), facet_tags, area_exact, num_cells, num_vertices,
    num_contact_facets, contact_size_min/max (all arc facets), min_scaled_jacobian.
    """
    R = require_positive("radius", radius)
    hc = require_positive("h_contact", h_contact)
    w = require_positive("contact_width", contact_width)
    g = require_ratio("grading", grading)
    if w > 0.5 * R:
        raise ValueError(f"contact_width={contact_width} must be <= radius/2 = {0.5 * R}")
    if hc > w:
        raise ValueError(f"h_contact={h_contact} must not exceed contact_width={contact_width}")
    hmax = R * DEFAULT_MAX_SIZE_FRACTION if max_size is None else require_positive(
        "max_size", max_size)
    if hmax < hc:
        raise ValueError(f"max_size={max_size} must be >= h_contact={h_contact}")
    alpha = math.asin(w / R)
    # gmsh meshes with twice the sizes, then splits every cell into quadrilaterals
    # (Mesh.SubdivisionAlgorithm = 1), which halves every edge and guarantees an all-quad mesh.
    n_coarse = math.ceil(R * alpha / (2.0 * hc) * (1.0 - 1e-12))
    n_half = 2 * n_coarse
    if comm.rank == 0:  # gmsh runs on one rank; DOLFINx distributes the mesh
        with gmsh_session("hertz_cylinder", verbose) as gmsh:
            contact_curves = _geometry(gmsh, R, alpha, quarter)
            for c in contact_curves:
                gmsh.model.mesh.setTransfiniteCurve(c, n_coarse + 1)
            _size_field(gmsh, contact_curves, 2.0 * hc, 2.0 * hmax, g, n_coarse)
            gmsh.model.mesh.generate(2)
            points, quads = quad_mesh_arrays(gmsh)
        cells = orient_and_reorder_gmsh_quads(points, quads)
    else:
        points, cells = np.empty((0, 2)), np.empty((0, 4), dtype=np.int64)
    tol = GEOMETRY_TOL * R
    rules = [(CONTACT, lambda p: np.abs(np.hypot(p[:, 0], p[:, 1] - R) - R) <= tol),
             (OPPOSITE, lambda p: np.abs(p[:, 1] - R) <= tol)]
    tags = {"contact": CONTACT, "top": OPPOSITE}
    if quarter:
        rules.append((LEFT, lambda p: np.abs(p[:, 0]) <= tol))
        tags["symmetry"] = LEFT
    info = {"body": "hertz_cylinder", "radius": R, "h_contact": hc, "contact_width": w,
            "grading": g, "max_size": hmax, "quarter": bool(quarter),
            "contact_zone_half_angle": alpha,
            "contact_zone_elements": n_half * (1 if quarter else 2),
            "contact_zone_size": 2.0 * R * math.sin(0.5 * alpha / n_half),
            "facet_tags": tags, "area_exact": math.pi * R * R / (4.0 if quarter else 2.0)}
    return build_body_mesh(comm, points, cells, rules, (), info)


def _geometry(gmsh, R: float, alpha: float, quarter: bool) -> list[int]:
    """Build the (half or quarter) disc in the built-in kernel, boundary counter-clockwise;
    return the curve tags of the contact zone arcs."""
    geo = gmsh.model.geo
    s, c = R * math.sin(alpha), R - R * math.cos(alpha)
    centre = geo.addPoint(0.0, R, 0.0)
    bottom = geo.addPoint(0.0, 0.0, 0.0)
    q_r, p_r = geo.addPoint(s, c, 0.0), geo.addPoint(R, R, 0.0)
    zone = [geo.addCircleArc(bottom, centre, q_r)]
    right = geo.addCircleArc(q_r, centre, p_r)
    if quarter:
        loop = [zone[0], right, geo.addLine(p_r, centre), geo.addLine(centre, bottom)]
    else:
        q_l, p_l = geo.addPoint(-s, c, 0.0), geo.addPoint(-R, R, 0.0)
        left = geo.addCircleArc(p_l, centre, q_l)
        zone.insert(0, geo.addCircleArc(q_l, centre, bottom))
        loop = [left, zone[0], zone[1], right, geo.addLine(p_r, p_l)]
    geo.addPlaneSurface([geo.addCurveLoop(loop)])
    geo.synchronize()
    return zone


def _size_field(gmsh, curves: list[int], hc: float, hmax: float, g: float, n: int) -> None:
    """Element size hc + (grading - 1) * distance, capped at hmax (before subdivision);
    recombination followed by the all-quadrilateral subdivision. The 'simple' recombination
    is used: over a parameter sweep (R, h_contact, width, grading, half/quarter) its worst
    cell had a scaled Jacobian of 0.39 against 0.12 for Blossom."""
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "CurvesList", curves)
    field.setNumber(dist, "NumPointsPerCurve", max(50, 8 * n))
    size = field.add("Threshold")
    field.setNumber(size, "InField", dist)
    field.setNumber(size, "SizeMin", hc)
    field.setNumber(size, "SizeMax", hmax if g > 1.0 else hc)
    field.setNumber(size, "DistMin", 0.0)
    field.setNumber(size, "DistMax", (hmax - hc) / (g - 1.0) if g > 1.0 else 1.0)
    field.setAsBackgroundMesh(size)
    for name, value in {"Mesh.MeshSizeExtendFromBoundary": 0, "Mesh.MeshSizeFromPoints": 0,
                        "Mesh.MeshSizeFromCurvature": 0, "Mesh.Algorithm": 6,
                        "Mesh.RecombineAll": 1, "Mesh.RecombinationAlgorithm": 0,
                        "Mesh.SubdivisionAlgorithm": 1, "Mesh.ElementOrder": 1}.items():
        gmsh.option.setNumber(name, value)
