"""The macro temperature profile for the lower scales: eq. (8.1) and the partitions of 8.3.3.

Checked on constructed fields where the answers are exact: the mean and standard deviation over
the active columns, partition values equal to the exact mean of the macro field over them, bounds
on the macro levels, every lower-scale block's partitions down to its own height against the
closed form of steady conduction, the hot layer unchanged, and the FE heat block's grid read-out
(block_grid) against the nodal field it comes from.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.thermal.profile import (
    average_profile,
    partition_profile,
    uniform_partitions,
)

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


# --- the macro field over a lower-scale block's height (issue: partitions only to 0.074 mm) -----

T_S, T_TOP = 353.15, 293.15  # contact face and the macro block's top (held at T0), K
H_MACRO = 2.0  # the macro block's height, mm


def conduction_profile():
    """Steady 1D conduction through the macro block: T linear from T_S at the face to T_TOP at
    its top, on a graded column of levels (first 0.01 mm, ratio 1.2 where it fits)."""
    from rubberfriction.driver.thermal.conduction import block_levels

    z = block_levels(H_MACRO, 0.01, 1.2)
    T = T_S + (T_TOP - T_S) * z / H_MACRO
    return average_profile(z, np.tile(T, (2, 1)), np.ones(2, bool))


def exact_mean(a: float, b: float) -> float:
    """Closed form: the mean over [a, b] of the linear profile, T_TOP beyond the macro block."""
    def integral(z):  # of T from 0 to z
        zz = min(z, H_MACRO)
        return T_S * zz + 0.5 * (T_TOP - T_S) * zz ** 2 / H_MACRO + T_TOP * max(z - H_MACRO, 0.0)
    return (integral(b) - integral(a)) / (b - a)


@pytest.mark.parametrize("height", [0.05, 0.3, 1.0, 2.0, 3.7, 20.0])
def test_each_block_takes_the_macro_field_over_its_own_height(height: float):
    """Every partition of a block of ``height`` -- the thesis' n_p = 4 down to d (the deepest
    macro level within 0.09 mm) and those below them down to the block's top -- is at the exact
    mean of the conduction profile over its depth range (1e-12 K); the layers cover the block;
    the deepest is at the profile's mean there, not the value at d; at most
    n_p + ceil(log2(height / d)) regions."""
    prof = conduction_profile()
    part = partition_profile(prof, 4, depth=0.09)
    d = float(part.bounds[-1])
    assert 0.06 < d <= 0.09
    layers, background = part.block(height)
    edges = np.concatenate([[0.0], np.cumsum([t for t, _ in layers])])
    for (_, T), a, b in zip(layers, edges[:-1], edges[1:]):
        assert T == pytest.approx(exact_mean(a, b), abs=1e-12)
    if height <= d:  # a block inside the partitions: the thesis' partitions as they are
        assert layers == part.layers and background == part.background
        return
    assert edges[-1] == pytest.approx(height, rel=1e-12)
    assert len(layers) <= 4 + int(np.ceil(np.log2(height / d)))
    deepest = layers[-1][1]
    assert deepest == pytest.approx(exact_mean(edges[-2], height), abs=1e-12)
    # cooler than the field at d, which the whole block below d took before
    assert deepest < float(np.interp(d, prof.z, prof.mean)) - 0.25 * (T_S - T_TOP) * d / H_MACRO
    at_top = T_S + (T_TOP - T_S) * min(height, H_MACRO) / H_MACRO  # the field at the block's top
    assert background == pytest.approx(at_top, abs=1e-12)
    # the bounds depend on the height alone: the isothermal cascade meshes the block alike
    flat, _ = uniform_partitions(prof.z, 4, 0.09, T_TOP).block(height)
    assert [t for t, _ in flat] == [t for t, _ in layers]
    assert all(T == T_TOP for _, T in flat)


def test_the_deep_partitions_double_down_to_the_block():
    """The stated rule: below d the thicknesses double (d, 2d, 4d, ...); a last layer thinner
    than half the one below joins it."""
    part = partition_profile(conduction_profile(), 4, depth=0.09)
    d = float(part.bounds[-1])
    layers, _ = part.block(16.5 * d)  # bounds d, 2d, 4d, 8d, 16d: [16d, 16.5d] joins [8d, 16d]
    np.testing.assert_allclose([t for t, _ in layers[4:]], [d, 2 * d, 4 * d, 8.5 * d], rtol=1e-12)
    layers, _ = part.block(20.0 * d)  # [16d, 20d] is half of 8d: kept
    np.testing.assert_allclose([t for t, _ in layers[4:]], [d, 2 * d, 4 * d, 8 * d, 4 * d],
                               rtol=1e-12)


def test_a_partition_over_several_macro_elements_takes_the_fields_mean():
    """A kinked profile (linear to z = 0.0364, then flat): the partition [0.022, 0.0537] spans two
    macro elements; its value is the field's exact mean there, not the mean of its bounds."""
    T = np.where(Z < 0.0364, 330.0 - 400.0 * Z, 330.0 - 400.0 * 0.0364)
    prof = average_profile(Z, np.tile(T, (2, 1)), np.ones(2, bool))
    part = partition_profile(prof, 4, depth=0.09)
    np.testing.assert_allclose(part.bounds, [0.0, 0.01, 0.022, 0.0537, 0.0744])
    a, k, b = 0.022, 0.0364, 0.0537
    flat = 330.0 - 400.0 * k
    exact = (0.5 * (330.0 - 400.0 * a + flat) * (k - a) + flat * (b - k)) / (b - a)
    assert part.layers[2][1] == pytest.approx(exact, abs=1e-12)
    assert abs(exact - 0.5 * (T[2] + T[4])) > 0.3  # the bounds' mean would differ


def test_the_hot_layer_setup_is_the_same_on_every_block():
    """Hot-layer mode (thesis 8.5.3, fig. 8.17 b): 5 um at T_S, down to 20 um at (T_S + T0) / 2,
    T0 above, on every lower-scale block whatever its height."""
    from rubberfriction.driver.multiscale.thermal_loop import (HotLayerSettings,
                                                               hot_layer_partitions)

    part = hot_layer_partitions(T_S, T_TOP, HotLayerSettings())
    expected = ((0.005, T_S), (0.015, 0.5 * (T_S + T_TOP)))
    assert part.profile is None
    for height in (0.01, 0.3, 3.0, 20.0):
        layers, background = part.block(height)
        assert len(layers) == 2 and background == T_TOP
        for (t, T), (t_e, T_e) in zip(layers, expected):
            assert t == pytest.approx(t_e, rel=1e-12) and T == T_e
