"""Volumetric locking: Cook's membrane with nu = 0.4999 (plane strain, small load).

The mixed Q1-P0 element converges under refinement; the displacement-only Q1 element locks
(its tip deflection is a fraction of the converged one on the same meshes).  No closed form
exists; the test compares the two elements with each other and with refinement.
"""

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


def test_mixed_converges_and_q1_locks():
    mixed = {n: tip_deflection(n, "Q1P0") for n in (8, 16, 32)}
    q1 = {n: tip_deflection(n, "Q1") for n in (8, 16)}
    ref = mixed[32]
    assert ref > 0.0
    # mixed: successive differences shrink, 16 -> 32 changes by < 2 %
    assert abs(mixed[16] - ref) < abs(mixed[8] - ref)
    assert abs(mixed[16] - ref) < 0.02 * ref
    # Q1 locks: far below the converged value on the same meshes
    assert q1[8] < 0.5 * ref and q1[16] < 0.7 * ref, (q1, mixed)


@pytest.mark.parametrize("element", ["Q1P0", "Q1"])
def test_compressible_elements_agree(element):
    """Sanity: with nu = 0.3 both elements give nearly the same deflection (no locking)."""
    global NU
    saved, NU = NU, 0.3
    try:
        d = tip_deflection(16, element)
        d_ref = tip_deflection(16, "Q1P0")
    finally:
        NU = saved
    assert abs(d - d_ref) < 0.05 * d_ref
