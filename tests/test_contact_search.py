"""Contact search: the pairs found are exactly the local ones, however long the master.

Oracle (exact, by counting): a straight, flat slave chain (vertical nodal normals) held within
the search radius of a master that is the graph of a function z(x) pairs every point of the slave
with the master point straight below it, so the mortar segmentation has one piece per interval
between consecutive break points, the slave nodes and the master vertices that lie strictly
inside the slave's x-range:

    n_pairs = n_slave_segments + #{master vertices strictly inside the slave's x-range}

(the geometries are chosen with no master vertex within 1e-6 mm of a slave node, so no two break
points merge).  This grows linearly with the slave size at a given master density and does not
depend on master segments away from the slave: a 100x longer master, a sliding offset of 150
block lengths, or a deformable master of 16x more segments change the count only by the local
vertices, and leave the contact forces unchanged to round-off.

Timings (the search cost O(n_slave + local master segments), independent of the master's total
size) are measured by ``rubberfriction bench contact``, not asserted here.  The ``_contact``
module exposes only the number of accepted pairs (``state()["n_pairs"]``); an operation count of
the search itself (candidates returned by the segment grid) is not exposed, so these tests cannot
tell a grid search from a brute-force one with the same result.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe.contact import (Contact, DeformableMaster, PenaltySettings,
                                              RigidMaster, SlaveSurface)

Z_SLAVE, U_Z = 0.002, -0.006  # slave height and its prescribed u_z: slave at z = -0.004
AMPLITUDE = 0.01  # master |z| <= 0.01: every gap below |z| + 0.004 < search radius 0.02
RADIUS = 0.02
SEPARATION = 1e-6  # minimum distance between a master vertex and a slave node (mm)


def rough_profile(n, length, seed=0):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, length, n + 1)
    h = np.cumsum(rng.standard_normal(n + 1)) * length / n * 0.3
    h -= np.linspace(h[0], h[-1], n + 1)  # no drift
    return np.column_stack([x, AMPLITUDE * h / max(np.abs(h).max(), 1e-12)])


def slave(n, x0, length):
    x = x0 + np.linspace(0.0, length, n + 1)
    X = np.column_stack([x, np.full(x.size, Z_SLAVE)])
    return SlaveSurface(X, np.arange(2 * x.size).reshape(-1, 2),
                        np.column_stack([np.arange(n), np.arange(1, n + 1)]))


def expected_pairs(slave_x: np.ndarray, master_x: np.ndarray) -> int:
    """n_slave_segments + master vertices strictly inside the slave's x-range (see the module
    docstring); asserts that no master vertex is ambiguously close to a slave node."""
    x0, x1 = slave_x.min(), slave_x.max()
    inside = master_x[(master_x > x0) & (master_x < x1)]
    gaps = (np.abs(inside[:, None] - slave_x[None, :]).min(axis=1) if inside.size
            else np.array([np.inf]))
    assert gaps.min() > SEPARATION, \
        f"test set-up: a master vertex within {gaps.min():.2e} mm of a slave node"
    return slave_x.size - 1 + inside.size


def evaluate(c: Contact, offset=(0.0, 0.0)) -> dict:
    u = np.zeros(c.cpp.max_dof + 1)
    u[1::2] = U_Z
    c.evaluate(u, offset=offset)
    return c.state()


def test_pairs_do_not_depend_on_the_master_length():
    """Same local master geometry, 100x longer master (1000 -> 100 000 segments)."""
    long = rough_profile(100_000, 100.0)
    sl = slave(400, 0.3 + 1e-3 / 3.0, 0.5)  # master spacing 1e-3, slave 1.25e-3, shifted by 1/3
    n_expected = expected_pairs(sl.X[:, 0], long[:, 0])
    states = []
    for m in (1_000, 100_000):
        c = Contact(sl, RigidMaster(long[: m + 1]), penalty=PenaltySettings(c_N=100.0),
                    search_radius=RADIUS)
        assert c.report()["master"]["segments"] == m
        states.append(evaluate(c))
    short, full = states
    assert short["n_pairs"] == full["n_pairs"] == n_expected  # 400 + 499
    assert short["n_active"] == full["n_active"] > 50
    assert full["Fz"] == pytest.approx(short["Fz"], rel=1e-12, abs=0.0) and short["Fz"] > 0.0
    assert full["Fx"] == pytest.approx(short["Fx"], rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("n", [250, 2000])
def test_pairs_linear_in_the_slave_size(n):
    """8 mm of slave over a 10 mm master of 20 000 segments: n + 16 000 pairs (a search returning
    a segment twice, or a pair per slave segment and *every* master segment, would not match).
    The slave's two chain ends are vertices of a body, whose points are projected along the
    master's normal (cpp_contact/README.md, "Frame of a chain end"), not straight down: the master
    is flat within 0.05 mm of them (longer than an end segment), so that normal is vertical too."""
    master = rough_profile(20_000, 10.0)
    sl = slave(n, 1.0 + 5e-4 / 3.0, 8.0)
    for x_end in (sl.X[0, 0], sl.X[-1, 0]):
        master[np.abs(master[:, 0] - x_end) < 0.05, 1] = 0.0
    c = Contact(sl, RigidMaster(master), penalty=PenaltySettings(c_N=100.0), search_radius=RADIUS)
    st = evaluate(c)
    assert st["n_pairs"] == expected_pairs(sl.X[:, 0], master[:, 0]) == n + 16_000
    assert st["n_paired"] == n + 1


@pytest.mark.parametrize("offset", [-1.0, -150.0])
def test_long_sliding_finds_only_the_local_pairs(offset):
    """Sliding by many block lengths over a long non-periodic sample: at any offset the pairs are
    those of the master vertices under the block."""
    master = rough_profile(50_000, 200.0)  # spacing 4e-3
    sl = slave(400, 0.0, 1.0 + 1e-3)  # spacing 2.5025e-3
    c = Contact(sl, RigidMaster(master), penalty=PenaltySettings(c_N=100.0), search_radius=RADIUS)
    st = evaluate(c, offset=(offset, 0.0))
    assert st["n_pairs"] == expected_pairs(sl.X[:, 0], master[:, 0] + offset)
    assert st["n_paired"] == 401 and st["n_active"] > 0


def test_deformable_master_pairs_are_local():
    """A deformable master of 2000 and of 32 000 segments (rebuilt grid at every evaluation)."""
    counts = {}
    for m in (2_000, 32_000):
        V = rough_profile(m, 10.0)[::-1]  # counter-clockwise around the lower body: right to left
        master = DeformableMaster(V, 10_000 + np.arange(2 * V.shape[0]).reshape(-1, 2),
                                  np.column_stack([np.arange(m), np.arange(1, m + 1)]))
        sl = slave(200, 4.0 + 5e-3 / 3.0, 1.0)  # spacing 5e-3 = the coarse master's: shifted by 1/3
        c = Contact(sl, master, penalty=PenaltySettings(c_N=100.0), search_radius=RADIUS)
        assert c.report()["master"]["segments"] == m
        u = np.zeros(10_000 + 2 * V.shape[0])
        u[1:402:2] = U_Z  # slave only; the master stays in place
        c.evaluate(u)
        st = c.state()
        counts[m] = st["n_pairs"]
        assert st["n_pairs"] == expected_pairs(sl.X[:, 0], V[:, 0])
        assert st["n_active"] > 20
    assert counts == {2_000: 200 + 200, 32_000: 200 + 3200}
