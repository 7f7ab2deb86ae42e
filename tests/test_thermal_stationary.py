"""The thermal loop's point mu (thesis 8.5.3): the time average of the macro mu over the stationary
part of the slide (``window.stationary_mean``), and the loop modes' macro block on the rough macro
band (``[thermal] road_surface = "macro"``, thesis figs. 8.2, 8.17 a).  No FE run here."""

from __future__ import annotations

import dataclasses
import math
import re
from importlib import resources

import numpy as np
import pytest

from rubberfriction.driver.multiscale.thermal_loop_scene import (
    hot_layer_settings,
    loop_settings,
)
from rubberfriction.driver.scenes import SceneError, load_scene, parse_scene
from rubberfriction.driver.scenes.rough import SCENES_PACKAGE
from rubberfriction.driver.sliding.window import stationary_mean

S = 0.05 * np.arange(1, 201)  # 200 steps of 0.05 mm: a 10 mm slide, 10 blocks of 1 mm


def test_plateau_after_a_transient_is_averaged_exactly():
    """mu(s) = 0.8 - 0.05 (3 - s)^2 up to s = 3 mm, then 0.8: the last block agrees with the one
    before (and each half with its twin): the window is the last 1 mm block, its mean the plateau
    itself, its drift 0."""
    mu = np.where(S < 3.0, 0.8 - 0.05 * (3.0 - S) ** 2, 0.8)
    avg = stationary_mean(S, mu, blocks=10, tol=0.01)
    assert avg.stationary and avg.blocks == 1
    assert (avg.lo, avg.hi) == pytest.approx((9.0, 10.0), rel=1e-12)
    assert avg.mean == pytest.approx(0.8, rel=1e-14) and avg.drift == pytest.approx(0.0, abs=1e-14)
    assert "stationary" in avg.describe() and "NOT" not in avg.describe()


def test_a_linear_drift_is_refused_and_said_so():
    """mu = 1 + 0.05 s (5 % per block, beyond the 1 % tolerance for every window): no window
    passes; the mean is that of the last half, the distance-weighted mean of the step values
    over (5, 10] mm, 1 + 0.05 * 7.525 (the steps end at 5.05 ... 10), and it is marked."""
    avg = stationary_mean(S, 1.0 + 0.05 * S, blocks=10, tol=0.01)
    assert not avg.stationary and avg.blocks == 5
    assert (avg.lo, avg.hi) == pytest.approx((5.0, 10.0), rel=1e-12)
    assert avg.mean == pytest.approx(1.0 + 0.05 * 7.525, rel=1e-13)
    # second half (7.5, 10] minus first half (5, 7.5], over the mean: 0.05 * 2.5 / mean
    assert avg.drift == pytest.approx(0.125 / avg.mean, rel=1e-12)
    assert "NOT stationary" in avg.describe()
    # the same trend within the tolerance (0.5 % per block) passes with the last block
    small = stationary_mean(S, 10.0 + 0.05 * S, blocks=10, tol=0.01)
    assert small.stationary and small.blocks == 1


def test_too_few_blocks_or_no_values_are_never_stationary():
    two = stationary_mean(S, np.full(S.shape, 0.5), blocks=2)
    assert not two.stationary and two.mean == pytest.approx(0.5, rel=1e-14) and two.lo == 5.0
    none = stationary_mean(S, np.full(S.shape, math.nan))
    assert not none.stationary and math.isnan(none.mean)


def _rough_text() -> str:
    return (resources.files(SCENES_PACKAGE) / "thermal_road_hot_layer_rough.toml").read_text()


def test_the_rough_hot_layer_scene_differs_only_in_its_road():
    hot, rough = load_scene("thermal_road_hot_layer"), load_scene("thermal_road_hot_layer_rough")
    assert hot.thermal.road_surface == "flat" and rough.thermal.road_surface == "macro"
    assert dataclasses.replace(rough.thermal, road_surface="flat") == hot.thermal
    assert (rough.surface, rough.samples, rough.conditions, rough.numerics, rough.physics) == \
        (hot.surface, hot.samples, hot.conditions, hot.numerics, hot.physics)
    assert hot_layer_settings(rough).rough and not hot_layer_settings(hot).rough
    assert loop_settings(rough).rough and loop_settings(rough).blocks == 10


@pytest.mark.parametrize("line, key", [('road_surface = "bumpy"', "road_surface"),
                                       ("stationary_blocks = 0", "stationary_blocks"),
                                       ("stationary_tol = 0.0", "stationary_tol")])
def test_bad_road_or_window_keys_are_named(line: str, key: str):
    text = _rough_text().replace('road_surface = "macro"', line)
    with pytest.raises(SceneError, match=re.escape(key)):
        parse_scene(text, "t.toml")


def test_the_loop_slides_on_the_given_modes_road():
    """The loop modes build their macro run with the given mode's code (``macro_inputs``): the
    rough hot-layer scene and the same scene in the given mode get the same road profile."""
    from rubberfriction.driver.multiscale.thermal_scene import _materials, _T0, macro_inputs

    text = _rough_text()
    given = re.sub(r'mode = "hot-layer"\n', 'mode = "given"\nmu = 0.5\n', text)
    given = re.sub(r"\nhot_layer_rises = .*\n", "\n", given).replace(
        "[physics]\nhysteresis = true\n", "[physics]\n")
    specs = []
    for t in (text, given):
        scene = parse_scene(t, "t.toml")
        (name, comp), *_ = _materials(scene)[0]
        road = _materials(scene)[1]
        spec, _ = macro_inputs(scene, comp, road, 0.3, 1000.0, _T0(scene, comp), 0.5)
        specs.append(spec)
    assert load_scene("thermal_road_hot_layer_rough").thermal.mode == "hot-layer"
    loop, ref = specs
    assert loop.surface_x.size > 100 and np.ptp(loop.surface_h) > 0.1  # the macro band, mm
    np.testing.assert_array_equal(loop.surface_x, ref.surface_x)
    np.testing.assert_array_equal(loop.surface_h, ref.surface_h)
