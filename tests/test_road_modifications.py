"""Road modifications of a scene's [surface]: ``height_scale`` (a rougher road, thesis 6.5.2) and
``polish_fraction`` / ``polish_scales`` (truncated asperity tips, thesis 6.5.3).

Closed form of the polishing level: for h = A sin(2 pi x / L) over one period the fraction of
points above a level c (|c| < A) is the fraction of the phase where sin > c / A, which is
(pi - 2 arcsin(c / A)) / (2 pi) = arccos(c / A) / pi; truncating a fraction f therefore cuts at
c = A cos(pi f).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from rubberfriction.driver.multiscale.results import Point
from rubberfriction.driver.multiscale.scales import build_scales
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
from rubberfriction.driver.runtime.store import run_key
from rubberfriction.driver.scenes import SCHEMA, SceneError, parse_scene, schema_text, with_surface
from rubberfriction.driver.surfaces import SurfaceError, polish_sample, truncate_tips

FOUR = 'source = "four_scale"\nedges = [20.0, 3.0, 0.3, 0.04, 0.003]\n'
SINES = 'source = "sines"\namplitudes = [0.02, 0.002]\nwavelengths = [2.0, 0.2]\n'


def scene(surface: str, extra: str = "") -> Any:
    text = 'name = "t"\n[surface]\n' + surface + textwrap.dedent(extra)
    return parse_scene(text, "t.toml", Path("."))


def error_of(surface: str) -> str:
    with pytest.raises(SceneError) as exc:
        scene(surface)
    return str(exc.value)


def closed_random(m: int, seed: int) -> np.ndarray:
    """m distinct random heights plus the closing vertex h[m] = h[0]."""
    y = np.random.default_rng(seed).normal(size=m)
    return np.append(y, y[0])


@pytest.mark.parametrize("f", [0.01, 0.2, 0.5, 0.9])
@pytest.mark.parametrize("m", [101, 1000])
def test_truncate_tips_cuts_a_fraction_f_flat_and_leaves_the_rest(f: float, m: int) -> None:
    h = closed_random(m, seed=m)
    out = truncate_tips(h, f)
    level = out.max()
    plateau = np.count_nonzero(out[:-1] == level)
    assert abs(plateau - f * m) <= 1.0  # within one grid point
    below = h < level
    assert np.array_equal(out[below], h[below])  # below the level: untouched, bit for bit
    assert np.all(out[~below] == level)
    assert out[-1] == out[0]  # still one closed period
    assert np.all(out <= h)


def test_truncate_tips_zero_is_the_identity_and_fractions_are_checked() -> None:
    h = closed_random(64, seed=3)
    out = truncate_tips(h, 0.0)
    assert np.array_equal(out, h) and out is not h
    for bad in (1.0, -0.1, 1.5):
        with pytest.raises(SurfaceError, match="fraction"):
            truncate_tips(h, bad)


@pytest.mark.parametrize("f", [0.1, 0.25, 0.5, 0.8])
def test_truncation_level_of_a_sine_is_a_cos_pi_f(f: float) -> None:
    """Module docstring: c = A cos(pi f).  On m points the fraction above c is the continuous one
    to within 2 / m (two crossings), so c is within A pi (1/m + 2/m) of the closed form."""
    A, m = 0.7, 200_000
    x = np.linspace(0.0, 1.0, m + 1)
    h = A * np.sin(2.0 * np.pi * x)
    h[-1] = h[0]
    level = truncate_tips(h, f).max()
    assert level == pytest.approx(A * math.cos(math.pi * f), abs=3.0 * A * math.pi / m)


def test_polish_sample_recomputes_the_sample_statistics() -> None:
    sample = build_scales(scene(SINES), 1).sets[1].samples[0]  # a frozen PeriodicSample
    road = build_scales(scene(FOUR + "cutoff = 0.003\n"), 1).sets[3].samples[0]  # SurfaceSample
    for s in (sample, road):
        p = polish_sample(s, 0.3)
        assert np.array_equal(p.h, truncate_tips(s.h, 0.3)) and np.array_equal(p.x, s.x)
        assert p.rms_height == pytest.approx(float(np.std(p.h[:-1])), rel=1e-12)
        slope = np.sqrt(np.mean((np.diff(p.h) / np.diff(p.x)) ** 2))
        assert p.rms_slope == pytest.approx(float(slope), rel=1e-9)
        assert p.rms_height < s.rms_height
        assert polish_sample(s, 0.0) is s
    assert polish_sample(road, 0.3).meta["polish_fraction"] == 0.3
    assert "polish_fraction" not in road.meta


def test_height_scale_multiplies_band_heights_and_slopes_exactly() -> None:
    """four_scale with a stated wavelength cut-off: the same bands, every rms height and slope
    (the cut-off report's too) times the factor; the samples too (their positions follow the
    carrier's top fraction and the closure its slopes, both unchanged by a positive factor)."""
    k = 2.5
    one = scene(FOUR + "cutoff = 0.003\n")
    big = scene(FOUR + f"cutoff = 0.003\nheight_scale = {k}\n")
    assert big.surface.edges == one.surface.edges == (20.0, 3.0, 0.3, 0.04, 0.003)
    for r1, rk in zip(one.surface.cutoff_report.rows, big.surface.cutoff_report.rows):
        assert rk.rms_slope == pytest.approx(k * r1.rms_slope, rel=1e-9)
        assert rk.cumulative_slope == pytest.approx(k * r1.cumulative_slope, rel=1e-9)
    s1, sk = build_scales(one, 2), build_scales(big, 2)
    for b1, bk in zip(s1.provenance["scales"], sk.provenance["scales"]):
        assert bk["rms_height_mm"] == pytest.approx(k * b1["rms_height_mm"], rel=1e-9)
        assert bk["rms_slope"] == pytest.approx(k * b1["rms_slope"], rel=1e-9)
    for a, b in zip(s1.sets, sk.sets):
        for p, q in zip(a.samples, b.samples):
            assert q.start == p.start
            np.testing.assert_allclose(q.h, k * p.h, rtol=1e-9, atol=1e-12 * k * np.ptp(p.h))
    assert (s1.provenance["height_scale"], sk.provenance["height_scale"]) == (1.0, k)
    # the slope rule sees the steeper bands: it stops sooner, at max_slope
    rule = scene(FOUR + f"height_scale = {k}\n").surface
    assert rule.edges[-1] > 0.04 and len(rule.edges) < 6
    assert rule.cutoff_report.cumulative_slope <= 1.3 * (1 + 1e-6)
    assert "dropped" in [r.status for r in rule.cutoff_report.rows]
    # sines: the amplitudes
    a, b = build_scales(scene(SINES), 1), build_scales(scene(SINES + "height_scale = 3.0\n"), 1)
    for sa, sb in zip(a.sets, b.sets):
        np.testing.assert_allclose(sb.samples[0].h, 3.0 * sa.samples[0].h, rtol=0, atol=1e-15)
    np.testing.assert_allclose(b.full_sample.h, 3.0 * a.full_sample.h, rtol=0, atol=1e-15)


def test_polished_scales_default_to_the_micro_scales_and_enter_the_store_key() -> None:
    f = 0.2
    plain = scene(FOUR + "cutoff = 0.003\n")
    polished = scene(FOUR + f"cutoff = 0.003\npolish_fraction = {f}\n")
    assert polished.surface.polished == ("micro1", "micro2") and plain.surface.polished == ()
    a, b = build_scales(plain, 1), build_scales(polished, 1)
    assert b.provenance["polish"] == {"fraction": f, "scales": ["micro1", "micro2"]}
    assert a.provenance["polish"] == {"fraction": 0.0, "scales": []}
    make = SpecBuilder(plain, load_compounds(plain))
    pt = Point(plain.conditions.compounds[0], 0.3, 10.0)
    for i, (sa, sb) in enumerate(zip(a.sets, b.sets)):
        p, q = sa.samples[0], sb.samples[0]
        ka, kb = (run_key(make(pt, i, s, 0.3, None, "up")) for s in (p, q))
        if sa.name in ("macro", "meso"):
            assert np.array_equal(p.h, q.h) and ka == kb  # untouched: the same runs
        else:
            assert np.array_equal(q.h, truncate_tips(p.h, f)) and ka != kb
    named = build_scales(scene(FOUR + "cutoff = 0.003\npolish_fraction = 0.2\n"
                                      'polish_scales = ["meso"]\n'), 1)
    assert [np.array_equal(s.samples[0].h, t.samples[0].h) for s, t in zip(a.sets, named.sets)
            ] == [True, False, True, True]
    # a rougher road's samples get other keys too
    big = build_scales(scene(FOUR + "cutoff = 0.003\nheight_scale = 1.5\n"), 1)
    assert run_key(make(pt, 0, big.sets[0].samples[0], 0.3, None, "up")) != run_key(
        make(pt, 0, a.sets[0].samples[0], 0.3, None, "up"))


def test_bad_polish_and_height_settings_name_the_key() -> None:
    err = error_of(FOUR + 'cutoff = 0.003\npolish_fraction = 0.1\npolish_scales = ["micro3"]\n')
    assert "[surface].polish_scales[0] = 'micro3'" in err and "micro1" in err
    # the default road keeps macro and meso under the slope rule: micro1 was dropped
    err = error_of('source = "default_road"\npolish_fraction = 0.1\npolish_scales = ["micro1"]\n')
    assert "polish_scales[0]" in err and "dropped" in err
    err = error_of(FOUR + "polish_fraction = 1.0\n")
    assert "[surface].polish_fraction" in err and "< 1" in err
    assert "[surface].height_scale" in error_of(FOUR + "height_scale = 0.0\n")
    assert "polish_scales" in error_of(FOUR + 'cutoff = 0.003\npolish_scales = ["meso", "meso"]\n')
    with pytest.raises(SceneError, match="polish_scales"):
        with_surface(scene(SINES), polish_fraction=0.5, polish_scales=("micro2",))
    # settings that do nothing say so
    assert any("polishes no scale" in w for w in scene(SINES + "polish_fraction = 0.1\n").warnings)
    assert any("polish_scales is ignored" in w
               for w in scene(SINES + 'polish_scales = ["micro"]\n').warnings)


def test_scene_round_trip_of_the_road_keys() -> None:
    """The keys as written come back from the reader, with_surface gives the same surface, the
    scene's own text reads back to it, and the schema lists them with their defaults."""
    text = 'height_scale = 1.5\npolish_fraction = 0.25\npolish_scales = ["micro2", "micro1"]\n'
    s = scene(FOUR + "cutoff = 0.003\n" + text)
    sf = s.surface
    assert sf.height_scale == 1.5 and sf.polish_fraction == 0.25
    assert sf.polish_scales == ("micro2", "micro1")
    assert sf.polished == ("micro2", "micro1")
    again = parse_scene(s.text, "t.toml", Path("."))
    assert again.surface == sf
    via = with_surface(scene(FOUR + "cutoff = 0.003\n"), height_scale=1.5, polish_fraction=0.25,
                       polish_scales=("micro2", "micro1"))
    assert via.surface == sf
    plain = scene(FOUR).surface
    assert (plain.height_scale, plain.polish_fraction, plain.polish_scales) == (1.0, 0.0, ())
    keys = SCHEMA["surface"]
    assert (keys["height_scale"].unit, keys["polish_fraction"].unit) == ("1", "1")
    listing = schema_text()
    for line in ("height_scale = 1.0  #", "polish_fraction = 0.0  #", "polish_scales = []  #"):
        assert line in listing
