"""The thermal macro block on a rough road: the macro band of the scene's surface
(``[thermal] road_surface = "macro"``) and the road's mechanics (``road_mechanics``), wired from the
scene into the run.  Each test states what it checks and its tolerance."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rubberfriction.driver.scenes import SceneError, parse_scene
from rubberfriction.driver.multiscale.thermal_scene import _materials, macro_inputs
from rubberfriction.driver.thermal.macro import run_thermal_macro

SCENE = """
name = "rough_macro"
[conditions]
compounds = ["tread_default"]
pressures = [0.3]
velocities = [1000.0]
[physics]
thermal = true
[surface]
source = "sines"
wavelengths = [2.0]
amplitudes = [0.05]
[thermal]
mu = 0.3
block_length = 4.0
block_height = 2.0
slide_distance = 2.0
road_depth = 4.0
road_ahead = 1.0
road_behind = 4.0
road_surface = "macro"
road_start = 0.3
"""
T0 = 293.15


def _inputs(text: str = SCENE):
    scene = parse_scene(text, "rough.toml", Path("."))
    [(_, compound)], road = _materials(scene)
    return scene, compound, macro_inputs(scene, compound, road, 0.3, 1000.0, T0, 0.3)


def test_macro_road_is_the_first_band_of_the_surface():
    """Sines: the road under the block is the first sine, h(x) = a sin(2 pi (x + span + start) /
    lambda) with x in the block frame from -span (span = slide + block length), to 1e-12 mm, sampled
    at most h_contact / 2; rigid unless road_mechanics = "elastic" (then E, nu of the road r1)."""
    _, _, (spec, settings) = _inputs()
    x, h = np.asarray(spec.surface_x), np.asarray(spec.surface_h)
    span = 2.0 + 4.0
    np.testing.assert_allclose(h, 0.05 * np.sin(2 * np.pi * (x + span + 0.3) / 2.0), atol=1e-12)
    assert (x[0] == pytest.approx(-span) and x[-1] >= 2 * span - 1e-9
            and np.diff(x).max() <= 0.125 + 1e-12)
    assert settings.road_elastic is None
    _, _, (_, elastic) = _inputs(SCENE + 'road_mechanics = "elastic"\n')
    assert (elastic.road_elastic.E, elastic.road_elastic.nu) == (40000.0, 0.15)


def test_macro_road_of_the_default_road_is_its_macro_band():
    """default_road: the road heights are the 20-3 mm band of the CAPTIF profile from road_start
    on (linear interpolation of the band, 1e-12 mm); a start beyond the band's end is refused."""
    from rubberfriction.driver.surfaces.default_road import default_road

    text = SCENE.replace('source = "sines"\nwavelengths = [2.0]\namplitudes = [0.05]\n',
                         'source = "default_road"\nedges = [20.0, 3.0, 0.3]\n')
    _, _, (spec, _) = _inputs(text)
    band = default_road(edges=(20.0, 3.0, 0.3)).scales[0].profile
    x = np.asarray(spec.surface_x)
    expected = np.interp(band.x[0] + 0.3 + x - x[0], band.x, band.h)
    np.testing.assert_allclose(spec.surface_h, expected, atol=1e-12)
    with pytest.raises(SceneError, match="road_start = 5000 mm"):
        _inputs(text.replace("road_start = 0.3", "road_start = 5000.0"))


def test_coupled_loop_takes_the_rough_macro_road():
    """A coupled thermal loop on the macro band (thesis 8.5.3): the scene is accepted and the loop
    and hot-layer settings run the macro block on the rough road (its F_x / F_z is the point's
    mu, see thermal_loop's module doc); the flat road stays the default."""
    from rubberfriction.driver.multiscale.thermal_loop_scene import (hot_layer_settings,
                                                                     loop_settings)

    text = SCENE.replace("mu = 0.3\n", 'mode = "coupled"\n').replace(
        'name = "rough_macro"\n', 'name = "rough_macro"\nvariant = "rough"\n')
    scene = parse_scene(text, "rough.toml", Path("."))
    assert scene.thermal.mode == "coupled"
    assert loop_settings(scene).rough and hot_layer_settings(scene).rough
    flat = parse_scene(text.replace('road_surface = "macro"\n', ""), "flat.toml", Path("."))
    assert not loop_settings(flat).rough


def test_block_on_the_rough_road_heats_and_keeps_the_heat_balance():
    """Real FE (4 x 2 mm block over a 2 mm sine of amplitude 0.05 mm, 1 m/s, mu = 0.3, elastic
    road r1): partial contact (< 60 % of the block), the heat put into block and road is the
    contact's frictional dissipation (1e-10) and, before the heated track reaches the outflow face,
    all of it is stored (1e-5); the macro band's hysteresis adds to the given mu: the mean -F_x/F_z
    of the second half of the slide lies above 0.3 by more than 2 %."""
    _, compound, (spec, settings) = _inputs(SCENE + 'road_mechanics = "elastic"\n')
    res = run_thermal_macro(spec, compound.thermal, settings)
    assert res.ok, (res.sliding.reason, res.stats)
    s = res.series
    contact = np.asarray(res.sliding.series["contact_length"]) / 4.0
    assert contact[-1] < 0.6
    np.testing.assert_allclose(s["friction_energy"], s["contact_dissipation"], rtol=1e-10)
    np.testing.assert_allclose(s["heat_block"][-1] + s["heat_road"][-1], s["friction_energy"][-1],
                               rtol=1e-5)
    assert s["T_contact"][-1] > T0 + 1.0
    assert np.mean(s["mu"][len(s["mu"]) // 2:]) > 1.02 * 0.3
    assert np.all(s["road_sink"] < 0.0)


def test_shipped_rough_thermal_scene_builds_its_macro_road():
    """The shipped scene thermal_rough: an elastic r1 road shaped by the default road's macro band
    (its first 69 mm: rms height 0.46 mm, rough on the block's scale)."""
    from rubberfriction.driver.scenes import load_scene

    scene = load_scene("thermal_rough")
    [(_, compound)], road = _materials(scene)
    spec, settings = macro_inputs(scene, compound, road, 0.3, 1000.0, T0, 0.3)
    assert settings.road_elastic == road
    assert 0.2 < float(np.std(spec.surface_h)) < 2.0
