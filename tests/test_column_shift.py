"""The "column" Newton start of sliding sub-steps (`driver.sliding.steps.ColumnShift`).

Steady sliding of a periodic cell is a travelling wave, u(X, t) = U(X + v t) in the block frame,
and on the structured block (equal x-columns at every height) a move by whole columns is a
permutation of nodes and cells.  Pinned here exactly (to round-off): a state that is a periodic
function of X, moved by k columns, equals the function at X + k h at every node (both periodic
images of the seam included) and every cell centroid; moves compose (k = 1 three times is
k = 3) and L / h columns give the state back.  The start itself is only compared by its
residual with the others, so its effect on a run is measured, not pinned (docs/performance.md).
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.sliding.steps import column_shift
from rubberfriction.forms.compound import Compound, MooneyRivlin
from rubberfriction.meshes.block import rubber_block

L, H, N = 1.2, 0.6, 12


def elastic_m1() -> Compound:
    return Compound(name="m1-elastic", hyperelastic=MooneyRivlin(0.174, 0.3, 0.0208),
                    prony=None, wlf=None, thermal=None, description="test",
                    source="thesis table C.2")


def solid(element: str) -> SolidProblem:
    body = rubber_block(L, H, nx_contact=N, grading=1.3)
    return SolidProblem(body.mesh, body.facet_tags, elastic_m1(), SolidSettings(element=element))


def wave(X: np.ndarray, c: int) -> np.ndarray:
    """A periodic field in x (period L) that varies with z too, per component c."""
    return np.sin(2 * np.pi * X[:, 0] / L + c) * (1.0 + X[:, 1]) + 0.1 * c * X[:, 1]


@pytest.mark.parametrize("element", ["Q1P0", "Q1"])
def test_a_move_by_whole_columns_is_the_field_at_x_plus_k_h(element):
    sp = solid(element)
    shift = column_shift(sp, L)
    assert shift is not None and shift.h == pytest.approx(L / N, rel=1e-12)
    x = np.zeros_like(sp.w.x.array)
    X, d = sp.node_X, sp.displacement_dofs()
    for c in (0, 1):
        x[d[:, c]] = wave(X, c)
    if shift.cell_dofs is not None:
        x[shift.cell_dofs] = wave(sp.cell_centroids(), 2)
    for k in (1, 2, 5):
        moved = shift(x, k)
        Xk = X + [k * shift.h, 0.0]
        for c in (0, 1):
            assert np.abs(moved[d[:, c]] - wave(Xk, c)).max() < 1e-12
        if shift.cell_dofs is not None:
            centroids = sp.cell_centroids() + [k * shift.h, 0.0]
            assert np.abs(moved[shift.cell_dofs] - wave(centroids, 2)).max() < 1e-12
    assert np.array_equal(shift(shift(shift(x, 1), 1), 1), shift(x, 3))
    # a whole period: the field again (the seam's two images swap values, equal to round-off)
    assert np.abs(shift(x, N) - x).max() < 1e-12


def test_no_shift_for_a_block_without_equal_columns():
    body = rubber_block(L, H, nx_contact=N, grading=1.3, leading_edge_radius=0.3)
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_m1(), SolidSettings())
    assert column_shift(sp, L) is None


def test_the_residual_and_tangent_of_the_moved_state_are_moved():
    """The discrete symmetry the column start rests on: on a periodic sliding cell with its
    constraints (periodic images, the tied top row) and the mortar contact, the state moved by
    k columns against the road moved by k columns has the reduced residual S r and tangent
    S A S^T, (S r)[i] = r[pi[i]] with pi the move on the reduced unknowns, to round-off (1e-9 of
    the largest entry), except on the contact face within two columns of the seam in either
    frame: the seam's two nodes are the contact chain's ends, whose frame is the road's normal
    (cpp_contact/README.md).  (A tangent moved so was tried as the preconditioner of later
    tangents, docs/performance.md, "The column start": it saved 5 % of the factorisations.)"""
    from scipy.sparse import csr_matrix

    from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, sliding_contact
    from rubberfriction.driver.sliding.spec import SlidingSpec
    from rubberfriction.forms.material_files import load_compound

    x = np.linspace(0.0, 1.0, 129)[:-1]
    spec = SlidingSpec(surface_x=x, surface_h=0.02 * np.cos(2 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=load_compound("tread_default"),
                       h_contact=1.0 / 16)
    run = SlidingRun(spec, block_mesh, sliding_contact)
    run.build("mortar")
    m = run.model
    shift = column_shift(m.sp, m.L)
    assert shift is not None and shift.h == pytest.approx(1.0 / 16, rel=1e-12)
    X, d = m.sp.node_X, m.sp.displacement_dofs()
    z = (X[:, 1] - X[:, 1].min()) / (X[:, 1].max() - X[:, 1].min())
    state = np.zeros_like(m.sp.w.x.array)
    state[d[:, 0]] = 1e-3 * np.sin(2 * np.pi * X[:, 0] + 0.4) * (1.0 - z)
    state[d[:, 1]] = -0.03 * (1.0 - z) * (1.0 + 0.3 * np.cos(2 * np.pi * X[:, 0]))
    k, o0 = 3, 0.13

    def system(x_state: np.ndarray, o: float) -> tuple[np.ndarray, np.ndarray]:
        m.contact.set_master_offset(o, 0.0)
        m.sp.w.x.array[:] = x_state
        m.problem.constraints.set_prescribed(m.sp.w.x.array)
        m.problem.assemble()
        indptr, cols, vals = m.problem.Ar.getValuesCSR()
        n = m.problem.Ar.getSize()[0]
        return m.problem.br.array.copy(), csr_matrix((vals, cols, indptr), shape=(n, n)).toarray()

    r0, A0 = system(state, o0)
    assert m.contact.state()["n_active"] > 0  # the contact is in the symmetry too
    r1, A1 = system(shift(state, k), o0 - k * shift.h)
    # the move on the reduced unknowns: every dof of a tied group moves to the same group
    red = m.problem.constraints.red_of_full
    perm = shift(np.arange(red.size, dtype=float), k).astype(np.int64)  # (S x)[f] = x[perm[f]]
    free = red >= 0
    pi = np.full(red.max() + 1, -1, dtype=np.int64)
    pi[red[free]] = red[perm[free]]
    assert sorted(pi) == list(range(pi.size))
    assert np.array_equal(pi[red[free][::-1]], red[perm[free]][::-1])
    # the reduced unknowns of contact-face nodes within two columns of either frame's seam
    face = np.isclose(X[:, 1], X[:, 1].min())
    near = np.zeros(pi.size, dtype=bool)
    for seam in (0.0, -k * shift.h):
        gap = np.abs((X[:, 0] - seam + 0.5) % 1.0 - 0.5)  # periodic distance, L = 1
        dofs = red[d[np.nonzero(face & (gap < 2.5 * shift.h))[0]].ravel()]
        near[dofs[dofs >= 0]] = True
    assert near.sum() <= 2 * 5 * 2
    far = ~near
    assert np.abs(r1 - r0[pi])[far].max() <= 1e-9 * np.abs(r0).max()
    assert np.abs(r1 - r0[pi])[near].max() > 1e-6 * np.abs(r0).max()  # the seam does differ
    assert np.abs(A1 - A0[np.ix_(pi, pi)])[far].max() <= 1e-9 * np.abs(A0).max()
