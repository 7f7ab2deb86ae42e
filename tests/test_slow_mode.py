"""The slow-mode extrapolation of a periodic cell (``driver.sliding.slowmode``).

Aitken's extrapolation is exact for a geometric sequence: fed the period starts
x_n = x_inf + D rho^n (and histories H_n = H_inf + A rho^n) it lands on x_inf and H_inf to
round-off (the rows' creep; a face that hardly creeps is left alone).  Where equilibrium cannot
be found it goes as far as it can, and where the changes are not geometric or not worth it, it
leaves the state alone.  The FE runs with and without it are compared in
``test_a_stationary_cell_is_not_extrapolated`` and (slow) ``test_extrapolated_creep_...``.
"""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from rubberfriction.driver.sliding import slowmode
from rubberfriction.driver.sliding.slowmode import SlowModeExtrapolation

NX, NZ, L, H, TERMS, NPTS = 8, 4, 1.0, 1.0, 3, 4
RHO = 0.7


class FakeHistory:
    def __init__(self, ncells: int):
        self.npts = NPTS
        self.H = np.zeros((TERMS, ncells * NPTS, 4))
        self.Sbar_n = np.zeros((ncells * NPTS, 4))

    def restore(self, H, Sbar):
        self.H[...] = H
        self.Sbar_n[...] = Sbar


class FakeSolid:
    """A structured NX x NZ grid of nodes (columns x = 0 .. L - L/NX, graded rows), its cells and
    histories: what SlowModeExtrapolation reads of a SolidProblem."""

    def __init__(self):
        x = np.arange(NX) * L / NX
        z = np.array([0.0, 0.1, 0.3, 1.0])
        X, Z = np.meshgrid(x, z)
        self.node_X = np.column_stack([X.ravel(), Z.ravel()])
        cx = x + 0.5 * L / NX
        cz = 0.5 * (z[1:] + z[:-1])
        CX, CZ = np.meshgrid(cx, cz)
        self.centroids = np.column_stack([CX.ravel(), CZ.ravel()])
        self.w = SimpleNamespace(x=SimpleNamespace(array=np.zeros(2 * NX * NZ + 5)))
        self.history = FakeHistory(self.centroids.shape[0])

    def displacement_dofs(self):
        return np.arange(2 * NX * NZ).reshape(-1, 2)

    def cell_centroids(self):
        return self.centroids

    def history_kinematics(self):
        return np.zeros_like(self.history.Sbar_n), None


def feed(ex: SlowModeExtrapolation, sp: FakeSolid, states, equilibrate=lambda s: True):
    """Period starts (x, H) one after the other; the result of the last after_jump."""
    out = None
    for x, Hn in states:
        sp.w.x.array[:] = x
        sp.history.H[...] = Hn
        out = ex.after_jump(equilibrate)
    return out


def geometric(x_inf, D, H_inf, A, n=4):
    return [(x_inf + D * RHO ** k, H_inf + A * RHO ** k) for k in range(n)]


def creep_sequence(sp: FakeSolid, rng):
    """A fixed contact pattern (random) plus a horizontal creep of each row by c(z) rho^k, many
    contact elements a period; histories creep by a row-wise amount too."""
    n = sp.w.x.array.size
    x_inf = rng.normal(scale=1e-3, size=n)
    D = np.zeros(n)
    dofs = sp.displacement_dofs()
    rows = np.round(sp.node_X[:, 1], 6)
    c = -0.5 * (1.0 - sp.node_X[:, 1])  # the face creeps most, the top (z = 1) not at all
    D[dofs[:, 0]] = c
    H_inf = rng.normal(size=sp.history.H.shape)
    cell_row = np.repeat(np.round(sp.centroids[:, 1], 6), NPTS)
    A = np.broadcast_to(cell_row[None, :, None] * np.arange(1, TERMS + 1)[:, None, None],
                        sp.history.H.shape).copy()
    return x_inf, D, H_inf, A, rows


def test_creep_of_the_rows_lands_on_the_limit_and_the_road_moves_with_the_face():
    rng = np.random.default_rng(1)
    sp = FakeSolid()
    ex = SlowModeExtrapolation(sp)
    x_inf, D, H_inf, A, _ = creep_sequence(sp, rng)
    shifts = []
    out = feed(ex, sp, geometric(x_inf, D, H_inf, A), lambda s: shifts.append(s) or True)
    assert out is not None and ex.count == 1
    assert np.allclose(sp.w.x.array, x_inf, rtol=0, atol=1e-12)
    assert np.allclose(sp.history.H, H_inf, rtol=0, atol=1e-12)
    moved, shift = out
    face_creep_left = 0.5 * RHO ** 3  # -c(0) rho^3: what the face still had to creep
    assert shift == pytest.approx(face_creep_left, rel=1e-12)
    assert shifts == [pytest.approx(shift, rel=1e-12)]
    assert np.allclose(moved, x_inf - (x_inf + D * RHO ** 3), atol=1e-12)
    assert ex.omegas == [pytest.approx(RHO / (1 - RHO), rel=1e-12)]


def test_a_face_that_hardly_creeps_is_left_alone():
    """Below CREEP_ELEMENTS of face creep a period nothing is extrapolated, however geometric the
    changes of the rest of the state (the contact's settling is not extrapolated)."""
    rng = np.random.default_rng(2)
    sp = FakeSolid()
    ex = SlowModeExtrapolation(sp)
    n = sp.w.x.array.size
    x_inf, D = rng.normal(size=n), rng.normal(scale=1e-3, size=n)
    face = sp.displacement_dofs()[sp.node_X[:, 1] == 0.0, 0]
    D[face] -= D[face].mean()  # no creep of the face
    H_inf, A = rng.normal(size=sp.history.H.shape), rng.normal(size=sp.history.H.shape)
    seq = geometric(x_inf, D, H_inf, A)
    assert feed(ex, sp, seq) is None and ex.count == 0
    assert np.array_equal(sp.w.x.array, seq[-1][0])


def test_without_equilibrium_it_goes_as_far_as_equilibrium_is_found():
    """Equilibrium only up to a third of the way: full and half fail, a quarter converges, then
    the rest in parts that halve; no equilibrium at all leaves the state as it was."""
    rng = np.random.default_rng(3)
    sp = FakeSolid()
    x_inf, D, H_inf, A, _ = creep_sequence(sp, rng)
    seq = geometric(x_inf, D, H_inf, A)
    full = 0.5 * RHO ** 3
    ex = SlowModeExtrapolation(sp)
    feed(ex, sp, seq, lambda s: abs(s) <= abs(full) / 3 + 1e-15)
    f = ex.omegas[0] / (RHO / (1 - RHO))
    assert 0.25 <= f <= 1 / 3 and ex.count == 1
    x3 = seq[-1][0]
    assert np.allclose(sp.w.x.array, x3 + f * (x_inf - x3), atol=1e-12)
    ex = SlowModeExtrapolation(sp)
    calls = []
    assert feed(ex, sp, seq, lambda s: calls.append(s) or s == 0.0) is None
    assert ex.rejected == 1 and calls[-1] == 0.0  # the road back where it was
    assert np.array_equal(sp.w.x.array, x3) and np.array_equal(sp.history.H, seq[-1][1])


def test_changes_that_are_not_geometric_or_not_worth_it_leave_the_state_alone():
    rng = np.random.default_rng(4)
    sp = FakeSolid()
    x_inf, D, H_inf, A, _ = creep_sequence(sp, rng)
    seq = geometric(x_inf, D, H_inf, A)
    wobbly = [seq[0], seq[1], (seq[0][0] + 0.3 * D, seq[2][1]), seq[3]]  # ratios disagree
    ex = SlowModeExtrapolation(sp)
    assert feed(ex, sp, wobbly) is None and ex.count == 0
    assert np.array_equal(sp.w.x.array, seq[3][0])
    ex = SlowModeExtrapolation(sp)
    out = None
    for x, Hn in seq:
        sp.w.x.array[:] = x
        sp.history.H[...] = Hn
        out = ex.after_jump(lambda s: True, lambda omega: False)
    assert out is None and np.array_equal(sp.w.x.array, seq[3][0])
    assert slowmode.RHO_MIN <= RHO <= slowmode.RHO_MAX


def test_a_stationary_cell_is_not_extrapolated():
    """The three-cosine cell of ``test_shortcut`` (0.05 MPa, 100 mm/s) settles in five periods;
    with the extrapolation on its results are bit-identical (the changes are below half the
    window's tolerance, so nothing restarts its window)."""
    from test_shortcut import spec

    from rubberfriction.driver.sliding.run import run_sliding

    base = dataclasses.replace(spec(0.05, 100.0), h_contact=1.0 / 24, converge_tol=0.01,
                               slide_distance=16.0, steady_state=True)
    off = run_sliding(base)
    on = run_sliding(dataclasses.replace(base, period_extrapolation=True))
    assert on.stats["extrapolated_creep"] == 0.0
    assert on.mu_force == off.mu_force and on.stats["periods"] == off.stats["periods"]


@pytest.mark.slow
def test_extrapolated_creep_reaches_the_steady_state_the_window_rule_misses():
    """The four-scale road's first micro2 cell at 7.21 MPa and 100 mm/s on contact elements twice
    as long as the scene's (``rubberfriction bench periods --coarsen 2 --reference 40
    --factor-reuse 0``, the same code): the block creeps under the friction's mean shear for some
    30 periods.  The steady state is the reference's last period mean (40 periods, no window
    rule; its last five within 0.3 %; 0.27.0: 0.2265, settled from period 32 on.  Up to 0.26.0
    the cell slid at half steps after a cut-back, the step control's clip, and 30 periods
    sufficed).  With the extrapolation the run lands within 3 % of it (0.27.0: +0.9 %, the run
    without it +2.7 %), and closer than the window rule alone, which can stop on a plateau of
    the creep (measured: 18 % above it, docs/performance.md).  With a factorisation at every
    Newton iteration, as measured there: after its ninth period this coarse cell's path forks on
    any perturbation of the linear solves (MUMPS, or the reused factorisations, each take another
    path that does not settle within 40 periods; docs/performance.md, "Why 1e-10"), so the
    reference is the LU path."""
    from rubberfriction.driver.bench.periods import compare, micro2_spec

    rows = compare(micro2_spec(7.21, 100.0, coarsen=2.0), reference_periods=40,
                   factor_reuse=0)
    ref = rows["reference"]
    tail = ref["period_mu"][-5:]
    assert ref["status"] == "ok" and (max(tail) - min(tail)) <= 0.003 * tail[-1]
    steady = ref["mu_force"]
    ex, plain = rows["extrapolated"], rows["not extrapolated"]
    assert ex["status"] == plain["status"] == "ok"
    assert ex["extrapolated_creep"] >= 1
    assert abs(ex["mu_force"] / steady - 1) <= 0.03
    assert abs(ex["mu_force"] - steady) < abs(plain["mu_force"] - steady)
