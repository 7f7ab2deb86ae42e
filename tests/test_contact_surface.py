"""Node-to-surface contact on a smooth periodic height field (``Contact(method="surface")``).

The rigid master is the periodic C2 cubic spline through its uniformly spaced vertices
(``cpp_contact/height_field.hpp``); slave node A has the gap g_A = (z_A - h(x_A)) / sqrt(1 + h'^2),
the penalty potential Pi = sum_A w_A c_N <-g_A>^2 / 2 with constant reference weights w_A (half the
adjacent reference segments), and the residual R = dPi/du.  What is checked, with tolerances:

* the spline reproduces a smooth periodic profile and its first three derivatives (to the
  spline's O(dx^4) / O(dx) accuracy, stated per derivative);
* the residual is the gradient of Pi (central differences of Pi, 1e-7 relative), the tangent the
  derivative of the residual (1e-6 relative, as ``test_contact_tangent``), symmetric without
  friction (1e-12);
* a flat road under a flat block: force = c_N w g exactly, and the contact length is the length
  in contact;
* friction, stick and slip, and the thermal blocks through the same nodal law (tangent 1e-6);
* bad input: an open or non-uniform master is refused with a message naming the method.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction import _contact
from rubberfriction.driver.fe.contact import (
    Contact,
    DeformableMaster,
    PenaltySettings,
    RigidMaster,
    SlaveSurface,
    ThermalSettings,
)
from test_contact_tangent import fd_check, pv_T_law, residual_jacobian

RTOL = 1e-6
PERIOD = 2.0


def road(x: np.ndarray) -> np.ndarray:
    return 0.03 * np.cos(np.pi * x) + 0.01 * np.sin(3.0 * np.pi * x)


def road_derivatives(x: np.ndarray) -> list[np.ndarray]:
    a, b = np.pi, 3.0 * np.pi
    return [road(x),
            -0.03 * a * np.sin(a * x) + 0.01 * b * np.cos(b * x),
            -0.03 * a**2 * np.cos(a * x) - 0.01 * b**2 * np.sin(b * x),
            0.03 * a**3 * np.sin(a * x) - 0.01 * b**3 * np.cos(b * x)]


def master(n: int = 40) -> RigidMaster:
    xm = np.linspace(-0.5, -0.5 + PERIOD, n, endpoint=False)
    return RigidMaster(np.column_stack([xm, road(xm)]), PERIOD)


def chain(nd: int = 2, thermal: bool = False):
    """Curved slave chain of 9 nodes, dofs (u_x, u_z[, T]) interleaved per node."""
    n = 9
    x = np.linspace(0.0, 1.0, n) + 0.01 * np.sin(7.0 * np.arange(n))
    X = np.column_stack([x, 0.05 * np.sin(3.0 * x) + 0.02])
    dofs = np.column_stack([nd * np.arange(n), nd * np.arange(n) + 1])
    return SlaveSurface(X, dofs, np.column_stack([np.arange(n - 1), np.arange(1, n)]),
                        nd * np.arange(n) + 2 if thermal else None)


def pressed(nd: int, *, slide: float, thermal: bool, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u = np.zeros(9 * nd)
    u[1::nd] = -0.045 + 0.004 * rng.standard_normal(9)
    u[0::nd] = slide + 0.002 * rng.standard_normal(9)
    if thermal:
        u[2::nd] = 300.0 + 20.0 * rng.random(9)
    return u


def test_spline_reproduces_a_smooth_periodic_profile():
    """h, h', h'', h''' of the periodic spline through 400 points per period against the exact
    profile: errors O(dx^4), O(dx^3), O(dx^2), O(dx) relative to each derivative's amplitude;
    tolerances 1e-8, 1e-6, 1e-3, 5e-2 at dx = 0.005 (amplitudes 0.04, 0.4, 1, 9)."""
    n = 400
    xm = np.linspace(-0.5, -0.5 + PERIOD, n, endpoint=False)
    hf = _contact.HeightField(np.column_stack([xm, road(xm)]), PERIOD)
    x = np.linspace(-3.0, 3.0, 1001)  # across several periods
    got = np.array([hf(xi) for xi in x]).T
    for k, (g, exact, tol) in enumerate(zip(got, road_derivatives(x), (1e-8, 1e-6, 1e-3, 5e-2))):
        err = np.abs(g - exact).max() / np.abs(exact).max()
        assert err < tol, f"derivative {k}: relative error {err:.2e} > {tol}"


def penalty_energy(c: Contact, u: np.ndarray, w: np.ndarray, cN: float) -> float:
    c.local_system(u)
    g = c.state()["gap"]
    g = np.where(np.isfinite(g), g, 0.0)
    return 0.5 * cN * float(np.sum(w * np.minimum(g, 0.0) ** 2))


def test_residual_is_the_gradient_of_the_penalty_potential():
    """R = dPi/du with Pi = sum_A w_A c_N <-g_A>^2 / 2 (central differences of Pi, 1e-7 relative),
    and the tangent is symmetric (1e-12): the frictionless interface is conservative, so every
    incremental step has an equilibrium however sharp the road is against the elements."""
    cN = 100.0
    slave = chain()
    c = Contact(slave, master(), method="surface", penalty=PenaltySettings(c_N=cN, c_T=0.0),
                search_radius=0.3)
    seg = np.linalg.norm(np.diff(slave.X, axis=0), axis=1)
    w = np.zeros(9)
    w[:-1] += 0.5 * seg
    w[1:] += 0.5 * seg
    u = pressed(2, slide=0.0, thermal=False)
    R, J = residual_jacobian(c, u)
    assert np.count_nonzero(c.state()["status"]) >= 3
    h = 1e-7
    grad = np.array([(penalty_energy(c, u + h * e, w, cN) - penalty_energy(c, u - h * e, w, cN))
                     / (2 * h) for e in np.eye(u.size)])
    assert np.abs(grad - R).max() < 1e-7 * np.abs(R).max()
    assert np.abs(J - J.T).max() < 1e-12 * np.abs(J).max()


CASES = [  # (friction, slide, thermal, statuses that must be present)
    (None, 0.0, False, {1}),
    (0.3, 0.03, False, {2}),
    ("spline", 0.03, True, {2}),
]


@pytest.mark.parametrize("friction,slide,thermal,expect", CASES)
def test_jacobian_matches_finite_differences(friction, slide, thermal, expect):
    nd = 3 if thermal else 2
    th = (ThermalSettings(h0=2.0, h1=0.5, beta=1.5, kappa=0.3, master_temperature=300.0)
          if thermal else None)
    c = Contact(chain(nd, thermal), master(), method="surface",
                friction=pv_T_law() if friction == "spline" else friction,
                penalty=PenaltySettings(c_N=100.0, c_T=60.0), thermal=th, search_radius=0.3)
    u = pressed(nd, slide=slide, thermal=thermal)
    errors, status = fd_check(c, u, nd, dt=0.1, temperature=310.0)
    assert expect <= set(status[status > 0].tolist())
    assert set(errors) == ({"u-u", "u-T", "T-u", "T-T"} if thermal else {"u-u"})
    for name, err in errors.items():
        assert err < RTOL, f"{name} tangent error {err:.2e}"


def test_flat_road_gives_the_penalty_force_and_contact_length():
    """A flat slave 1e-4 mm into a flat road: every node in contact with g = -1e-4, total force
    c_N g times the chain length (exactly, 1e-12), contact length = the chain length."""
    n, L, cN, depth = 11, 1.0, 50.0, 1e-4
    X = np.column_stack([np.linspace(0.0, L, n), np.zeros(n)])
    slave = SlaveSurface(X, np.column_stack([2 * np.arange(n), 2 * np.arange(n) + 1]),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    xm = np.linspace(0.0, 2.0, 16, endpoint=False)
    flat = RigidMaster(np.column_stack([xm, np.full_like(xm, -0.2)]), 2.0)
    c = Contact(slave, flat, method="surface", penalty=PenaltySettings(c_N=cN, c_T=0.0),
                search_radius=0.5)
    u = np.zeros(2 * n)
    u[1::2] = -0.2 - depth
    c.local_system(u)
    s = c.state()
    assert np.all(s["status"] == 1)
    assert abs(s["force_z"] - cN * depth * L) < 1e-12 * cN * depth * L
    assert abs(s["force_x"]) < 1e-15
    assert abs(s["contact_length"] - L) < 1e-12


def test_bad_masters_are_refused():
    slave = chain()
    pen = PenaltySettings(c_N=100.0, c_T=0.0)
    xm = np.linspace(-0.5, 1.5, 40, endpoint=False)
    with pytest.raises(ValueError, match="periodic rigid master"):
        Contact(slave, RigidMaster(np.column_stack([xm, road(xm)])), method="surface", penalty=pen)
    uneven = xm + 0.01 * np.sin(xm)
    with pytest.raises(ValueError, match="uniform x"):
        Contact(slave, RigidMaster(np.column_stack([uneven, road(uneven)]), PERIOD),
                method="surface", penalty=pen)
    other = DeformableMaster(slave.X + [0.0, -1.0], slave.dofs + 100, slave.segments)
    with pytest.raises(ValueError, match="rigid periodic master"):
        Contact(slave, other, method="surface", penalty=pen)
