"""The contact tangent is the exact derivative of the contact residual.

Central finite differences of the assembled residual against the Jacobian, column by column, on
curved slave and master surfaces (so the projection, the segmentation points and the averaged
normals all vary with u), for every group of terms: normal penalty, stick, slip with constant mu,
slip with mu(p, v, T) from a spline, and the thermal blocks (conduction with h_c(p), frictional
heating, temperature coupling of mu).  Mortar and node-to-segment, rigid and deformable master,
and a chain end in contact across a master kink (its frame is the master normal averaged over its
support).
Tolerance: 1e-6 relative, per block (u-u, u-T, T-u, T-T), to the block's largest entry.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.fe.contact import (Contact, DeformableMaster, PenaltySettings,
                                              RigidMaster, SlaveSurface, ThermalSettings)

RTOL = 1e-6


def pv_T_law() -> fl.SplineLaw:
    """A smooth mu(p, v, T) with all three derivatives nonzero in the test range."""
    p = np.linspace(0.0, 20.0, 6)
    v = np.logspace(-3, 2, 7)
    T = np.linspace(250.0, 400.0, 5)
    P, V, TT = np.meshgrid(p, v, T, indexing="ij")
    mu = 0.5 + 0.2 * np.exp(-P / 10.0) * (0.5 + 0.3 * np.tanh(np.log10(V))) - 0.003 * (TT - 300.0)
    return fl.fit_mu_pvT(p, v, T, mu)


def build(method="mortar", *, friction=None, thermal=False, deformable=False):
    """Curved slave chain above a curved master; dofs (u_x, u_z[, T]) interleaved per node."""
    n = 9
    x = np.linspace(0.0, 1.0, n) + 0.01 * np.sin(7.0 * np.arange(n))
    X = np.column_stack([x, 0.05 * np.sin(3.0 * x) + 0.02])
    nd = 3 if thermal else 2
    dofs = np.column_stack([nd * np.arange(n), nd * np.arange(n) + 1])
    tdofs = nd * np.arange(n) + 2 if thermal else None
    slave = SlaveSurface(X, dofs, np.column_stack([np.arange(n - 1), np.arange(1, n)]), tdofs)
    ndof = nd * n
    if deformable:
        m = 13
        xm = np.linspace(1.3, -0.3, m)  # the lower body's top face runs right to left
        mdofs = ndof + np.column_stack([nd * np.arange(m), nd * np.arange(m) + 1])
        mt = ndof + nd * np.arange(m) + 2 if thermal else None
        master = DeformableMaster(np.column_stack([xm, 0.03 * np.cos(2.0 * xm)]), mdofs,
                                  np.column_stack([np.arange(m - 1), np.arange(1, m)]), mt)
        ndof += nd * m
    else:
        xm = np.linspace(-0.5, 1.5, 23)
        master = RigidMaster(np.column_stack([xm, 0.03 * np.cos(2.0 * xm)]))
    th = ThermalSettings(h0=2.0, h1=0.5, beta=1.5, kappa=0.3,
                         master_temperature=None if deformable else 300.0) if thermal else None
    c = Contact(slave, master, method=method, friction=friction,
                penalty=PenaltySettings(c_N=100.0, c_T=60.0), thermal=th, search_radius=0.3)
    return c, ndof, nd


def residual_jacobian(c: Contact, u, **kw):
    rr, rv, jr, jc, jv = c.local_system(u, **kw)
    R = np.zeros(u.size)
    np.add.at(R, rr, rv)
    J = np.zeros((u.size, u.size))
    np.add.at(J, (jr, jc), jv)
    return R, J


def state_of(c: Contact, u, **kw):
    c.local_system(u, **kw)
    return c.state()["status"].copy()


def fd_check(c: Contact, u, nd, h=1e-7, **kw) -> tuple[dict, np.ndarray]:
    """Per-block relative errors {name: err} of the Jacobian against central differences."""
    R, J = residual_jacobian(c, u, **kw)
    status = state_of(c, u, **kw)
    Jfd = np.zeros_like(J)
    for j in range(u.size):
        hj = h * max(1.0, abs(u[j]))  # temperatures are O(300 K)
        up, um = u.copy(), u.copy()
        up[j] += hj
        um[j] -= hj
        assert np.array_equal(state_of(c, up, **kw), status), \
            "the FD stencil crosses a stick/slip/open switch"
        Jfd[:, j] = ((residual_jacobian(c, up, **kw)[0] - residual_jacobian(c, um, **kw)[0])
                     / (2 * hj))
    T = (np.arange(u.size) % nd == 2) if nd == 3 else np.zeros(u.size, bool)
    U = ~T
    errors = {}
    for name, (r, k) in {"u-u": (U, U), "u-T": (U, T), "T-u": (T, U), "T-T": (T, T)}.items():
        blk, blk_fd = J[np.ix_(r, k)], Jfd[np.ix_(r, k)]
        if blk.size == 0 or np.abs(blk_fd).max() == 0.0:
            assert blk.size == 0 or np.abs(blk).max() == 0.0, \
                f"{name}: tangent has entries FD does not"
            continue
        errors[name] = float(np.abs(blk - blk_fd).max() / np.abs(blk_fd).max())
    return errors, status


def configuration(ndof, nd, *, deformable, slide, thermal, seed=1):
    """Slave pushed 0.04 into the master, random perturbation, rigid slide of the slave by
    `slide`."""
    rng = np.random.default_rng(seed)
    u = np.zeros(ndof)
    ns = 9
    u[1:nd * ns:nd] = -0.045 + 0.004 * rng.standard_normal(ns)
    u[0:nd * ns:nd] = slide + 0.002 * rng.standard_normal(ns)
    if deformable:
        u[nd * ns::nd] = 0.003 * rng.standard_normal((ndof - nd * ns) // nd)
        u[nd * ns + 1::nd] = 0.02 + 0.003 * rng.standard_normal((ndof - nd * ns) // nd)
    if thermal:
        u[2::nd] = 300.0 + 20.0 * rng.random(ndof // nd)
    return u


CASES = [
    # (method, deformable, friction, slide, thermal, expected statuses present)
    ("mortar", False, None, 0.0, False, {1}),
    ("mortar", False, 0.3, 0.0, False, {1}),  # stick (no slip increment yet)
    ("mortar", False, 0.3, 0.03, False, {2}),  # slip
    ("mortar", False, "spline", 0.03, False, {2}),  # slip with mu(p, v, T)
    ("mortar", False, "spline", 0.03, True, {2}),  # + thermal blocks, mu(T) from the slave nodes
    ("mortar", True, None, 0.0, False, {1}),
    ("mortar", True, 0.3, 0.03, False, {2}),
    ("mortar", True, "spline", 0.03, True, {2}),
    ("nts", False, 0.3, 0.0, False, {1}),
    ("nts", False, "spline", 0.03, True, {2}),
    ("nts", True, "spline", 0.03, True, {2}),
]


@pytest.mark.parametrize("method,deformable,friction,slide,thermal,expect", CASES)
def test_jacobian_matches_finite_differences(method, deformable, friction, slide, thermal, expect):
    law = pv_T_law() if friction == "spline" else friction
    c, ndof, nd = build(method, friction=law, thermal=thermal, deformable=deformable)
    u = configuration(ndof, nd, deformable=deformable, slide=slide, thermal=thermal)
    errors, status = fd_check(c, u, nd, dt=0.1, temperature=310.0)
    active = set(status[status > 0].tolist())
    assert expect <= active, f"statuses {status}"
    assert np.count_nonzero(status) >= 3
    # the blocks compared (a block that FD sees as zero is skipped by fd_check: none may be)
    assert set(errors) == ({"u-u", "u-T", "T-u", "T-T"} if thermal else {"u-u"})
    for name, err in errors.items():
        assert err < RTOL, f"{name} tangent error {err:.2e}"


def test_thermal_blocks_are_nonzero_and_checked():
    """The FD check above includes T-rows/T-cols: make sure they carry weight (not vacuous)."""
    c, ndof, nd = build("mortar", friction=pv_T_law(), thermal=True, deformable=True)
    u = configuration(ndof, nd, deformable=True, slide=0.03, thermal=True)
    _, J = residual_jacobian(c, u, dt=0.1)
    T = np.arange(ndof) % nd == 2
    U = ~T
    for name, block in {"T-T": J[np.ix_(T, T)], "T-u": J[np.ix_(T, U)],
                        "u-T": J[np.ix_(U, T)]}.items():
        assert np.abs(block).max() > 1e-6 * np.abs(J).max(), f"{name} block is empty"


def test_jacobian_exact_for_a_slave_wrapped_around_a_sharp_peak():
    """A coarse slave chain bent over a rigid peak sharper than its elements (nodal normals up to
    63 degrees apart, master segments 10x shorter): many master nodes have no projection inside
    the slave segment along the rotating normal field (no real root, or a root outside [0, 1]).
    Such an overlap end is a slave end, a constant; it used to be linearised as a master-node
    projection at the clamped value, and Newton converged only linearly (a micro-scale sliding
    run of the default road stalled at a residual of 1e-7).  Positions from that run."""
    xs = np.array([[-0.02275, 0.08652], [-0.01856, 0.09866], [-0.01606, 0.10826],
                   [-0.00314, 0.11416], [7e-05, 0.10312], [0.00491, 0.0898], [0.00767, 0.07793]])
    n = len(xs)
    xm = np.arange(-0.05, 0.04 + 1e-9, 0.0005)
    master = RigidMaster(np.column_stack([xm, 0.116 * np.exp(-((xm + 0.0087) / 0.0272) ** 2)]))
    slave = SlaveSurface(xs, np.column_stack([2 * np.arange(n), 2 * np.arange(n) + 1]),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    c = Contact(slave, master, penalty=PenaltySettings(c_N=5e4, c_T=0.0), search_radius=0.0133)
    errors, status = fd_check(c, np.zeros(2 * n), 2, h=1e-8)
    assert np.count_nonzero(status) == n  # every node in contact
    assert errors["u-u"] < RTOL, f"tangent error {errors['u-u']:.2e}"


def corner_chain(method, *, deformable, friction):
    """A slave chain whose end segment dips into a kinked master like a sharp corner pressed into
    a road: the end node's support spans a kink of the master, so its frame (the mortar average of
    the master normal over the support, cpp_contact/README.md, Kinematics) moves with the slave
    and (deformable) master nodes."""
    n = 5
    X = np.column_stack([np.linspace(0.0, 1.0, n), [0.02, 0.021, 0.019, 0.02, -0.005]])
    slave = SlaveSurface(X, np.column_stack([2 * np.arange(n), 2 * np.arange(n) + 1]),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    xm = np.array([-0.5, 0.3, 0.87, 1.5])
    zm = np.array([0.0, 0.004, -0.008, 0.01])
    ndof = 2 * n
    if deformable:  # the lower body's top face runs right to left
        m = len(xm)
        master = DeformableMaster(np.column_stack([xm[::-1], zm[::-1]]),
                                  ndof + np.column_stack([2 * np.arange(m), 2 * np.arange(m) + 1]),
                                  np.column_stack([np.arange(m - 1), np.arange(1, m)]))
        ndof += 2 * m
    else:
        master = RigidMaster(np.column_stack([xm, zm]))
    c = Contact(slave, master, method=method, friction=friction,
                penalty=PenaltySettings(c_N=100.0, c_T=60.0), search_radius=0.3)
    rng = np.random.default_rng(3)
    u = np.zeros(ndof)
    u[1:2 * n:2] = -0.03 + 0.002 * rng.standard_normal(n)
    u[0:2 * n:2] = (0.03 if friction else 0.0) + 0.002 * rng.standard_normal(n)
    if deformable:
        u[2 * n:] = 0.002 * rng.standard_normal(ndof - 2 * n)
    return c, u, n


@pytest.mark.parametrize("method,deformable,friction", [("mortar", False, 0.3),
                                                        ("mortar", True, 0.3),
                                                        ("mortar", False, None),
                                                        ("nts", False, 0.3),
                                                        ("nts", True, 0.3)])
def test_jacobian_exact_at_a_chain_end_on_a_kinked_master(method, deformable, friction):
    """FD check of the chain-end frame: the end node is in contact, its frame is the master's
    normal averaged over its support (not the one-sided normal of the tilted end segment), the
    support straddles the master kink at x = 0.87 (mortar: two master pieces with moving
    breakpoints; node-to-segment: the segment under the node) and the tangent stays exact."""
    c, u, n = corner_chain(method, deformable=deformable, friction=friction)
    errors, status = fd_check(c, u, 2, dt=0.1)
    assert status[n - 1] == (2 if friction else 1) and np.count_nonzero(status) == n
    assert errors["u-u"] < RTOL, f"tangent error {errors['u-u']:.2e}"
    nrm = c.state()["normal"][n - 1]
    x = c.slave.X + u[c.slave.dofs]
    t_end = x[n - 1] - x[n - 2]
    one_sided = np.array([t_end[1], -t_end[0]]) / np.linalg.norm(t_end)
    # the end segment is tilted
    assert np.degrees(np.arccos(np.clip(nrm @ one_sided, -1.0, 1.0))) > 5.0
    assert nrm[1] < -0.99  # the master's normal, seen from the slave


def test_chain_end_frame_is_the_flat_masters_normal():
    """On a flat rigid master the frame of a chain end in contact is exactly -z, whatever the
    tilt of its end segment, so p n_A + t_T tau_A adds nothing to F_x from the pressure and
    nothing to F_z from the friction; the interior nodes keep their averaged normals (5.36)."""
    n = 4
    X = np.column_stack([np.linspace(0.0, 0.3, n), np.zeros(n)])
    slave = SlaveSurface(X, np.column_stack([2 * np.arange(n), 2 * np.arange(n) + 1]),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    c = Contact(slave, RigidMaster(np.array([[-1.0, 0.0], [1.0, 0.0]])), friction=0.5,
                penalty=PenaltySettings(c_N=100.0, c_T=10.0), search_radius=0.2)
    u = np.zeros(2 * n)
    # the last node digs in: end segment tilted 10 degrees
    u[1::2] = [-0.001, -0.001, -0.002, -0.02]
    u[0::2] = 0.5  # slip everywhere: c_T x 0.5 > mu p
    st = c.evaluate(u, dt=1.0)
    assert np.all(st["status"] == 2)
    assert np.array_equal(st["normal"][[0, n - 1]], [[0.0, -1.0], [0.0, -1.0]])
    assert st["normal"][n - 2, 0] < -0.02  # interior: averaged over the tilted end segment
    t = st["tangential_traction"]
    assert np.allclose(np.abs(t), 0.5 * st["pressure"], rtol=1e-14)
    # force of the two chain ends: exactly on the master's friction cone
    w, p = st["weight"], st["pressure"]
    ends = [0, n - 1]
    Fz_ends = np.sum(w[ends] * p[ends])
    Fx_ends = -np.sum(w[ends] * t[ends])
    assert Fx_ends == pytest.approx(-0.5 * Fz_ends, rel=1e-14)


@pytest.mark.parametrize("tilt_deg", [30.0, 101.0, 150.0])
def test_chain_end_projects_along_the_flat_masters_normal(tilt_deg):
    """A chain end is a vertex of the body: its frame is the master's normal, and so is the
    direction along which the slave points next to it are projected.  End segment A-B of length
    L tilted by `tilt_deg` below the road's x axis, its neighbour segment flat: projected along
    -z near A (its normal field turns from B's averaged normal to -z at A, always facing the
    road), the whole segment is covered, so A's mortar weight is L/2 and its weighted gap
    Int N_A z da / Int N_A da = (2 z_A + z_B)/3 (z linear along the segment; the frame is -z, so
    only the vertical distance counts) -- closed form, within 1e-12.
    Before, the points next to A were projected along the one-sided normal of the end segment:
    past 90 degrees of tilt (the sharp corner of the 20 x 8 mm block at 0.3 MPa, 80 contact
    elements, tucks under like this) that normal faces away from the road, the part of the
    segment next to A was not paired, A's weight fell to a fraction of L/2 and its own
    penetration no longer entered its gap (the corner node sank 0.09 mm with a gap of 0.014 mm
    under a 10 x stiffer penalty)."""
    L, zB = 0.25, 0.004
    t = np.radians(tilt_deg)
    B = np.array([0.5, zB])
    A = B + L * np.array([np.cos(t), -np.sin(t)])
    X = np.array([[0.0, zB], [0.25, zB], B, A])
    n = len(X)
    slave = SlaveSurface(X, np.column_stack([2 * np.arange(n), 2 * np.arange(n) + 1]),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    c = Contact(slave, RigidMaster(np.array([[-1.0, 0.0], [2.0, 0.0]])), friction=0.5,
                penalty=PenaltySettings(c_N=100.0, c_T=10.0), search_radius=0.5)
    st = c.evaluate(np.zeros(2 * n), dt=1.0)
    assert st["weight"][n - 1] == pytest.approx(0.5 * L, rel=1e-12)
    assert st["gap"][n - 1] == pytest.approx((2.0 * A[1] + B[1]) / 3.0, rel=1e-12)
    assert np.array_equal(st["normal"][n - 1], [0.0, -1.0])
    assert st["pressure"][n - 1] == pytest.approx(-100.0 * (2.0 * A[1] + B[1]) / 3.0, rel=1e-12)
    errors, status = fd_check(c, np.full(2 * n, 1e-3), 2, dt=1.0)  # and the tangent stays exact
    assert status[n - 1] > 0 and errors["u-u"] < RTOL, f"tangent error {errors['u-u']:.2e}"
