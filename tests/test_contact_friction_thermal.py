"""Friction law, return mapping and heat bookkeeping on a flat interface (exact identities).

A flat slave chain uniformly penetrating a flat master (pressure p = c_N g) is moved tangentially
by prescribed increments:
* stick while c_T |slip| <= mu p, then slip with F_x/F_z = -mu exactly (constant mu and a
  mu(p, v) spline evaluated at the known p and v = slip increment / dt);
* frictional power mu p v L goes kappa to the slave and 1 - kappa to the master, and the thermal
  residual rows carry exactly that heat (rigid and deformable master);
* conduction across a uniform thermal gap: nodal heat h_c(p) dT Int N_A on both non-matching
  sides; dissipation of a step = mu p L x slip.
The spline evaluation itself is checked against scipy.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import interpolate

from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.fe.contact import (
    Contact, DeformableMaster, PenaltySettings, RigidMaster, SlaveSurface, ThermalSettings)

XS = np.array([0.0, 0.11, 0.2, 0.37, 0.5, 0.62, 0.8, 1.0])
CN, CT, G = 200.0, 120.0, 0.005
P = CN * G


def build_interface(friction, *, thermal=None, deformable=False, temps=False):
    n = XS.size
    nd = 3 if temps else 2
    dofs = np.column_stack([nd * np.arange(n), nd * np.arange(n) + 1])
    slave = SlaveSurface(np.column_stack([XS, np.zeros(n)]), dofs,
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]),
                         nd * np.arange(n) + 2 if temps else None)
    ndof = nd * n
    if deformable:
        xm = np.array([1.0, 0.77, 0.45, 0.3, 0.0])
        m = xm.size
        mdofs = ndof + np.column_stack([nd * np.arange(m), nd * np.arange(m) + 1])
        master = DeformableMaster(np.column_stack([xm, np.zeros(m)]), mdofs,
                                  np.column_stack([np.arange(m - 1), np.arange(1, m)]),
                                  ndof + nd * np.arange(m) + 2 if temps else None)
        ndof += nd * m
    else:
        master = RigidMaster(np.array([[-1.0, 0.0], [0.33, 0.0], [0.71, 0.0], [2.0, 0.0]]))
    c = Contact(slave, master, friction=friction, penalty=PenaltySettings(c_N=CN, c_T=CT),
                thermal=thermal)
    u = np.zeros(ndof)
    u[1: nd * n: nd] = -G
    return c, u, nd


def residual(c, u, **kw):
    rr, rv, *_ = c.local_system(u, **kw)
    R = np.zeros(u.size)
    np.add.at(R, rr, rv)
    return R


@pytest.mark.parametrize("method", ["mortar", "nts"])
def test_stick_then_slip_coulomb_exact(method):
    mu = 0.35
    c, u, nd = build_interface(mu)
    c = Contact(c.slave, c.master, method=method, friction=mu,
                penalty=PenaltySettings(c_N=CN, c_T=CT))
    stick_limit = mu * P / CT
    u[0::nd] = 0.5 * stick_limit  # stick
    s = c.evaluate(u, dt=0.1)
    assert np.all(s["status"] == 1)
    np.testing.assert_allclose(s["tangential_traction"], CT * 0.5 * stick_limit, rtol=1e-12)
    np.testing.assert_allclose(s["Fx"], -CT * 0.5 * stick_limit * 1.0, rtol=1e-12)
    u[0::nd] = 3.0 * stick_limit  # slip
    s = c.evaluate(u, dt=0.1)
    assert np.all(s["status"] == 2)
    assert abs(s["Fx"] / s["Fz"] + mu) <= 1e-12 * mu
    np.testing.assert_allclose(s["slip_increment"], 2.0 * stick_limit, rtol=1e-12)
    assert abs(s["dissipation"] - mu * P * 1.0 * 2.0 * stick_limit) <= 1e-12 * s["dissipation"]
    # committed history: moving back by less than 2 stick limits sticks again
    c.commit()
    u[0::nd] = 3.0 * stick_limit - 1.5 * stick_limit
    s = c.evaluate(u, dt=0.1)
    assert np.all(s["status"] == 1)
    np.testing.assert_allclose(s["tangential_traction"], mu * P - CT * 1.5 * stick_limit,
                               rtol=1e-12)


def pv_spline():
    p = np.linspace(0.1, 3.0, 7)
    v = np.logspace(-2, 3, 9)
    mu = 0.8 - 0.1 * np.log(1.0 + p)[:, None] + 0.15 * np.tanh(np.log10(v) - 0.5)[None, :]
    return fl.fit_mu_pv(p, v, mu), p, v, mu


def test_spline_matches_scipy_values_and_derivatives():
    law, p, v, mu = pv_spline()
    ref = interpolate.RectBivariateSpline(p, np.log10(v), mu)
    pp = np.array([0.15, 0.8, 1.7, 2.9])
    vv = np.array([0.013, 0.9, 44.0, 700.0])
    e = law.evaluate(pp, vv)
    np.testing.assert_allclose(e[:, 0], ref.ev(pp, np.log10(vv)), rtol=1e-13)
    np.testing.assert_allclose(e[:, 1], ref.ev(pp, np.log10(vv), dx=1), rtol=1e-12)
    np.testing.assert_allclose(e[:, 2], ref.ev(pp, np.log10(vv), dy=1) / (vv * np.log(10.0)),
                               rtol=1e-12)
    np.testing.assert_allclose(law(p[3], v[4]), mu[3, 4], rtol=1e-13)  # interpolates the data
    # outside the data: clamped, zero derivative
    out = law.evaluate(10.0, 1e6)
    np.testing.assert_allclose(out[0], law(3.0, 1e3), rtol=1e-13)
    assert out[1] == 0.0 and out[2] == 0.0


def test_sliding_with_mu_pv_law_at_known_p_v():
    law, *_ = pv_spline()
    c, u, nd = build_interface(law)
    dt, du = 0.02, 0.03
    u[0::nd] = du
    s = c.evaluate(u, dt=dt)
    assert np.all(s["status"] == 2)
    v = du / dt
    np.testing.assert_allclose(s["slip_velocity"], v, rtol=1e-12)
    assert abs(-s["Fx"] / s["Fz"] - law(P, v)) <= 1e-12 * law(P, v)


@pytest.mark.parametrize("deformable", [False, True])
@pytest.mark.parametrize("kappa", [0.0, 0.3, 1.0])
def test_frictional_heat_split_by_kappa(deformable, kappa):
    mu, dt, du = 0.4, 0.05, 0.02
    th = ThermalSettings(h0=0.0, kappa=kappa)  # no conduction: only frictional heating
    c, u, nd = build_interface(mu, thermal=th, deformable=deformable, temps=True)
    u[2::nd] = 300.0
    u[0: nd * XS.size: nd] = du
    R = residual(c, u, dt=dt)
    s = c.state()
    assert np.all(s["status"] == 2)
    slip = du - mu * P / CT  # slip increment (the elastic part is mu p / c_T)
    length = 1.0 - du if deformable else 1.0  # the slave has slid du past the end of the master
    assert abs(s["contact_length"] - length) <= 1e-12
    power = mu * P * (slip / dt) * length  # mu p v_slip L
    assert abs(s["friction_power"] - power) <= 1e-12 * power
    assert abs(s["heat_slave"] - kappa * power) <= 1e-12 * power
    assert abs(s["heat_master"] - (1 - kappa) * power) <= 1e-12 * power
    assert abs(s["heat_slave"] + s["heat_master"] - power) <= 1e-12 * power
    Tslave = np.arange(nd * XS.size)[2::nd]
    assert abs(-R[Tslave].sum() - kappa * power) <= 1e-12 * power  # heat entering = -residual
    if deformable:
        Tmaster = np.arange(nd * XS.size, u.size)[2::nd]
        assert abs(-R[Tmaster].sum() - (1 - kappa) * power) <= 1e-12 * power


def weights(x):
    x = np.sort(x)
    h = np.diff(x)
    w = np.zeros(x.size)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


def test_conduction_uniform_jump_exact_nonmatching():
    h0, h1, beta = 0.8, 0.3, 2.0
    th = ThermalSettings(h0=h0, h1=h1, beta=beta, kappa=0.5)
    c, u, nd = build_interface(None, thermal=th, deformable=True, temps=True)
    T1, T2 = 310.0, 290.0
    ns = XS.size
    u[2: nd * ns: nd] = T1
    u[nd * ns + 2:: nd] = T2
    R = residual(c, u)
    hc = h0 + h1 * P**beta
    q_into_slave = hc * (T2 - T1)
    np.testing.assert_allclose(-R[2: nd * ns: nd], q_into_slave * weights(XS), rtol=1e-12)
    xm = np.array([1.0, 0.77, 0.45, 0.3, 0.0])
    np.testing.assert_allclose(-R[nd * ns + 2:: nd], -q_into_slave * weights(xm)[::-1], rtol=1e-12)
    s = c.state()
    assert abs(s["heat_slave"] - q_into_slave) <= 1e-12 * abs(q_into_slave)
    assert abs(s["heat_slave"] + s["heat_master"]) <= 1e-12 * abs(q_into_slave)


def test_rigid_master_temperature_conduction():
    th = ThermalSettings(h0=1.5, kappa=0.5, master_temperature=350.0)
    c, u, nd = build_interface(None, thermal=th, temps=True)
    u[2::nd] = 300.0
    R = residual(c, u)
    np.testing.assert_allclose(-R[2::nd], 1.5 * 50.0 * weights(XS), rtol=1e-12)


def test_slave_node_temperatures_select_mu_per_node_and_power_density_sums_to_the_total():
    """Staggered coupling: with per-node temperatures T_A and a law linear in T, every slipping node
    gets mu(T_A) exactly (1e-12); the nodal power density times the weight sums to the interface's
    friction power (1e-12), and with no temperatures set the law without T input is refused."""
    T = np.linspace(273.0, 473.0, 5)
    law = fl.fit_mu_pvT([0.0, 10.0], [1e-6, 1e5], T,
                        np.broadcast_to(0.8 - 0.002 * (T - 273.0), (2, 2, T.size)).copy(), degree=1)
    c, u, nd = build_interface(law)
    dt, du = 0.02, 0.03
    u[0::nd] = du
    with pytest.raises(ValueError, match="depends on temperature"):
        c.evaluate(u, dt=dt)
    TA = 300.0 + 20.0 * np.arange(XS.size)
    c.set_slave_temperatures(TA)
    s = c.evaluate(u, dt=dt)
    assert np.all(s["status"] == 2)
    np.testing.assert_allclose(s["mu"], 0.8 - 0.002 * (TA - 273.0), rtol=1e-12)
    np.testing.assert_allclose(np.sum(s["friction_power_density"] * s["weight"]),
                               s["friction_power"], rtol=1e-12)
    with pytest.raises(ValueError, match="slave temperatures"):
        c.set_slave_temperatures(TA[:-1])
    with pytest.raises(ValueError, match="slave temperatures"):
        c.set_slave_temperatures(np.full(XS.size, -1.0))
