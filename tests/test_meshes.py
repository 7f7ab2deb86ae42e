"""Meshes: single cell type, exact areas and face lengths, grading, periodic node match,
determinism, positive Jacobians, clear errors (rubberfriction.meshes).

Tolerances: straight geometry is exact to round-off, checked at 1e-12 relative. Curved
boundaries (rounded edge, cylinder) are polygons through nodes on the circle: the area deficit
must equal the sum of the circular segments cut off by the boundary chords (1e-10 relative,
i.e. nodes on the circle, no gaps/overlaps), stay below the stated bound
(pi / 12) s_max**2 per half circle (s_max the largest element arc length; pi / 24 for a
quarter arc) and shrink when the mesh is refined.
"""

from __future__ import annotations

import math
import shutil
import subprocess
import sys
from pathlib import Path

import basix
import numpy as np
import pytest
import ufl

import dolfinx.cpp.mesh
import dolfinx.fem
import dolfinx.mesh
from conftest import missing
from rubberfriction.meshes import (
    CONTACT, LEFT, OPPOSITE, RIGHT, contact_element_size, geometric_sizes, graded_nodes,
    hertz_cylinder, patch_test_pair, road_body, rubber_block)
from rubberfriction.meshes.block import polyline_element_size

REL = 1e-12


# ----------------------------------------------------------------------------- helpers
def assemble(form) -> float:
    return dolfinx.fem.assemble_scalar(dolfinx.fem.form(form))


def area(body, tag=None) -> float:
    dx = ufl.Measure("dx", domain=body.mesh, subdomain_data=body.cell_tags)
    one = dolfinx.fem.Constant(body.mesh, 1.0)
    return assemble(one * (dx if tag is None else dx(tag)))


def face_length(body, tag: int) -> float:
    ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
    return assemble(dolfinx.fem.Constant(body.mesh, 1.0) * ds(tag))


def facet_points(body, tag: int) -> np.ndarray:
    """(F, 2, 2) end points of the facets with `tag`."""
    facets = body.facet_tags.indices[body.facet_tags.values == tag]
    geo = dolfinx.cpp.mesh.entities_to_geometry(body.mesh._mesh, 1, facets, False)
    return body.mesh.geometry.x[geo][:, :, :2]


def face_nodes(body, axis: int, value: float, tol: float = 1e-9) -> np.ndarray:
    """Coordinates of the mesh nodes with x[axis] == value, sorted along the other axis."""
    x = body.mesh.geometry.x[:, :2]
    pts = x[np.abs(x[:, axis] - value) <= tol]
    return pts[np.argsort(pts[:, 1 - axis])]


def min_jacobian_at_quadrature_points(body, degree: int = 4) -> float:
    """det J of the DOLFINx geometry map at Gauss points of every cell (UFL/FFCx, independent
    of the builders' own corner check)."""
    pts, _ = basix.make_quadrature(basix.CellType.quadrilateral, degree)
    expr = dolfinx.fem.Expression(ufl.JacobianDeterminant(body.mesh), pts)
    imap = body.mesh.topology.index_map(2)
    cells = np.arange(imap.size_local, dtype=np.int32)
    return float(np.min(expr.eval(cells)))


def circular_segments(chords: np.ndarray, radius: float) -> float:
    """Total area between a circle of `radius` and the given chords (lengths)."""
    theta = 2.0 * np.arcsin(np.clip(chords / (2.0 * radius), 0.0, 1.0))
    return float(np.sum(0.5 * radius**2 * (theta - np.sin(theta))))


def arc_lengths(chords: np.ndarray, radius: float) -> np.ndarray:
    return 2.0 * radius * np.arcsin(chords / (2.0 * radius))


def arc_chords(body, centre: tuple[float, float], radius: float) -> np.ndarray:
    """Lengths of contact facets whose two end points lie on the given circle."""
    p = facet_points(body, CONTACT)
    d = np.hypot(p[:, :, 0] - centre[0], p[:, :, 1] - centre[1])
    on = np.all(np.abs(d - radius) <= 1e-9 * radius, axis=1)
    return np.linalg.norm(p[on, 1] - p[on, 0], axis=1)


def assert_rel(a: float, b: float, tol: float = REL) -> None:
    assert abs(a - b) <= tol * max(abs(b), 1.0), (a, b)


# ----------------------------------------------------------------------------- grading
@pytest.mark.parametrize("T,first,ratio", [(1.0, 0.01, 1.1), (8.0, 0.01, 1.2), (1.0, 0.05, 1.0),
                                           (1.0, 0.3, 1.0), (3.3, 0.1, 1.05)])
def test_geometric_sizes_first_exact_sum_exact_ratio_capped(T, first, ratio):
    sizes, q = geometric_sizes(T, first, ratio)
    assert sizes[0] == first
    assert_rel(float(np.sum(sizes)), T)
    assert q <= ratio * (1 + REL)
    np.testing.assert_allclose(sizes[1:] / sizes[:-1], q, rtol=1e-12)
    assert sizes.min() >= 0.5 * first
    # n is minimal: one element fewer cannot reach T with growth <= ratio
    n = len(sizes) - 1
    assert first * sum(ratio**i for i in range(n)) < T * (1 - 1e-14)


def test_graded_nodes_levels_are_nodes_and_growth_capped():
    zs, _ = graded_nodes(1.0, 0.02, 1.15, [0.1, 0.101, 0.6])
    for level in (0.1, 0.101, 0.6, 1.0):
        assert np.min(np.abs(zs - level)) == 0.0
    assert zs[1] == 0.02 and zs[0] == 0.0
    sizes = np.diff(zs)
    assert np.all(sizes > 0)
    # growth is capped everywhere except where a thin partition forces a smaller element
    ok = sizes[1:] / sizes[:-1] <= 1.15 * (1 + 1e-12)
    assert np.sum(~ok) <= 2


def test_graded_nodes_lowest_layer_too_thin_is_an_error():
    with pytest.raises(ValueError, match="lowest layer"):
        graded_nodes(1.0, 0.1, 1.2, [0.11])


# ----------------------------------------------------------------------------- block
@pytest.fixture(scope="module")
def block():
    return rubber_block(2.0, 1.0, nx_contact=16, grading=1.2, first_layer=0.01)


def test_block_is_quadrilateral_with_exact_area_and_face_lengths(block):
    assert block.mesh.topology.cell_type == dolfinx.mesh.CellType.quadrilateral
    assert_rel(area(block), 2.0)
    assert_rel(face_length(block, CONTACT), 2.0)
    assert_rel(face_length(block, OPPOSITE), 2.0)
    assert_rel(face_length(block, LEFT), 1.0)
    assert_rel(face_length(block, RIGHT), 1.0)
    assert block.info["num_contact_facets"] == 16
    assert set(np.unique(block.cell_tags.values)) == {1}


def test_block_contact_face_is_uniform_and_at_z0(block):
    bottom = face_nodes(block, 1, 0.0)
    np.testing.assert_allclose(bottom[:, 0], np.linspace(0.0, 2.0, 17), rtol=0, atol=1e-12 * 2)
    p = facet_points(block, CONTACT)
    assert np.all(p[:, :, 1] == 0.0)
    np.testing.assert_allclose(np.linalg.norm(p[:, 1] - p[:, 0], axis=1), 2.0 / 16, rtol=REL)


@pytest.mark.parametrize("kwargs", [
    dict(nx_contact=16, grading=1.2, first_layer=0.01),
    dict(h_contact=0.07, grading=1.1),
    dict(h_contact=0.1, grading=1.0, first_layer=0.3),
    dict(nx_contact=10, grading=1.3, first_layer=0.004, partitions=[0.05, 0.3]),
])
def test_block_first_element_height_and_growth(kwargs):
    body = rubber_block(2.0, 1.0, **kwargs)
    left = face_nodes(body, 0, 0.0)[:, 1]
    expected_first = kwargs.get("first_layer", 2.0 / math.ceil(2.0 / kwargs.get(
        "h_contact", 2.0 / kwargs.get("nx_contact", 1))))
    assert left[0] == 0.0 and left[-1] == 1.0
    assert_rel(left[1] - left[0], expected_first)
    assert_rel(body.info["first_layer"], expected_first)
    sizes = np.diff(left)
    growth = sizes[1:] / sizes[:-1]
    assert growth.max() <= kwargs["grading"] * (1 + 1e-12)
    for level in kwargs.get("partitions", []):
        assert np.min(np.abs(left - level)) <= 1e-15


def test_block_left_right_z_nodes_match_for_periodicity():
    body = rubber_block(1.0, 1.0, h_contact=0.03, grading=1.1, partitions=[0.2, 0.45])
    left = face_nodes(body, 0, 0.0)[:, 1]
    right = face_nodes(body, 0, 1.0)[:, 1]
    assert len(left) == len(right)
    np.testing.assert_allclose(left, right, rtol=0, atol=1e-12)
    assert body.info["periodic"] is True


def test_block_partitions_become_cell_tag_layers():
    levels = [0.1, 0.35]
    body = rubber_block(2.0, 1.0, nx_contact=20, grading=1.1, partitions=levels)
    assert set(np.unique(body.cell_tags.values)) == {1, 2, 3}
    for tag, (lo, hi) in enumerate(zip([0.0, *levels], [*levels, 1.0]), start=1):
        assert_rel(area(body, tag), 2.0 * (hi - lo))
    assert body.info["layers"] == [[0.0, 0.1], [0.1, 0.35], [0.35, 1.0]]


def test_block_and_rounded_block_have_positive_jacobians_at_quadrature_points():
    for body in (rubber_block(1.0, 1.0, nx_contact=12, grading=1.3, first_layer=0.001),
                 rubber_block(1.0, 1.0, h_contact=0.05, leading_edge_radius=0.3),
                 rubber_block(1.0, 1.0, h_contact=0.05, leading_edge_radius=0.3,
                              leading_edge="left")):
        assert min_jacobian_at_quadrature_points(body) > 0.0
        assert body.info["min_scaled_jacobian"] > 0.5


def test_rounded_leading_edge_area_and_contact_face():
    l, h, r = 1.0, 1.0, 0.3
    deficits = []
    for hc in (0.05, 0.025):
        body = rubber_block(l, h, h_contact=hc, leading_edge_radius=r, partitions=[0.5])
        assert_rel(area(body, 2), l * 0.5)  # layers above the arc stay exact
        exact = l * h - (1 - math.pi / 4) * r * r
        chords = arc_chords(body, (l - r, r), r)
        assert chords.max() <= hc * (1 + REL)
        deficit = exact - area(body)
        assert deficit > 0.0
        assert_rel(deficit, circular_segments(chords, r), 1e-10)
        assert deficit <= math.pi / 24 * arc_lengths(chords, r).max() ** 2
        deficits.append(deficit)
        # the arc belongs to the contact face; right face starts at z = r
        assert_rel(face_length(body, CONTACT), (l - r) + float(np.sum(chords)))
        assert_rel(face_length(body, RIGHT), h - r)
        assert_rel(face_length(body, LEFT), h)
        assert_rel(face_length(body, OPPOSITE), l)
        # flat part of the contact face keeps its uniform spacing
        flat = face_nodes(body, 1, 0.0)[:, 0]
        assert_rel(flat[-1], l - r)
        np.testing.assert_allclose(np.diff(flat), body.info["h_contact"], rtol=1e-10)
    assert deficits[1] < 0.3 * deficits[0]


def test_rounded_leading_edge_left_mirrors_the_block():
    l, h, r = 2.0, 1.0, 0.4
    right = rubber_block(l, h, nx_contact=16, leading_edge_radius=r)
    left = rubber_block(l, h, nx_contact=16, leading_edge_radius=r, leading_edge="left")
    assert_rel(face_length(left, LEFT), h - r)
    assert_rel(face_length(left, RIGHT), h)
    assert len(arc_chords(left, (r, r), r)) == right.info["arc_elements"]
    assert_rel(area(left), area(right))


def test_rounded_macro_block_thermal_grading():
    """Thesis 8.4.1 set-up: 20 mm x 8 mm block, first node at 0.01 mm, run-in radius 2 mm."""
    body = rubber_block(20.0, 8.0, h_contact=0.2, grading=1.15, first_layer=0.01,
                        leading_edge_radius=2.0)
    left = face_nodes(body, 0, 0.0)[:, 1]
    assert_rel(left[1], 0.01)
    assert body.info["contact_size_max"] <= 0.2 * (1 + REL)
    assert body.info["min_scaled_jacobian"] > 0.5
    assert min_jacobian_at_quadrature_points(body) > 0.0


def test_block_is_deterministic():
    for kwargs in (dict(h_contact=0.04, grading=1.1, partitions=[0.3]),
                   dict(h_contact=0.05, leading_edge_radius=0.25)):
        a, b = rubber_block(1.0, 1.0, **kwargs), rubber_block(1.0, 1.0, **kwargs)
        assert np.array_equal(a.mesh.geometry.x, b.mesh.geometry.x)
        assert np.array_equal(a.mesh.geometry.dofmap.array, b.mesh.geometry.dofmap.array)
        assert np.array_equal(a.facet_tags.values, b.facet_tags.values)


# ----------------------------------------------------------------------------- road
def test_road_body_tags_grading_and_periodic_nodes():
    body = road_body(10.0, 4.0, h_surface=0.5, grading=1.2)
    assert body.mesh.topology.cell_type == dolfinx.mesh.CellType.quadrilateral
    assert_rel(area(body), 40.0)
    assert_rel(face_length(body, CONTACT), 10.0)
    assert np.all(facet_points(body, CONTACT)[:, :, 1] == 0.0)
    assert_rel(face_length(body, OPPOSITE), 10.0)
    assert_rel(face_length(body, LEFT), 4.0)
    assert_rel(face_length(body, RIGHT), 4.0)
    left = face_nodes(body, 0, 0.0)[:, 1][::-1]
    right = face_nodes(body, 0, 10.0)[:, 1][::-1]
    assert left[0] == 0.0 and left[-1] == -4.0
    assert_rel(left[1], -0.01)  # thesis 8.4.1: first node at 0.01 mm
    np.testing.assert_allclose(left, right, rtol=0, atol=1e-12)
    sizes = -np.diff(left)
    assert np.max(sizes[1:] / sizes[:-1]) <= 1.2 * (1 + 1e-12)
    assert min_jacobian_at_quadrature_points(body) > 0.0


# ----------------------------------------------------------------------------- patch
def test_patch_pair_is_non_matching_with_documented_tags():
    upper, lower = patch_test_pair(2.0, 0.6, 0.4, n_upper=7, n_lower=5, gap=0.01)
    xu = face_nodes(upper, 1, 0.01)[:, 0]
    xl = face_nodes(lower, 1, 0.0)[:, 0]
    assert len(xu) == 8 and len(xl) == 6
    interior = np.abs(xu[1:-1, None] - xl[None, 1:-1])
    assert interior.min() > 1e-3  # no interior node of one face on the other face's nodes
    for body, z_contact, z_far, height in ((upper, 0.01, 0.61, 0.6), (lower, 0.0, -0.4, 0.4)):
        assert_rel(area(body), 2.0 * height)
        assert np.allclose(facet_points(body, CONTACT)[:, :, 1], z_contact, rtol=0, atol=1e-15)
        assert np.allclose(facet_points(body, OPPOSITE)[:, :, 1], z_far, rtol=0, atol=1e-15)
        assert_rel(face_length(body, CONTACT), 2.0)
        assert_rel(face_length(body, LEFT), height)
        assert_rel(face_length(body, RIGHT), height)
        assert min_jacobian_at_quadrature_points(body) > 0.0


# ----------------------------------------------------------------------------- cylinder
@pytest.mark.parametrize("quarter", [False, True])
def test_hertz_cylinder_area_tags_and_contact_zone(quarter):
    R, hc, w = 10.0, 0.05, 1.0
    frac = 0.25 if quarter else 0.5
    deficits = []
    for hmax in (1.0, 0.5):
        body = hertz_cylinder(R, h_contact=hc, contact_width=w, max_size=hmax, quarter=quarter)
        assert body.mesh.topology.cell_type == dolfinx.mesh.CellType.quadrilateral
        assert min_jacobian_at_quadrature_points(body) > 0.0
        chords = arc_chords(body, (0.0, R), R)
        assert len(chords) == body.info["num_contact_facets"]
        deficit = frac * math.pi * R * R - area(body)
        assert deficit > 0.0
        assert_rel(deficit, circular_segments(chords, R), 1e-10)
        assert deficit <= frac * math.pi / 6 * arc_lengths(chords, R).max() ** 2
        deficits.append(deficit)
        assert_rel(face_length(body, OPPOSITE), R if quarter else 2 * R)
        if quarter:
            assert_rel(face_length(body, LEFT), R)
        # refined zone: uniform chords <= h_contact; (0, 0) is a node
        p = facet_points(body, CONTACT)
        zone = np.all(np.abs(p[:, :, 0]) <= w * (1 + 1e-12), axis=1)
        lengths = np.linalg.norm(p[zone, 1] - p[zone, 0], axis=1)
        assert len(lengths) == body.info["contact_zone_elements"]
        # gmsh places transfinite nodes to ~1e-8 relative (measured), hence 1e-7
        np.testing.assert_allclose(lengths, body.info["contact_zone_size"], rtol=1e-7)
        assert lengths.max() <= hc
        assert np.min(np.linalg.norm(body.mesh.geometry.x[:, :2], axis=1)) <= 1e-14
        assert body.info["contact_size_max"] <= hmax * (1 + 0.25)
    assert deficits[1] < 0.5 * deficits[0]


def test_hertz_cylinder_is_deterministic_and_leaves_gmsh_finalised():
    import gmsh

    a = hertz_cylinder(1.0, h_contact=0.01, contact_width=0.1)
    b = hertz_cylinder(1.0, h_contact=0.01, contact_width=0.1)
    assert np.array_equal(a.mesh.geometry.x, b.mesh.geometry.x)
    assert np.array_equal(a.mesh.geometry.dofmap.array, b.mesh.geometry.dofmap.array)
    with pytest.raises(Exception):
        gmsh.model.getCurrent()  # raises only when gmsh is not initialised


def test_hertz_cylinder_finalises_gmsh_on_error(monkeypatch):
    import gmsh

    import rubberfriction.meshes.cylinder as cyl

    def boom(_gmsh):
        raise RuntimeError("boom")

    monkeypatch.setattr(cyl, "quad_mesh_arrays", boom)
    with pytest.raises(RuntimeError, match="boom"):
        cyl.hertz_cylinder(1.0, h_contact=0.02, contact_width=0.1)
    with pytest.raises(Exception):
        gmsh.model.getCurrent()


# ----------------------------------------------------------------------------- sizes
def test_contact_element_size_rule():
    # thesis 6.5.1: 10 master segments per shortest wavelength, slave twice finer
    assert_rel(contact_element_size(0.2), 0.01)
    assert_rel(contact_element_size(0.2, elements_per_wavelength=5), 0.02)
    assert_rel(contact_element_size(0.2, master_segment_length=0.019), 0.0095)
    assert_rel(contact_element_size(0.2, slave_to_master_ratio=4.0), 0.005)


def test_polyline_element_size_from_slope_sign_changes():
    """Two slope sign changes per wavelength: lambda = 2 L / changes, over elements_per_wavelength;
    the periodic closure counts the wrap-around change; the estimate is bounded below by 4 dx."""
    lam, n = 0.8, 5  # five wavelengths, sampled off the extrema
    x = np.linspace(0.0, n * lam, 401)[:-1] + 0.3e-3
    h = np.cos(2 * np.pi * x / lam)
    assert_rel(polyline_element_size(x, h, n * lam, 10.0), lam / 10.0)  # 2 n changes
    x1 = np.linspace(0.0, lam, 81)[:-1] + 0.3e-3  # one period: 1 inside, 1 across the closure
    assert_rel(polyline_element_size(x1, np.cos(2 * np.pi * x1 / lam), lam, 4.0), lam / 4.0)
    zigzag = np.arange(20) % 2 * 0.01  # a sign change at every vertex: lambda -> 4 dx = 0.4
    assert_rel(polyline_element_size(np.arange(20) * 0.1, zigzag, 2.0, 10.0), 0.04)


# ----------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("call,match", [
    (lambda: rubber_block(-1.0, 1.0, nx_contact=4), "length"),
    (lambda: rubber_block(1.0, 0.0, nx_contact=4), "height"),
    (lambda: rubber_block(1.0, 1.0), "exactly one of nx_contact and h_contact"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, h_contact=0.1), "exactly one"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=0), "nx_contact"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=2.5), "nx_contact"),
    (lambda: rubber_block(1.0, 1.0, h_contact=-0.1), "h_contact"),
    (lambda: rubber_block(1.0, 1.0, h_contact=float("nan")), "h_contact"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, grading=0.9), "grading"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, first_layer=2.0), "first_layer"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, partitions=[0.5, 0.2]), "partitions"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, partitions=[1.5]), "partitions"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, leading_edge_radius=1.0), "smaller than"),
    (lambda: rubber_block(3.0, 1.0, nx_contact=4, leading_edge_radius=2.0), "smaller than"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, leading_edge_radius=-0.1),
     "leading_edge_radius"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=10, leading_edge_radius=0.01), "too small"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=10, leading_edge_radius=0.3, partitions=[0.2]),
     "leading_edge_radius"),
    (lambda: rubber_block(1.0, 1.0, nx_contact=4, leading_edge="front"), "leading_edge"),
    (lambda: road_body(1.0, 0.0, h_surface=0.1), "depth"),
    (lambda: road_body(1.0, 1.0, h_surface=0.1, first_layer=2.0), "first_layer"),
    (lambda: road_body(1.0, 1.0), "exactly one of nx_surface and h_surface"),
    (lambda: hertz_cylinder(-1.0, h_contact=0.01, contact_width=0.1), "radius"),
    (lambda: hertz_cylinder(1.0, h_contact=0.01, contact_width=0.6), "contact_width"),
    (lambda: hertz_cylinder(1.0, h_contact=0.2, contact_width=0.1), "h_contact"),
    (lambda: hertz_cylinder(1.0, h_contact=0.01, contact_width=0.1, max_size=0.005),
     "max_size"),
    (lambda: patch_test_pair(n_upper=0), "n_upper"),
    (lambda: patch_test_pair(height_lower=0.5, gap=-0.5), "gap"),
    (lambda: contact_element_size(0.0), "shortest_wavelength"),
    (lambda: contact_element_size(0.2, slave_to_master_ratio=0.0), "slave_to_master_ratio"),
])
def test_bad_input_is_rejected_with_a_message_naming_the_field(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ----------------------------------------------------------------------------- MPI
_MPI_SCRIPT = """
import sys
sys.path.insert(0, {root!r})
import numpy as np
import ufl
import dolfinx.fem
from mpi4py import MPI
from rubberfriction.meshes import rubber_block, hertz_cylinder
comm = MPI.COMM_WORLD
for body in (rubber_block(1.0, 1.0, h_contact=0.05, partitions=[0.3], comm=comm),
             rubber_block(1.0, 1.0, h_contact=0.05, leading_edge_radius=0.3, comm=comm),
             hertz_cylinder(1.0, h_contact=0.01, contact_width=0.1, comm=comm)):
    one = dolfinx.fem.Constant(body.mesh, 1.0)
    ds = ufl.Measure("ds", domain=body.mesh, subdomain_data=body.facet_tags)
    dx = ufl.Measure("dx", domain=body.mesh, subdomain_data=body.cell_tags)
    vals = [comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(f)), op=MPI.SUM)
            for f in (one * dx, one * dx(1), one * ds(1), one * ds(2))]
    if comm.rank == 0:
        print(body.info["num_cells"], body.info["num_contact_facets"], *vals)
"""


@pytest.mark.mpi
def test_meshes_on_two_ranks_match_serial(tmp_path):
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        missing("mpirun not found (openmpi-bin, installed by scripts/setup.sh)")
    root = str(Path(__file__).resolve().parents[1])
    script = tmp_path / "mesh_mpi.py"
    script.write_text(_MPI_SCRIPT.format(root=root))
    outs = []
    for n in (1, 2):
        run = subprocess.run([mpirun, "-n", str(n), sys.executable, str(script)],
                             capture_output=True, text=True, timeout=120,
                             env={**__import__("os").environ, "OMPI_ALLOW_RUN_AS_ROOT": "1",
                                  "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMP_NUM_THREADS": "1"})
        assert run.returncode == 0, run.stderr
        outs.append(np.array([[float(v) for v in line.split()]
                              for line in run.stdout.strip().splitlines()]))
    np.testing.assert_allclose(outs[1], outs[0], rtol=1e-12)
