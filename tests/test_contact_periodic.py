"""Periodic rigid master: the sample wraps across the cell boundary.

* A slave chain straddling the period boundary sees the same gaps and forces as the same chain
  shifted by any number of periods, and as an explicitly repeated (non-periodic) profile.
* The rigid offset may be many periods large (sliding over many block lengths).
* A rigid slave chain (prescribed motion) sliding with friction over three periods of a
  periodic profile, one step at a time with committed history: after the first period (run-in)
  the per-period means of F_x and F_z agree within 1e-6 relative.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe.contact import Contact, PenaltySettings, RigidMaster, SlaveSurface

L = 2.0  # period
K = 40  # vertices per period


def profile(x):
    return 0.05 * np.cos(2 * np.pi * x / L) + 0.01 * np.sin(6 * np.pi * x / L + 0.3)


def periodic_master():
    x = np.arange(K) * L / K + 0.137  # the sample does not start at x = 0
    return RigidMaster(np.column_stack([x, profile(x)]), period=L)


def chain(x0, length, n, z0):
    x = x0 + np.linspace(0.0, length, n)
    X = np.column_stack([x, np.full(n, z0)])
    return SlaveSurface(X, np.arange(2 * n).reshape(n, 2),
                        np.column_stack([np.arange(n - 1), np.arange(1, n)]))


def outputs(c: Contact, u, offset=(0.0, 0.0)):
    rr, rv, jr, jc, jv = c.local_system(u, offset=offset)
    R = np.zeros(u.size)
    np.add.at(R, rr, rv)
    s = c.state()
    return R, s["gap"], s["pressure"]


def test_wrap_is_shift_invariant_and_matches_repeated_profile():
    n = 23
    slave = chain(L - 0.6, 1.3, n, 0.06)  # straddles x = L (and the sample start 0.137 + L)
    pen = PenaltySettings(c_N=300.0)
    c = Contact(slave, periodic_master(), penalty=pen, search_radius=0.2)
    u = np.zeros(2 * n)
    u[1::2] = -0.02 + 0.01 * np.sin(np.arange(n))
    R0, g0, p0 = outputs(c, u)
    assert np.count_nonzero(p0) >= 5 and np.count_nonzero(p0) < n  # partial contact
    for k in (1, -3, 17):
        us = u.copy()
        us[0::2] += k * L  # the chain moved by k periods
        Rk, gk, pk = outputs(c, us)
        np.testing.assert_allclose(gk, g0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(Rk, R0, rtol=0, atol=1e-12 * np.abs(R0).max())
        # the same through the rigid offset of the master instead
        Ro, go, po = outputs(c, u, offset=(-k * L, 0.0))
        np.testing.assert_allclose(go, g0, rtol=0, atol=1e-12)
    # explicitly repeated profile, not periodic
    x = np.concatenate([np.arange(K) * L / K + 0.137 + j * L for j in range(-2, 3)])
    c_open = Contact(slave, RigidMaster(np.column_stack([x, profile(x)])), penalty=pen,
                     search_radius=0.2)
    R1, g1, p1 = outputs(c_open, u)
    np.testing.assert_allclose(g1, g0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(R1, R0, rtol=0, atol=1e-12 * np.abs(R0).max())


def test_sliding_three_periods_repeats_each_period():
    """Rigid slave chain (one period long) dragged over 3 periods with friction and history."""
    n = 33
    steps_per_period = 48
    slave = chain(0.0, L, n, 0.0)
    c = Contact(slave, periodic_master(), friction=0.4,
                penalty=PenaltySettings(c_N=500.0, c_T=250.0), search_radius=0.3)
    u = np.zeros(2 * n)
    u[1::2] = 0.02 - 0.0005 * np.arange(n) / n  # fixed vertical position: penetrates the crests
    v, dt = 10.0, L / steps_per_period / 10.0
    Fx, Fz, D, nslip = [], [], [], []
    for k in range(1, 3 * steps_per_period + 1):
        c.set_master_offset(-v * k * dt)  # the road moves in -x, the block slides in +x over it
        c.set_time_step(dt)
        s = c.evaluate(u)
        c.commit()
        Fx.append(s["Fx"])
        Fz.append(s["Fz"])
        D.append(s["dissipation"])
        nslip.append(s["n_slip"])
    Fx, Fz, D = (np.array(a).reshape(3, steps_per_period) for a in (Fx, Fz, D))
    assert Fz.min() > 0 and max(nslip) > 0
    assert np.all(Fx.mean(axis=1) < 0)  # friction on the block opposes its sliding
    for a in (Fx, Fz, D):
        m = a.mean(axis=1)
        assert abs(m[2] - m[1]) <= 1e-6 * abs(m[1]), m


def test_large_offsets_many_periods():
    n = 17
    slave = chain(0.3, 1.0, n, 0.0)
    c = Contact(slave, periodic_master(), penalty=PenaltySettings(c_N=300.0), search_radius=0.2)
    u = np.zeros(2 * n)
    u[1::2] = -0.03
    _, g0, _ = outputs(c, u, offset=(0.25, 0.0))
    _, g1, _ = outputs(c, u, offset=(0.25 - 1000 * L, 0.0))
    np.testing.assert_allclose(g1, g0, rtol=0, atol=1e-10)


def test_diverged_iterate_is_assembled_at_once():
    """A Newton iterate that flung a slave node far away (1e14 mm) is assembled without looping
    over its billions of master images; the flung node's segments get no contact, the rest of the
    chain is unchanged (a diverged iterate is then rejected by its bulk residual). A non-finite
    one is refused with a clear error."""
    n = 23
    slave = chain(L - 0.6, 1.3, n, 0.06)
    c = Contact(slave, periodic_master(), penalty=PenaltySettings(c_N=300.0), search_radius=0.2)
    u = np.zeros(2 * n)
    u[1::2] = -0.02
    _, g_ok, p_ok = outputs(c, u)
    for bad in (np.nan, np.inf):
        ub = u.copy()
        ub[2 * (n - 1)] = bad
        with pytest.raises(ValueError, match="non-finite displacement at slave node 22"):
            outputs(c, ub)
    for bad in (1e14, -1e30):
        ub = u.copy()
        ub[2 * (n - 1)] = bad  # last node's x
        _, g, p = outputs(c, ub)
        assert np.all(np.isfinite(p[: n - 3]))
        np.testing.assert_allclose(p[: n - 3], p_ok[: n - 3], rtol=1e-12, atol=0)


def test_seam_of_a_periodic_cell_is_not_a_corner():
    """A flat chain exactly one period long is a closed periodic chain; with ``periodic_seam`` its
    two ends keep the slave normal (vertical here), so frictionless contact gives F_x = 0 to
    roundoff and the forces do not depend on where the seam sits (the same node set rolled by m
    nodes).  Without the flag the ends are corners of an open body: they take the master's normal
    and, at the tilted crest the seam sits on, push sideways (|F_x| > 1e-4 F_z)."""
    n = 41
    h = L / (n - 1)
    pen = PenaltySettings(c_N=300.0)

    def forces(x0: float, seam: bool) -> tuple[float, float]:
        s = chain(x0, L, n, 0.035)
        s.periodic_seam = seam
        c = Contact(s, periodic_master(), penalty=pen, search_radius=0.2)
        R, _, p = outputs(c, np.zeros(2 * n))
        # ends in contact, partial contact
        assert p[0] > 0 and p[-1] > 0 and np.count_nonzero(p) < n
        return R[0::2].sum(), R[1::2].sum()

    Fx0, Fz0 = forces(0.0, True)
    assert abs(Fz0) > 0 and abs(Fx0) <= 1e-12 * abs(Fz0)
    for m in (1, 2):  # seam still on the crest region, node set unchanged modulo L
        Fx, Fz = forces(m * h, True)
        assert abs(Fx) <= 1e-12 * abs(Fz0)
        assert abs(Fz - Fz0) <= 1e-12 * abs(Fz0)
    Fx_open, _ = forces(0.0, False)
    assert abs(Fx_open) > 1e-4 * abs(Fz0)
