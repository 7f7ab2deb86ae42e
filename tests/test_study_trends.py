"""The trend study's table builder (driver/study): exact, never the outcome of a trend.

What is pinned: the ratio of two evidence values and its sign against the thesis' direction,
the spread test (|r - 1| against the two 95 % half widths in quadrature), the factor-1.5 ratio
test, a failed or absent case giving a "missing" row with its reason, evidence.json round trips
(NaN included), and that the evidence read from a finished campaign is the campaign's own
numbers (results.csv).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.driver.study.cases import (
    TrendSettings,
    lowest_scale,
    quick_settings,
    scene_texts,
)
from rubberfriction.driver.study.evidence import (
    Evidence,
    PointValue,
    SawtoothValue,
    SpreadValue,
    point_key,
)
from rubberfriction.driver.study.trends import RATIO_FACTOR, build_rows, table_text, trends

TABLE = trends(100.0, 1000.0, 1000.0, "m1")


def _evidence(**mu: float) -> Evidence:
    """Materials c1..c6 and the other cases at 1000 mm/s, mu given per compound (default 0.5)."""
    ev = Evidence({})
    for c in ("c1", "c2", "c3", "c4", "c5", "c6"):
        ev.points[point_key("materials", c, 1000.0)] = PointValue(mu.get(c, 0.5), ci95=0.01,
                                                                  contact=0.2)
    ev.points[point_key("rough", "c3", 1000.0)] = PointValue(mu.get("rough", 0.6), ci95=0.01)
    ev.points[point_key("polished", "c3", 1000.0)] = PointValue(mu.get("polished", 0.45),
                                                                ci95=0.01, contact=0.3)
    for v, iso, hot in ((100.0, 0.5, 0.45), (1000.0, 0.6, 0.40)):
        ev.points[point_key("flash", "m1", v)] = PointValue(iso)
        ev.points[point_key("flash_hot", "m1", v)] = PointValue(hot)
    ev.spread = SpreadValue("micro1", 30, 0.047, 0.015, 0.0149, 0.3)
    ev.sawtooth = SawtoothValue(0.3, 0.2)
    return ev


def _row(rows, key):
    return next(r for r in rows if r.key == key)


def test_eight_rows_with_thesis_statements():
    assert [t.key for t in TABLE] == ["speed", "glass", "hardness", "filler", "rough",
                                      "sawtooth", "samples", "polish"]
    assert all(t.thesis and t.comparisons for t in TABLE)


def test_ratios_signs_and_verdicts_are_exact():
    rows = build_rows(_evidence(c1=0.6, c4=0.5, c2=0.55, c5=0.5, c6=0.7, c3=0.4,
                                polished=0.35), TABLE)
    glass = _row(rows, "glass")
    assert glass.comparisons[0].ratio == pytest.approx(0.6 / 0.5, rel=1e-12)
    assert glass.comparisons[1].ratio == pytest.approx(0.55 / 0.5, rel=1e-12)
    assert glass.verdict == "agrees"
    hardness = _row(rows, "hardness")  # c6 / c2 > 1 agrees, c3 / c1 = 0.4 / 0.6 < 1 does not
    assert [c.sign for c in hardness.comparisons] == [True, False]
    assert hardness.verdict == "partly"
    assert any("c3 / c1" in w for w in hardness.why)  # the disagreement says why
    speed = _row(rows, "speed")  # isothermal 0.6 / 0.5 rises, flash 0.40 / 0.45 falls
    assert speed.comparisons[0].ratio == pytest.approx(1.2)
    assert speed.comparisons[1].ratio == pytest.approx(0.40 / 0.45)
    assert speed.verdict == "agrees"
    polish = _row(rows, "polish")  # mu 0.35 / 0.4 falls, contact 0.3 / 0.2 rises
    assert polish.comparisons[1].ratio == pytest.approx(1.5)
    assert polish.verdict == "agrees"
    assert "7 of 8 trends agree in sign" in table_text(rows, "header")


def test_information_only_pairs_do_not_count():
    # filler: c1 / c2 counts; c3 / c6 and c4 / c5 (missed by the thesis too) are information
    rows = build_rows(_evidence(c1=0.6, c2=0.5, c3=0.1, c6=0.9, c4=0.1, c5=0.9), TABLE)
    filler = _row(rows, "filler")
    assert [c.counts for c in filler.comparisons] == [True, False, False]
    assert [c.sign for c in filler.comparisons] == [True, False, False]
    assert filler.verdict == "agrees"


def test_spread_test_uses_both_half_widths():
    ev = _evidence(c1=0.505, c4=0.5)
    ev.points[point_key("materials", "c1", 1000.0)].ci95 = 0.03
    ev.points[point_key("materials", "c4", 1000.0)].ci95 = 0.04
    c = _row(build_rows(ev, TABLE), "glass").comparisons[0]
    assert c.uncertainty == pytest.approx(math.hypot(0.03 / 0.505, 0.04 / 0.5), rel=1e-12)
    assert c.sign is True and c.significant is False  # 1 % against about 10 %
    one_sample = _evidence()
    one_sample.points[point_key("materials", "c1", 1000.0)].ci95 = math.nan
    assert _row(build_rows(one_sample, TABLE), "glass").comparisons[0].significant is None


def test_thesis_ratio_within_a_factor():
    ev = _evidence()
    ev.sawtooth = SawtoothValue(1.4 * RATIO_FACTOR * 1.01, 1.0)
    saw = _row(build_rows(ev, TABLE), "sawtooth")
    assert saw.verdict == "agrees" and saw.ratio_ok is False
    ev.sawtooth = SawtoothValue(1.4 * RATIO_FACTOR * 0.99, 1.0)
    assert _row(build_rows(ev, TABLE), "sawtooth").ratio_ok is True
    samples = _row(build_rows(ev, TABLE), "samples")
    assert samples.comparisons[0].ratio == pytest.approx(0.047 / 0.015)
    assert samples.ratio_ok is True


def test_failed_or_absent_case_is_missing_with_its_reason():
    ev = _evidence()
    ev.points[point_key("materials", "c5", 1000.0)] = PointValue(math.nan, ok=False,
                                                                 reason="micro1: no window")
    del ev.points[point_key("flash_hot", "m1", 1000.0)]
    rows = build_rows(ev, TABLE)
    glass = _row(rows, "glass")
    assert glass.verdict == "missing"
    assert any("micro1: no window" in w for w in glass.why)
    assert _row(rows, "speed").verdict == "missing"
    assert any("not run" in w for w in _row(rows, "speed").why)


def test_evidence_round_trip(tmp_path):
    ev = _evidence()
    ev.points["x:c1@10"] = PointValue(math.nan, ok=False, reason="r",
                                      scale_mu={"macro": 0.5, "meso": 0.25})
    ev.notes.append("materials: note")
    back = Evidence.load(ev.save(tmp_path / "evidence.json"))
    assert back.spread == ev.spread and back.sawtooth == ev.sawtooth
    assert back.notes == ev.notes
    assert math.isnan(back.points["x:c1@10"].mu)
    assert back.points["x:c1@10"].scale_mu == {"macro": 0.5, "meso": 0.25}
    assert back.points[point_key("materials", "c2", 1000.0)] == \
        ev.points[point_key("materials", "c2", 1000.0)]
    assert "NaN" not in (tmp_path / "evidence.json").read_text()  # strict JSON


def test_settings_and_cases():
    full, quick = TrendSettings(), quick_settings()
    assert lowest_scale(full) == "meso" and lowest_scale(quick) == "meso"
    assert full.flash_cut == 0.003 and quick.flash_cut == 0.3
    assert full.flash_slide == 25.0  # thesis 8.5.1's sliding interval
    texts = scene_texts(full)
    assert set(texts) == {"materials", "rough", "polished", "spread", "flash"}
    assert 'compounds = ["c1", "c2", "c3", "c4", "c5", "c6"]' in texts["materials"]
    assert "height_scale = 1.25" in texts["rough"]
    assert 'polish_scales = ["meso"]' in texts["polished"]
    assert 'mode = "hot-layer"' in texts["flash"] and "cutoff = 0.003" in texts["flash"]
    assert all("cutoff = 0.3" in t for c, t in texts.items() if c != "flash")


def test_every_case_scene_is_valid(tmp_path):
    from rubberfriction.driver.scenes import parse_scene

    for settings in (TrendSettings(), quick_settings()):
        for case, text in scene_texts(settings).items():
            scene = parse_scene(text, case, tmp_path)
            cut = settings.flash_cut if case == "flash" else settings.cutoff
            assert scene.n_scales == {"micro2": 4, "micro1": 3,
                                      "meso": 2}[lowest_scale(settings, cut)], case
    flash = parse_scene(scene_texts(TrendSettings(flash_mu_const=0.25))["flash"], "f", tmp_path)
    assert flash.thermal.mu_const == 0.25  # the constant part reaches the macro contact


def test_the_flash_case_takes_its_own_cut_off(tmp_path):
    """--flash-cutoff 0.003: the flash scene keeps micro2 (four scales, thesis 8.5.3) with the
    four_scale scene's micro2 mesh; the other cases keep the study's cut-off and numerics."""
    from rubberfriction.driver.scenes import parse_scene

    settings = TrendSettings(flash_cutoff=0.003, flash_mu_const=0.0)
    texts = scene_texts(settings)
    flash = parse_scene(texts["flash"], "f", tmp_path)
    assert flash.n_scales == 4 and "cutoff = 0.003" in texts["flash"]
    assert "[numerics.micro2]\nelements_per_wavelength = 8" in texts["flash"]
    assert lowest_scale(settings, settings.flash_cut) == "micro2"
    for case in ("materials", "rough", "polished", "spread"):
        assert "cutoff = 0.3" in texts[case] and "numerics.micro2" not in texts[case], case
    assert "flash case cut at 0.003 mm" in settings.describe()
    assert "cut at" not in quick_settings().describe().split("flash case")[1]


def test_speed_evidence_places_the_lowest_scale_against_the_loss_peak():
    """The speed row's note: the flash compound's tan delta peak at 20 degC (a local maximum on
    the grid) and the side of it on which the lowest scale's band 2 pi v / lambda lies.  A glass
    transition moved by dT moves the peak by exactly 1 / tg_shift_factor (forms.derive), to the
    grid's 1/100 decade."""
    from rubberfriction.driver.study.run import STUDY_T0, speed_notes, tan_delta_peak
    from rubberfriction.forms import derive as D
    from rubberfriction.forms.material_files import load_compound

    m1 = load_compound("m1")
    w, td = tan_delta_peak(m1)
    for f in (0.9, 1.1):
        E = m1.complex_modulus(w * f, STUDY_T0)
        assert E.imag / E.real < td
    base = D.Spectrum(m1.E_inf, m1.prony.moduli(m1.E_inf), m1.prony.tau, m1.wlf)
    low = D.shift_glass_transition(base, -30.0)
    assert tan_delta_peak(base)[0] == pytest.approx(w, rel=0.024)
    assert tan_delta_peak(low)[0] == pytest.approx(w / D.tg_shift_factor(m1.wlf, -30.0),
                                                   rel=0.024)
    # m1 is placed (its tau_factor) with micro2 (0.04-0.003 mm) below the peak at 1 m/s:
    # 2 pi 1000 / 0.003 = 2.09e6 rad/s < 2.95e6
    assert 2.09e6 < w < 3.0e6
    note = speed_notes(TrendSettings())[0]  # the flash case cut at 0.003 mm
    assert note.startswith("speed: m1's loss tangent")
    assert "micro2 (0.04-0.003 mm)" in note
    assert "at 100 mm/s (below the peak)" in note and "at 1000 mm/s (below the peak)" in note
    glassy = speed_notes(TrendSettings(flash_compound="tread_default"))[0]  # m1 before 0.26.0
    assert "at 1000 mm/s (above the peak, glassy side)" in glassy
    assert "mu_const = 0.6" in note
    assert speed_notes(TrendSettings(flash=False)) == []


def test_evidence_of_a_campaign_is_its_results_csv(tmp_path):
    """point_value reads mu, its spread, the contact and mu per scale of a finished campaign:
    the same numbers as the campaign's results.csv / scales.csv (printed to 6 digits)."""
    from mpi4py import MPI  # noqa: F401  (before DOLFINx)

    from rubberfriction.driver.multiscale.campaign import run_scene
    from rubberfriction.driver.scenes import parse_scene
    from rubberfriction.driver.study.evidence import point_value
    from tiny_scenes import two_sines

    scene = parse_scene(two_sines("study_tiny", [10.0]), "tiny", tmp_path).with_output(tmp_path)
    res = run_scene(scene, quiet=True)
    pv = point_value(res.points[0])
    with open(Path(res.output) / "results.csv") as f:
        row = next(csv.DictReader(f))
    assert pv.ok and pv.mu == pytest.approx(float(row["mu"]), rel=1e-5)  # the CSV prints 6 digits
    with open(Path(res.output) / "scales.csv") as f:
        scales = list(csv.DictReader(f))
    assert pv.scale_mu == pytest.approx({s["name"]: float(s["mu"]) for s in scales}, rel=1e-5)
    assert pv.contact == pytest.approx(float(scales[-1]["contact_fraction"]), rel=1e-5)


def test_flash_values_of_a_loop_result():
    from types import SimpleNamespace

    from rubberfriction.driver.study.evidence import flash_values

    res = SimpleNamespace(ok=True, mu=0.41, mu_isothermal=0.52,
                          notes=["macro mu: not stationary, mean of the last half"])
    iso, hot, notes = flash_values(res)
    assert (iso.mu, hot.mu, iso.ok, hot.ok) == (0.52, 0.41, True, True)
    assert notes == res.notes
    hot_layer = SimpleNamespace(ok=True, mu=0.41, mu_isothermal=0.52, notes=[],
                                temperatures=np.array([293.15, 333.15]),
                                mu_lower=np.array([0.188, 0.17]))
    assert flash_values(hot_layer)[2] == ["hot-layer law, the lower scales' mu: 0.188 at +0 K, "
                                          "0.17 at +40 K"]
    failed = SimpleNamespace(ok=False, mu=math.nan, mu_isothermal=0.52, notes=["no law"])
    assert flash_values(failed)[1].reason == "no law" and not flash_values(failed)[1].ok


def test_api_refuses_an_unknown_setting():
    import rubberfriction as rf

    with pytest.raises(rf.InputError, match="did you mean 'cutoff'"):
        rf.study_trends(cutof=0.04)


@pytest.mark.parametrize("key,value", [("cutoff", 0.001), ("flash_cutoff", 5.0)])
def test_a_cut_off_off_the_road_is_refused_by_name(key, value):
    import rubberfriction as rf

    with pytest.raises(rf.InputError, match=rf"^{key} = {value} mm: expected a wavelength from "
                       r"0.003 to 3 mm"):
        rf.study_trends(**{key: value})
