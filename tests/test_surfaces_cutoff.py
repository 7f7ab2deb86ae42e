"""The lowest-scale rule (driver.surfaces.cutoff) and the four-scale road.

Closed form used: a self-affine spectrum C1D(q) = K q^-(1+2H) has the 1D slope mean square
2 int q^2 C1D dq = 2 K (q_b^(2-2H) - q_a^(2-2H)) / (2 - 2H) between q_a and q_b, and an isotropic
surface's 2D mean square slope is twice its 1D one (module docstring of cutoff.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rubberfriction.driver.scenes import SceneError, load_scene, parse_scene
from rubberfriction.driver.surfaces import (
    fit_psd_power_law,
    multiscale_from_measurements,
    psd_1d,
    self_affine_profile,
)
from rubberfriction.driver.surfaces.cutoff import (
    CutoffRule,
    apply_cutoff,
    cumulative_slope_2d,
    parse_cutoff,
)
from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.four_scale import FOUR_SCALE_H, four_scale_road
from rubberfriction.driver.surfaces.multiscale import MultiScaleSurface

H = 0.8
EDGES = (5.0, 0.5, 0.05, 0.005)


def _profile(kind: str, length: float, dx: float, lam_min: float, seed: int):
    """A self-affine profile with exact amplitudes (random phases) whose provenance says kind."""
    p = self_affine_profile(length, dx, H=H, rms_height=0.05, q_rolloff=2 * math.pi / EDGES[0],
                            q_cutoff=2 * math.pi / lam_min, seed=seed, amplitudes="fixed")
    p.meta["provenance"]["kind"] = kind
    return p


def _builder(kinds: tuple[str, str]):
    """Two 'measurements' of one spectrum: a coarse one (dx 5 um) and a fine one (dx 0.5 um)."""
    def build(edges: tuple[float, ...]) -> MultiScaleSurface:
        coarse = _profile(kinds[0], 50.0, 0.005, 0.02, 1)
        fine = _profile(kinds[1], 5.0, 0.0005, min(edges), 2)
        return multiscale_from_measurements([coarse, fine], edges)
    return build


def test_slope_rule_shortens_the_crossing_band_where_the_closed_form_says() -> None:
    build = _builder(("generated", "generated"))
    full = build(EDGES)
    cum = cumulative_slope_2d([s.rms_slope for s in full.scales])
    target = 0.5 * (cum[1] + cum[2])  # inside the third band
    road, rep = apply_cutoff(build, EDGES, CutoffRule("slope", target))
    assert [r.status for r in rep.rows] == ["kept", "kept", "shortened"]
    lam_c = road.edges[-1]
    # the kept road reaches the limit to within the last Fourier mode of the 5 mm record (the
    # cut falls between two modes; each adds about 3e-4 of the slope here)
    assert math.isclose(rep.cumulative_slope, target, rel_tol=1e-3)
    assert rep.cumulative_slope <= target
    # closed form: 2 * 2 K (q_c^(2-2H) - q_0^(2-2H)) / (2 - 2H) = target^2 on the fine profile's
    # spectrum K = C0 q_r^(1+2H); the bands above from the coarse profile are their own closed
    # forms, so compare the third band alone: 4 K (q_c^a - q_1^a) / a = target^2 - cum[1]^2
    q_r = 2 * math.pi / EDGES[0]
    C0 = _profile("generated", 5.0, 0.0005, EDGES[-1], 2).meta["provenance"]["C0_mm3"]
    K = C0 * q_r ** (1 + 2 * H)
    a = 2 - 2 * H
    q1 = 2 * math.pi / EDGES[2]
    qc = ((target**2 - cum[1] ** 2) * a / (4 * K) + q1**a) ** (1 / a)
    # finite differences at dx = 0.5 um lose sinc^2(q dx / 2) >= 0.96 of a mode's slope near
    # 5 um, less at 14 um, and the record has discrete modes: 1 % on the wavelength (0.07 %)
    assert lam_c == pytest.approx(2 * math.pi / qc, rel=0.01)


def test_measured_bands_are_never_cut_and_generated_ones_below_them_are_dropped() -> None:
    build = _builder(("measured", "generated"))
    full = build(EDGES)
    cum = cumulative_slope_2d([s.rms_slope for s in full.scales])
    limit = 0.5 * (cum[0] + cum[1])  # crossed inside the measured meso band
    road, rep = apply_cutoff(build, EDGES, CutoffRule("slope", limit))
    assert [r.kind for r in rep.rows] == ["measured", "measured", "generated"]
    assert [r.status for r in rep.rows] == ["kept", "kept", "dropped"]
    assert road.edges == pytest.approx(EDGES[:3])
    assert "cumulative 2D slope" in rep.rows[2].reason
    road, rep = apply_cutoff(build, EDGES, CutoffRule("resolution"))
    assert [r.status for r in rep.rows] == ["kept", "kept", "dropped"]
    # above everything: the generated band is kept whole
    road, rep = apply_cutoff(build, EDGES, CutoffRule("slope", 2 * cum[-1]))
    assert [r.status for r in rep.rows] == ["kept"] * 3


def test_stated_wavelength_cuts_there_and_drops_the_bands_below() -> None:
    build = _builder(("measured", "generated"))
    road, rep = apply_cutoff(build, EDGES, parse_cutoff(0.02))
    assert road.edges == pytest.approx((5.0, 0.5, 0.05, 0.02))
    assert rep.rows[2].status == "shortened" and rep.rows[2].short_edge == pytest.approx(0.02)
    road, rep = apply_cutoff(build, EDGES, parse_cutoff("0.5"))
    assert road.edges == pytest.approx((5.0, 0.5))
    assert [r.status for r in rep.rows] == ["kept", "dropped", "dropped"]
    with pytest.raises(SurfaceError, match="between the finest edge"):
        apply_cutoff(build, EDGES, parse_cutoff(10.0))
    for bad in ("steep", -1.0, float("nan"), True):
        with pytest.raises(SurfaceError, match="cutoff"):
            parse_cutoff(bad)


def test_four_scale_road_is_self_affine_and_reaches_the_slope_limit_at_3um() -> None:
    road = four_scale_road()
    assert road.edges == (20.0, 3.0, 0.3, 0.04, 0.003)
    slopes = [s.rms_slope for s in road.scales]
    assert cumulative_slope_2d(slopes)[-1] == pytest.approx(1.3, rel=1e-9)
    # its spectrum is the stated power law: the Hurst exponent fitted on the coarse profile's
    # PSD over 3-0.04 mm is 0.8 within 0.05 (a Gaussian random profile scatters the periodogram)
    meso, micro1 = road.scales[1].profile, road.scales[2].profile  # both from the coarse one
    coarse = meso.with_h(meso.h + micro1.h)
    q, c = psd_1d(coarse)
    fit = fit_psd_power_law(q, c, (2 * math.pi / 2.0, 2 * math.pi / 0.05))
    assert fit.H == pytest.approx(FOUR_SCALE_H, abs=0.05)
    # band slopes grow down the scales as the power law says: s_i^2 ~ q^(2-2H) band by band
    ratios = np.array(slopes[1:]) / np.array(slopes[:-1])
    assert np.all(ratios > 1.2) and np.all(ratios < 2.2)


def test_default_scene_states_its_lowest_scale_and_keeps_the_measured_bands() -> None:
    scene = load_scene("default")
    rep = scene.surface.cutoff_report
    assert scene.surface.stated_edges == (20.0, 3.0, 0.3, 0.04, 0.003)
    assert scene.surface.edges == (20.0, 3.0, 0.3)
    assert scene.surface.names == ("macro", "meso")
    assert [(r.kind, r.status) for r in rep.rows] == [
        ("measured", "kept"), ("measured", "kept"), ("generated", "dropped"),
        ("generated", "dropped")]
    assert not scene.warnings
    stress = load_scene("captif_stress")
    assert stress.surface.edges == (20.0, 3.0, 0.3, 0.04, 0.003)
    assert sum("max_slope" in w for w in stress.warnings) == 2  # micro1 and micro2
    four = load_scene("four_scale")
    assert four.n_scales == 4 and four.surface.cutoff_report.cumulative_slope == pytest.approx(1.3)


SCENE = """
name = "t"
[surface]
source = "default_road"
edges = [20.0, 3.0, 0.3, 0.04]
{extra}
[conditions]
compounds = ["tread_default"]
pressures = [0.3]
velocities = [10.0]
[numerics.micro]
newton = "hybrid"
"""


def test_scene_cutoff_keys_and_tables_of_dropped_scales() -> None:
    sc = parse_scene(SCENE.format(extra=""))
    assert sc.surface.names == ("macro", "meso")
    assert any("[numerics.micro] is ignored" in w for w in sc.warnings)
    kept = parse_scene(SCENE.format(extra="cutoff = 0.04"))
    assert kept.surface.names == ("macro", "meso", "micro")
    assert dict(kept.numerics.scales)["micro"] == (("newton", "hybrid"),)
    for extra, match in (('cutoff = "steep"', r"\[surface\].cutoff"),
                         ("cutoff = -0.1", r"\[surface\].cutoff"),
                         ("cutoff = 50.0", "between the finest edge"),
                         ("max_slope = 0", r"\[surface\].max_slope")):
        with pytest.raises(SceneError, match=match):
            parse_scene(SCENE.format(extra=extra))


def test_run_check_prints_the_bands_and_the_sharpest_tips(capsys) -> None:
    from rubberfriction.driver.cli.main import main

    assert main(["run", "four_scale", "--check", "--samples", "1", "1"]) == 0
    out = capsys.readouterr().out
    assert "lowest scale: cutoff = \"slope\"" in out and out.count(" kept") >= 4
    tips = [line for line in out.splitlines() if "sharpest tip radius" in line]
    assert [t.split()[0] for t in tips] == ["macro", "meso", "micro1", "micro2"]


def test_tip_radius_of_a_sine_is_one_over_its_curvature() -> None:
    """h = a sin(2 pi x / lam): R = 1 / (a (2 pi / lam)^2) at the crest; central differences on
    200 points per wavelength are within 0.1 %."""
    from rubberfriction.driver.surfaces.roads import smallest_tip_radius

    a, lam = 0.01, 0.3
    x = np.linspace(0.0, 2 * lam, 401)
    h = a * np.sin(2 * np.pi * x / lam)
    h[-1] = h[0]
    assert smallest_tip_radius(x, h) == pytest.approx(1 / (a * (2 * np.pi / lam) ** 2), rel=1e-3)


def test_a_finer_cut_of_the_four_scale_road_continues_the_same_road() -> None:
    """Edges below 3 um add an ultra-fine 'scan'; the bands above stay the same realisation, and
    max_slope 1.0 / 1.3 / 2.0 cut it at 11 um / 3 um / below 3 um (scene.with_surface)."""
    from rubberfriction.driver.scenes import with_surface

    design = four_scale_road()
    finer = four_scale_road((20.0, 3.0, 0.3, 0.04, 0.003, 0.0002))
    np.testing.assert_array_equal(finer.scales[2].profile.h, design.scales[2].profile.h)
    assert finer.scales[3].rms_slope == pytest.approx(design.scales[3].rms_slope, rel=5e-3)
    scene = load_scene("four_scale")
    kept = {}
    for m in (1.0, 1.3, 2.0):
        s = with_surface(scene, max_slope=m, edges=finer.edges,
                         names=("macro", "meso", "micro1", "micro2", "micro3"))
        kept[m] = s.surface.edges[-1]
        assert s.surface.cutoff_report.cumulative_slope <= m * (1 + 1e-6)
    assert kept[1.0] == pytest.approx(0.0111, rel=0.01) and kept[1.3] == 0.003
    assert 0.0002 < kept[2.0] < 0.003


def test_cli_four_scale_road_writes_its_table_samples_and_plot(tmp_path, capsys) -> None:
    from rubberfriction.driver.cli.main import main

    out = tmp_path / "fs"
    assert main(["surface", "four-scale", "--out", str(out), "--samples", "1", "--cutoff",
                 "0.01", "--plot", str(out / "scales.png")]) == 0
    text = capsys.readouterr().out
    assert "shortened to 0.04-0.01 mm: the stated cut-off" in text
    assert len(list(out.glob("*_sample*.csv"))) == 4 and (out / "scales.png").stat().st_size > 1000
