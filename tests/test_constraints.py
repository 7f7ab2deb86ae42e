"""Dof constraints: tie groups and the prolongation P, checked against hand-built cases."""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec, tie_groups


def test_tie_groups_are_named_by_their_smallest_dof() -> None:
    # 5 - 3 - 7 is one chain, 1 - 2 another, the rest stand alone
    roots = tie_groups(8, [(5, 3), (3, 7), (2, 1)])
    assert roots.tolist() == [0, 1, 1, 3, 4, 3, 6, 3]
    assert tie_groups(3, []).tolist() == [0, 1, 2]


def test_prolongation_of_ties_and_a_prescribed_group() -> None:
    spec = ConstraintSpec(6)
    spec.tie([4, 1, 5])  # one unknown for 1, 4, 5
    spec.equal([2], [3])  # periodic pair
    spec.fix(3, 0.25)  # prescribes the whole group {2, 3}
    cmap = ConstraintMap(spec)
    assert cmap.n_red == 2  # unknowns: {0}, {1, 4, 5}
    P = cmap.P.convert("dense").getDenseArray()
    expected = np.zeros((6, 2))
    expected[0, 0] = 1.0
    expected[[1, 4, 5], 1] = 1.0
    np.testing.assert_array_equal(P, expected)
    dofs, vals = cmap.prescribed_dofs()
    assert dofs.tolist() == [2, 3] and vals.tolist() == [0.25, 0.25]


def test_conflicting_prescriptions_in_one_group_are_refused() -> None:
    spec = ConstraintSpec(3)
    spec.equal([0], [1])
    spec.fix(0, 0.0)
    spec.fix(1, 1.0)
    with pytest.raises(ValueError, match="prescribed"):
        ConstraintMap(spec)
