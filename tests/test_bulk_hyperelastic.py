"""Homogeneous states of the Mooney-Rivlin bulk against closed forms (thesis eq. 3.58, A.8).

Tolerance 1e-8 relative: the states are homogeneous, so bilinear elements represent them exactly
and only the Newton tolerance (1e-13) and round-off remain.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from fe_helpers import cauchy_at_points, mooney_rivlin_cauchy, n_full, solve, unit_square
from rubberfriction.driver.fe.constraints import ConstraintSpec
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.forms.compound import Compound, MooneyRivlin

C10, C01, D1 = 0.174, 0.300, 0.0208  # compound m1, table C.2


def rubber(form: str = "split") -> Compound:
    return Compound(name="m1-elastic", hyperelastic=MooneyRivlin(C10, C01, D1, form=form),
                    prony=None, wlf=None, thermal=None, description="test",
                    source="thesis table C.2")


@pytest.mark.parametrize("element", ["Q1P0", "Q1P0s", "Q1"])
def test_uniaxial_plane_strain_tension(element):
    """Stretch 1.3 in x, free in z, plane strain: sigma_xx and the lateral stretch match."""
    lam = 1.3
    m, ft = unit_square(2)
    sp = SolidProblem(m, ft, rubber(), SolidSettings(element=element))
    spec = ConstraintSpec(n_full(sp))
    X = sp.node_X
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 0], 0.0), 0), 0.0)
    right = sp.dofs_where(lambda x: np.isclose(x[:, 0], 1.0), 0)
    spec.fix(right, lam - 1.0)
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 1], 0.0), 1), 0.0)
    for s in np.linspace(0.2, 1.0, 5):  # load steps: a 30 % stretch in one Newton solve diverges
        spec.fix(right, s * (lam - 1.0))
        solve(sp, spec)
    u = sp.nodal_displacement()
    top = np.isclose(X[:, 1], 1.0)
    lam2_fe = 1.0 + u[top, 1].mean()

    def szz(l2):
        return mooney_rivlin_cauchy(np.diag([lam, l2, 1.0]), C10, C01, D1)[1, 1]

    lam2 = brentq(szz, 0.5, 1.2, xtol=1e-15)
    sig = mooney_rivlin_cauchy(np.diag([lam, lam2, 1.0]), C10, C01, D1)
    sig_fe = cauchy_at_points(sp)
    assert abs(lam2_fe - lam2) < 1e-8 * lam2
    for i, j in [(0, 0), (2, 2)]:
        assert np.allclose(sig_fe[:, i, j], sig[i, j], rtol=1e-8, atol=0), (i, j, sig_fe[0], sig)
    assert np.abs(sig_fe[:, 1, 1]).max() < 1e-8 * abs(sig[0, 0])


@pytest.mark.parametrize("element", ["Q1P0", "Q1P0s", "Q1"])
def test_simple_shear_periodic(element):
    """Top/bottom prescribed, left/right periodic (u_r = u_l): homogeneous simple shear."""
    gamma = 0.4
    m, ft = unit_square(3)
    sp = SolidProblem(m, ft, rubber(), SolidSettings(element=element))
    spec = ConstraintSpec(n_full(sp))
    X, d = sp.node_X, sp.displacement_dofs()
    for edge_z, ux in [(0.0, 0.0), (1.0, gamma)]:
        nodes = np.isclose(X[:, 1], edge_z)
        spec.fix(d[nodes, 0], ux)
        spec.fix(d[nodes, 1], 0.0)
    left = np.nonzero(np.isclose(X[:, 0], 0.0))[0]
    right = np.nonzero(np.isclose(X[:, 0], 1.0))[0]
    left, right = left[np.argsort(X[left, 1])], right[np.argsort(X[right, 1])]
    spec.equal(d[left, 0], d[right, 0])
    spec.equal(d[left, 1], d[right, 1])
    pb, res = solve(sp, spec)
    assert res.iterations >= 1  # interior nodes are unknowns: Newton did the work
    F = np.array([[1.0, gamma, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    sig = mooney_rivlin_cauchy(F, C10, C01, D1)
    sig_fe = cauchy_at_points(sp)
    scale = abs(sig[0, 1])
    assert np.abs(sig_fe - sig[None]).max() < 1e-8 * scale
    # shear stress of Mooney-Rivlin in simple shear is linear: sigma_xy = 2 (C10 + C01) gamma
    assert abs(sig[0, 1] - 2.0 * (C10 + C01) * gamma) < 1e-12


@pytest.mark.parametrize("element", ["Q1P0", "Q1P0s", "Q1"])
def test_volumetric_compression_bulk_modulus(element):
    """Equibiaxial in-plane compression: mean stress / (J - 1) = K = 2/D1 exactly (eq. A.8)."""
    lam = 0.995
    m, ft = unit_square(2)
    sp = SolidProblem(m, ft, rubber(), SolidSettings(element=element))
    spec = ConstraintSpec(n_full(sp))
    X, d = sp.node_X, sp.displacement_dofs()
    spec.fix(d[:, 0], 0.0)
    spec.fix(d[:, 1], 0.0)
    for i in range(sp.n_nodes):
        spec.fixed[int(d[i, 0])] = (lam - 1.0) * X[i, 0]
        spec.fixed[int(d[i, 1])] = (lam - 1.0) * X[i, 1]
    solve(sp, spec)
    sig = cauchy_at_points(sp)
    J = lam**2
    K_fe = np.trace(sig, axis1=1, axis2=2) / 3.0 / (J - 1.0)
    assert np.allclose(K_fe, 2.0 / D1, rtol=1e-8)


def test_feap_form_small_strain_moduli():
    """The FEAP-style form (3.53) has the same small-strain shear and bulk moduli as (3.58)."""
    eps = 1e-6
    m, ft = unit_square(1)
    sp = SolidProblem(m, ft, rubber("feap"), SolidSettings(element="Q1"))
    spec = ConstraintSpec(n_full(sp))
    X, d = sp.node_X, sp.displacement_dofs()
    for i in range(sp.n_nodes):
        spec.fix(d[i, 0], eps * X[i, 1])
        spec.fix(d[i, 1], eps * X[i, 1])  # shear + uniaxial compaction
    solve(sp, spec)
    sig = cauchy_at_points(sp)[0]
    mu, K = 2.0 * (C10 + C01), 2.0 / D1
    assert abs(sig[0, 1] / eps - mu) < 1e-4 * mu
    # uniaxial strain eps_zz = eps: sigma_zz = (K + 4/3 mu) eps
    assert abs(sig[1, 1] / eps - (K + 4.0 / 3.0 * mu)) < 1e-4 * K
