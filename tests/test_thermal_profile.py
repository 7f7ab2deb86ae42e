"""The macro temperature profile for the lower scales: eq. (8.1) and the partitions of 8.3.3.

Checked on constructed fields where the answers are exact: the mean and standard deviation over
the active columns, partition values equal to the mean of the profile at their bounds (for a
linear profile that is the exact partition mean), bounds on the macro levels, and the FE heat
block's grid read-out (block_grid) against the nodal field it comes from.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.thermal.profile import average_profile, partition_profile

Z = np.array([0.0, 0.01, 0.022, 0.0364, 0.0537, 0.0744, 0.0993, 0.129])  # graded, ratio 1.2


def field(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    return 293.15 + (40.0 + 10.0 * np.sin(x))[:, None] * np.exp(-z / 0.03)[None, :]


def test_profile_is_the_mean_over_active_columns_with_its_std():
    x = np.linspace(0.0, 20.0, 41)
    active = (x > 3.0) & (x < 17.0)
    T = field(x, Z)
    T[~active] += 500.0  # columns out of contact must not enter
    prof = average_profile(Z, T, active)
    cols = field(x[active], Z)
    assert prof.n_active == active.sum()
    np.testing.assert_allclose(prof.mean, cols.mean(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(prof.std, np.sqrt(((cols - cols.mean(axis=0)) ** 2).mean(axis=0)),
                               atol=1e-12)
    with pytest.raises(ValueError, match="no active contact node"):
        average_profile(Z, T, np.zeros_like(active))


def test_partitions_average_their_bound_values_on_macro_levels():
    """Linear profile T = 330 - 400 z: each partition value is the exact mean over it."""
    T = np.tile(330.0 - 400.0 * Z, (3, 1))
    prof = average_profile(Z, T, np.ones(3, bool))
    for n_p in (1, 2, 3, 5):
        part = partition_profile(prof, n_p, depth=0.09)
        assert len(part.layers) == n_p
        assert set(np.round(part.bounds, 12)) <= set(np.round(Z, 12))  # macro levels only
        # last level <= 0.09
        assert part.bounds[0] == 0.0 and part.bounds[-1] == pytest.approx(0.0744)
        top = np.concatenate([[0.0], np.cumsum([d for d, _ in part.layers])])
        for (d, t), a, b in zip(part.layers, top[:-1], top[1:]):
            assert d == pytest.approx(b - a)
            assert t == pytest.approx(330.0 - 400.0 * 0.5 * (a + b), abs=1e-10)
        assert part.background == pytest.approx(330.0 - 400.0 * 0.0744)
    assert partition_profile(prof, 2, 0.09, background=293.15).background == 293.15
    with pytest.raises(ValueError, match="only 5 element rows"):
        partition_profile(prof, 6, depth=0.09)
    with pytest.raises(ValueError, match="n_p"):
        partition_profile(prof, 0, depth=0.09)


def test_block_grid_of_the_heat_model_reads_the_nodal_field():
    """TwoBodyHeat.block_grid returns T(x_k, z_j) of the block's nodes: set T = f(x, z) on the
    dofs and read it back on the grid exactly."""
    from rubberfriction.driver.thermal.conduction import HeatGeometry, TwoBodyHeat
    from rubberfriction.forms.material_files import load_compound, load_road

    geo = HeatGeometry(block_length=4.0, block_height=2.0, road_depth=2.0, road_ahead=1.0,
                       road_behind=1.0, h_x=0.5, first_layer=0.05)
    heat = TwoBodyHeat(geo, load_compound("m3").thermal, load_road("r1").thermal, T0=293.15)
    X = heat.X
    heat.T.x.array[:] = 300.0 + X[:, 0] + 10.0 * X[:, 1] ** 2
    x, z, T = heat.block_grid()
    assert x[0] == pytest.approx(0.0, abs=1e-12) and x[-1] == pytest.approx(4.0)
    assert z[0] == pytest.approx(0.0, abs=1e-12) and z[-1] == pytest.approx(2.0)
    np.testing.assert_allclose(T, 300.0 + x[:, None] + 10.0 * z[None, :] ** 2, atol=1e-12)
