"""Volumetric locking: Cook's membrane with nu = 0.4999 (plane strain, small load).

The mixed Q1-P0 element and its stabilised form Q1P0s converge under refinement (to the same
deflection within 0.5 % on 32 x 32); the displacement-only Q1 element locks
(its tip deflection is a fraction of the converged one on the same meshes).  No closed form
exists; the test compares the two elements with each other and with refinement, and in the
compressible case (nu = 0.3) with a 4x finer mesh of the other element.
"""

import functools

import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from fe_helpers import n_full, solve
from rubberfriction.driver.fe.constraints import ConstraintSpec
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.forms.compound import Compound, MooneyRivlin

E, NU, LOAD = 250.0, 0.4999, 1.0  # MPa, -, N per unit depth on the free edge (small: linear regime)


def cook_membrane(n: int):
    m = dmesh.create_unit_square(MPI.COMM_SELF, n, n, dmesh.CellType.quadrilateral)
    xi, eta = m.geometry.x[:, 0].copy(), m.geometry.x[:, 1].copy()
    m.geometry.x[:, 0] = 48.0 * xi
    m.geometry.x[:, 1] = 44.0 * xi + 44.0 * eta - 28.0 * xi * eta
    right = dmesh.locate_entities_boundary(m, 1, lambda x: np.isclose(x[0], 48.0))
    tags = dmesh.meshtags(m, 1, right.astype(np.int32), np.full(right.size, 4, np.int32))
    return m, tags


def tip_deflection(n: int, element: str) -> float:
    m, ft = cook_membrane(n)
    mu = E / (2.0 * (1.0 + NU))
    K = E / (3.0 * (1.0 - 2.0 * NU))
    mat = Compound(name="cook", hyperelastic=MooneyRivlin.neo_hooke(mu, K), prony=None, wlf=None,
                   thermal=None)
    sp = SolidProblem(m, ft, mat, SolidSettings(element=element))
    sp.add_traction(4, fem.Constant(m, np.array([0.0, LOAD / 16.0])))
    spec = ConstraintSpec(n_full(sp))
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 0], 0.0)), 0.0)
    solve(sp, spec, rtol=1e-10)
    X, u = sp.node_X, sp.nodal_displacement()
    tip = np.argmin(np.hypot(X[:, 0] - 48.0, X[:, 1] - 60.0))
    return float(u[tip, 1])


@functools.lru_cache(maxsize=None)
def incompressible_deflection(n: int, element: str) -> float:
    return tip_deflection(n, element)


@pytest.mark.parametrize("element", ["Q1P0", "Q1P0s"])
def test_mixed_converges_and_q1_locks(element):
    mixed = {n: incompressible_deflection(n, element) for n in (8, 16, 32)}
    q1 = {n: incompressible_deflection(n, "Q1") for n in (8, 16)}
    ref = mixed[32]
    assert ref > 0.0
    # mixed: successive differences shrink, 16 -> 32 changes by < 2 %
    assert abs(mixed[16] - ref) < abs(mixed[8] - ref)
    assert abs(mixed[16] - ref) < 0.02 * ref
    # Q1 locks: far below the converged value on the same meshes
    assert q1[8] < 0.5 * ref and q1[16] < 0.7 * ref, (q1, mixed)


@functools.lru_cache(maxsize=None)
def compressible_deflection(n: int, element: str) -> float:
    """Tip deflection with nu = 0.3 (no locking)."""
    global NU
    saved, NU = NU, 0.3
    try:
        return tip_deflection(n, element)
    finally:
        NU = saved


#: the reference of the compressible case: 4x finer mesh (64 x 64) of the *other* element.  At
#: nu = 0.3 both elements converge (from below) to the same deflection; on 64 x 64 they agree
#: within 0.25 % (Q1P0 0.091702, Q1 0.091492 mm; 128 x 128: 0.091896, 0.091807).
REFERENCE = {"Q1P0": "Q1", "Q1": "Q1P0"}


def test_compressible_references_agree():
    q1p0, q1 = compressible_deflection(64, "Q1P0"), compressible_deflection(64, "Q1")
    assert q1p0 > 0.0 and abs(q1p0 - q1) < 0.005 * q1p0, (q1p0, q1)


@pytest.mark.parametrize("element,tol", [("Q1P0", 0.03), ("Q1", 0.05)])
def test_compressible_elements_agree(element, tol):
    """With nu = 0.3 (no locking) the 16 x 16 mesh is within tol of the 64 x 64 reference of the
    other element (achieved: Q1P0 1.6 %, Q1 3.5 %; Q1 is stiffer in bending) and both elements
    agree on the same mesh within 5 %."""
    d = compressible_deflection(16, element)
    d_ref = compressible_deflection(64, REFERENCE[element])
    assert 0.0 < d < d_ref  # both converge from below
    assert abs(d - d_ref) < tol * d_ref, (d, d_ref)
    other = compressible_deflection(16, REFERENCE[element])
    assert abs(d - other) < 0.05 * other, (d, other)


def test_stabilised_and_plain_mixed_agree():
    """The jump stabilisation is consistent: on 32 x 32 Q1P0s and Q1P0 give the same tip deflection
    within 0.5 %."""
    a, b = incompressible_deflection(32, "Q1P0s"), incompressible_deflection(32, "Q1P0")
    assert abs(a - b) < 0.005 * b, (a, b)
