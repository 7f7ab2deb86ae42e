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


def solid(element: str) -> SolidProblem:
    body = rubber_block(L, H, nx_contact=N, grading=1.3)
    compound = Compound(name="m1-elastic", hyperelastic=MooneyRivlin(0.174, 0.3, 0.0208),
                        prony=None, wlf=None, thermal=None, description="test",
                        source="thesis table C.2")
    return SolidProblem(body.mesh, body.facet_tags, compound, SolidSettings(element=element))


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
    compound = Compound(name="m1-elastic", hyperelastic=MooneyRivlin(0.174, 0.3, 0.0208),
                        prony=None, wlf=None, thermal=None, description="test",
                        source="thesis table C.2")
    sp = SolidProblem(body.mesh, body.facet_tags, compound, SolidSettings())
    assert column_shift(sp, L) is None
