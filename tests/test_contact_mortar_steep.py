"""Mortar segmentation of a slave segment bent over a master peak sharper than itself (issue 14).

Geometry taken from the failing micro1 run of the default scene (p = 15.1 MPa, v = 1000 mm/s,
frictionless pressure branch): slave nodes 13..16 of the deformed contact face and the road
vertices 192..224 under them, coordinates in mm.  The nodal normals of slave segment (14, 15)
rotate by about 68 degrees, so the ray of a point near node 15 is nearly parallel to the steep
master segment 211 it actually meets.  The former overlap rule (from the two end projections
only) lost that overlap and paired the segment with master segment 222 on the far flank through
a spurious root, and that piece appeared with a finite length under an infinitesimal
displacement: the residual jumped (1.17e-2 -> 4.70e-2 N/mm across 4e-16 mm) and Newton stagnated.

Oracle (geometry only, written here): every piece must be a true projection -- the ray
x(xi) + g n(xi) from the piece's midpoint meets its master segment at eta in [0, 1] -- and the
point xi = 0.98, whose ray meets master segment 211 at eta = 0.23, must be covered by segment 211.
"""

from __future__ import annotations

import numpy as np

from rubberfriction.driver.fe.contact import Contact, PenaltySettings, RigidMaster, SlaveSurface

SLAVE = np.array([[-0.079997, -0.007366], [-0.076534, 0.001485], [-0.067275, 0.006907],
                  [-0.064602, -0.001129]])
MASTER = np.array([
    [-0.077333, -0.000857], [-0.076833, 0.000113], [-0.076333, 0.001029], [-0.075833, 0.001889],
    [-0.075333, 0.002689], [-0.074833, 0.003424], [-0.074333, 0.004093], [-0.073833, 0.004691],
    [-0.073333, 0.005216], [-0.072833, 0.005665], [-0.072333, 0.006036], [-0.071833, 0.006327],
    [-0.071333, 0.006537], [-0.070833, 0.006663], [-0.070333, 0.006705], [-0.069833, 0.006662],
    [-0.069333, 0.006533], [-0.068833, 0.006318], [-0.068333, 0.006018], [-0.067833, 0.005633],
    [-0.067333, 0.005164], [-0.066833, 0.004612], [-0.066333, 0.003979], [-0.065833, 0.003267],
    [-0.065333, 0.002478], [-0.064833, 0.001614], [-0.064333, 0.000679], [-0.063833, -0.000324],
    [-0.063333, -0.001392], [-0.062833, -0.002521], [-0.062333, -0.003707], [-0.061833, -0.004945],
    [-0.061333, -0.006231]])
FIRST = 192  # index of MASTER[0] in the road sample (segment k here is road segment FIRST + k)


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _unit(v):
    return v / np.linalg.norm(v)


def _contact():
    slave = SlaveSurface(X=SLAVE.copy(), dofs=np.arange(8, dtype=np.int64).reshape(4, 2),
                         segments=np.array([[0, 1], [1, 2], [2, 3]], dtype=np.int64))
    c = Contact(slave, RigidMaster(MASTER.copy(), 0.0), method="mortar",
                penalty=PenaltySettings(c_N=1.0e4), search_radius=0.02)
    c.evaluate(np.zeros(8))
    return c


def _nodal_normals():
    """The core's nodal normals at the segment's nodes (state()["normal"])."""
    n = np.asarray(_contact().state()["normal"], float)
    return n[1], n[2]


def _eta(xi, na, nb, m):
    x = SLAVE[1] + xi * (SLAVE[2] - SLAVE[1])
    n = na + xi * (nb - na)
    q0, q1 = MASTER[m], MASTER[m + 1]
    return _cross(x - q0, n) / _cross(q1 - q0, n)


def _pairs():
    p = _contact().cpp.last_pairs()
    return p[p[:, 0] == 1]  # slave segment (node 1, node 2) = (14, 15) of the run


def test_normals_rotate_strongly_here():
    na, nb = _nodal_normals()
    assert np.degrees(np.arccos(np.clip(na @ nb, -1, 1))) > 60.0
    assert 0.0 <= _eta(0.98, na, nb, 211 - FIRST) <= 1.0  # the ray near node 15 meets 211


def test_every_piece_is_a_true_projection():
    na, nb = _nodal_normals()
    pairs = _pairs()
    assert pairs.shape[0] > 0
    for _, _, m, lo, hi, _ in pairs:
        eta = _eta(0.5 * (lo + hi), na, nb, int(m))
        assert -1e-9 <= eta <= 1.0 + 1e-9, f"master segment {int(m) + FIRST}: eta {eta:.3f}"


def test_the_steep_neighbour_covers_its_part():
    pairs = _pairs()
    at = [(int(m) + FIRST) for _, _, m, lo, hi, _ in pairs if lo <= 0.98 <= hi]
    assert at == [211], at
