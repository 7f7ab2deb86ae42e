"""Patch-level exactness of the contact integrals (no bulk): flat faces on non-matching meshes.

A flat slave chain uniformly penetrating a flat master by g must receive the consistent nodal
forces of the uniform pressure p = c_N g: f_B = p Int N_B da along the normal, total p L --
exactly (1e-12), for any master discretisation and orientation.  Segment-to-segment (mortar)
achieves this on both sides; node-to-segment transmits the slave forces and the total exactly but
distributes the master forces wrongly (reported, not hidden).
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe.contact import (Contact, DeformableMaster, PenaltySettings,
                                              RigidMaster, SlaveSurface)

CN = 250.0
G = 0.004  # penetration


def rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def slave_chain(x):
    n = x.size
    X = np.column_stack([x, np.zeros(n)])
    return X, np.arange(2 * n).reshape(n, 2), np.column_stack([np.arange(n - 1), np.arange(1, n)])


def consistent_weights(x):
    """Int N_B dx for the chain with nodes x (sorted)."""
    h = np.diff(x)
    w = np.zeros(x.size)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


def residual(c: Contact, u):
    rr, rv, *_ = c.local_system(u)
    R = np.zeros(u.size)
    np.add.at(R, rr, rv)
    return R


XS = np.array([0.0, 0.09, 0.23, 0.31, 0.5, 0.58, 0.77, 0.9, 1.0])  # non-uniform slave


@pytest.mark.parametrize("theta", [0.0, 0.3, -1.1, 2.5])
@pytest.mark.parametrize("method", ["mortar", "nts"])
def test_rigid_master_uniform_pressure_exact(theta, method):
    Q = rot(theta)
    X, dofs, seg = slave_chain(XS)
    X = X @ Q.T
    xm = np.array([-0.4, -0.05, 0.17, 0.4, 0.44, 0.71, 0.98, 1.3])  # non-matching master vertices
    V = np.column_stack([xm, np.zeros(xm.size)]) @ Q.T
    c = Contact(SlaveSurface(X, dofs, seg), RigidMaster(V), method=method,
                penalty=PenaltySettings(c_N=CN, c_T=0.0))
    n = Q @ np.array([0.0, -1.0])  # slave outward normal
    u = np.tile(G * n, XS.size)  # uniform penetration
    R = residual(c, u).reshape(-1, 2)
    p = CN * G
    expected = p * consistent_weights(XS)[:, None] * n[None, :]
    assert np.abs(R - expected).max() <= 1e-12 * np.abs(expected).max()
    s = c.state()
    np.testing.assert_allclose(s["pressure"], p, rtol=1e-12)
    np.testing.assert_allclose(s["gap"], -G, rtol=1e-12)
    assert abs(s["contact_length"] - 1.0) < 1e-12
    np.testing.assert_allclose([s["Fx"], s["Fz"]], -p * 1.0 * n, rtol=1e-12, atol=1e-14)


def lower_body_face(xm):
    """Top face of a lower body, counter-clockwise around it: runs right to left."""
    xm = np.sort(xm)[::-1]
    m = xm.size
    return np.column_stack([xm, np.zeros(m)]), np.column_stack([np.arange(m - 1), np.arange(1, m)])


@pytest.mark.parametrize("theta", [0.0, 0.7])
def test_deformable_master_mortar_exact_both_sides(theta):
    """Mortar: consistent nodal forces on the slave AND on the non-matching master."""
    Q = rot(theta)
    X, dofs, seg = slave_chain(XS)
    xm = np.array([0.0, 0.13, 0.41, 0.47, 0.66, 1.0])  # same span, no interior node matches
    Xm, mseg = lower_body_face(xm)
    mdofs = 2 * XS.size + np.arange(2 * xm.size).reshape(-1, 2)
    c = Contact(SlaveSurface(X @ Q.T, dofs, seg), DeformableMaster(Xm @ Q.T, mdofs, mseg),
                method="mortar", penalty=PenaltySettings(c_N=CN, c_T=0.0))
    n = Q @ np.array([0.0, -1.0])
    u = np.zeros(2 * (XS.size + xm.size))
    u[: 2 * XS.size] = np.tile(G * n, XS.size)
    R = residual(c, u).reshape(-1, 2)
    p = CN * G
    f_slave = p * consistent_weights(XS)[:, None] * n
    # master nodes run right to left
    f_master = -p * consistent_weights(np.sort(xm))[::-1][:, None] * n
    assert np.abs(R[: XS.size] - f_slave).max() <= 1e-12 * np.abs(f_slave).max()
    assert np.abs(R[XS.size:] - f_master).max() <= 1e-12 * np.abs(f_master).max()


def test_deformable_master_nts_slave_exact_master_not():
    """Node-to-segment: slave forces and the total are exact, the master distribution is not
    (the classical failure of one-pass NTS on non-matching meshes)."""
    X, dofs, seg = slave_chain(XS)
    xm = np.array([0.0, 0.13, 0.41, 0.47, 0.66, 1.0])
    Xm, mseg = lower_body_face(xm)
    mdofs = 2 * XS.size + np.arange(2 * xm.size).reshape(-1, 2)
    c = Contact(SlaveSurface(X, dofs, seg), DeformableMaster(Xm, mdofs, mseg), method="nts",
                penalty=PenaltySettings(c_N=CN, c_T=0.0))
    u = np.zeros(2 * (XS.size + xm.size))
    u[1: 2 * XS.size: 2] = -G
    R = residual(c, u).reshape(-1, 2)
    p = CN * G
    f_slave = p * consistent_weights(XS)[:, None] * np.array([0.0, -1.0])
    f_master = p * consistent_weights(np.sort(xm))[::-1]
    assert np.abs(R[: XS.size] - f_slave).max() <= 1e-12 * p
    assert abs(R[XS.size:, 1].sum() - p * 1.0) <= 1e-12 * p  # total transmitted
    err = np.abs(R[XS.size:, 1] - f_master).max() / f_master.max()
    assert err > 1e-2, "NTS unexpectedly passed the master-side patch test"


def test_partial_overlap_is_clipped_exactly():
    """A rigid master covering x in [0.2, 0.7] only: force = p x 0.5 exactly (segmentation)."""
    X, dofs, seg = slave_chain(XS)
    V = np.array([[0.2, 0.0], [0.33, 0.0], [0.61, 0.0], [0.7, 0.0]])
    c = Contact(SlaveSurface(X, dofs, seg), RigidMaster(V),
                penalty=PenaltySettings(c_N=CN, c_T=0.0))
    u = np.zeros(2 * XS.size)
    u[1::2] = -G
    R = residual(c, u)
    assert abs(R[1::2].sum() + CN * G * 0.5) <= 1e-12 * CN * G
    assert abs(c.state()["Fz"] - CN * G * 0.5) <= 1e-12 * CN * G


def test_gap_open_gives_no_force_and_reports_gap():
    X, dofs, seg = slave_chain(XS)
    c = Contact(SlaveSurface(X, dofs, seg), RigidMaster(np.array([[-1.0, -0.01], [2.0, -0.01]])),
                penalty=PenaltySettings(c_N=CN))
    u = np.zeros(2 * XS.size)
    rr, rv, jr, jc, jv = c.local_system(u)
    assert rr.size == 0 and jr.size == 0
    s = c.state()
    np.testing.assert_allclose(s["gap"], 0.01, rtol=1e-12)
    assert s["contact_length"] == 0.0 and not s["active"].any()


@pytest.mark.parametrize("method", ["mortar", "nts"])
def test_curved_slave_fully_paired_with_a_long_master_segment(method):
    """Regression: with rotating nodal normals, projecting far-away master nodes onto a slave
    segment has spurious roots; pairing must not depend on where the master segment ends."""
    R = 10.0
    # irregular arc near the bottom
    theta = np.linspace(-0.06, 0.06, 49) + 1e-3 * np.sin(np.arange(49))
    X = np.column_stack([R * np.sin(theta), R - R * np.cos(theta)])
    n = X.shape[0]
    slave = SlaveSurface(X, np.arange(2 * n).reshape(n, 2),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    for half in (2.0, 20.0, 2000.0):
        c = Contact(slave, RigidMaster(np.array([[-half, 0.0], [half, 0.0]])), method=method,
                    penalty=PenaltySettings(c_N=100.0), search_radius=1.0)
        s = c.evaluate(np.zeros(2 * n))
        assert s["paired"].all()
        if method == "mortar":
            length = np.linalg.norm(np.diff(X, axis=0), axis=1).sum()
            assert abs(s["weight"].sum() - length) <= 1e-12 * length
