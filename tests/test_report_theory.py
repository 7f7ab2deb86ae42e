"""The multiscale report draws the analytical baselines beside the FE mu(v) points (issue 7).

A tiny fake campaign result (no FE runs: the points carry made-up FE values) on a one-sine
scene in full contact, at T0 = 40 degC, two pressures.  For a sinusoid in full contact the
line-roughness Persson theory is the exact linear viscoelastic result
``mu = (k h0)^2 E''(k v, T0) / (4 (1 - nu^2) p0)`` (``driver/theory/persson.py``), so the
theory figures the report writes into its summary are checked against that closed form
(rel. 1e-3: the summary prints 4 digits), and against the same formula at the WLF reference
temperature, which they must *not* match (T0 is respected).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import matplotlib  # noqa: F401  (installed by scripts/setup.sh: a missing one must fail)
import numpy as np
import pytest

AMPLITUDE, WAVELENGTH = 0.01, 5.0  # mm
PRESSURES = (2.0, 3.0)  # MPa, both above the full-contact pressure of this sine
VELOCITIES = (1.0, 50.0)  # mm/s
T0_C = 40.0

SCENE = f"""
name = "tiny"
[surface]
source = "sines"
amplitudes = [{AMPLITUDE}]
wavelengths = [{WAVELENGTH}]
[conditions]
compounds = ["tread_default"]
pressures = [{PRESSURES[0]}, {PRESSURES[1]}]
velocities = [{VELOCITIES[0]}, {VELOCITIES[1]}]
T0 = {T0_C}
T0_unit = "degC"
"""


def fake_result(tmp_path: Path, scene_text: str = SCENE) -> Any:
    """A finished 'campaign' of one scale: FE values made up, report inputs real."""
    from rubberfriction.driver.multiscale.campaign import CampaignResult
    from rubberfriction.driver.multiscale.results import Point, PointResult, ScaleResult
    from rubberfriction.driver.multiscale.statistics import sample_stats
    from rubberfriction.driver.scenes import parse_scene
    from rubberfriction.driver.runtime.store import Store

    scene = parse_scene(scene_text, "<test>", tmp_path)
    points = []
    for p in scene.conditions.pressures:
        for v in scene.conditions.velocities:
            mu = sample_stats([0.01 * (1 + math.log10(v)) / p, 0.012 * (1 + math.log10(v)) / p])
            sc = ScaleResult(0, "s0", (WAVELENGTH, WAVELENGTH / 8), pressure=p, mu=mu,
                             contact=sample_stats([1.0, 1.0]), area_ratio=1.0)
            points.append(PointResult(Point("tread_default", p, v), "rough", status="ok", mu=mu,
                                      area_ratio=1.0, scales=[sc]))
    return CampaignResult(scene, tmp_path / "out", points, {}, None, 1.0, 1, "now",
                          Store(tmp_path / "store"))


def closed_form(p: float, v: float, T: float | None) -> float:
    from rubberfriction.driver.theory import rubber_from_compound
    from rubberfriction.driver.theory.persson import mu_full_contact_sinusoid
    from rubberfriction.forms.material_files import load_compound

    rub = rubber_from_compound(load_compound("tread_default"))
    k = 2 * math.pi / WAVELENGTH
    E = complex(rub.E(k * v, T))
    return mu_full_contact_sinusoid(k, AMPLITUDE, E, p, nu=rub.nu)


@pytest.fixture
def spy(monkeypatch) -> list[dict[str, Any]]:
    """Record every call of baseline.draw_beside_fe (the real one still draws)."""
    from rubberfriction.driver.multiscale import baseline

    calls: list[dict[str, Any]] = []
    real = baseline.draw_beside_fe

    def wrapper(ax, scene, **kw):
        out = real(ax, scene, **kw)
        calls.append({"ax": ax, "scene": scene, "kw": kw, "out": out})
        return out

    monkeypatch.setattr(baseline, "draw_beside_fe", wrapper)
    return calls


def test_report_draws_theory_beside_fe(tmp_path: Path, spy) -> None:
    from rubberfriction.driver.multiscale.report import write_report

    result = fake_result(tmp_path)
    files = write_report(result, quiet=True)
    mu_v = result.output / "mu_v.png"
    assert mu_v in files and mu_v.stat().st_size > 1000

    # one call per (compound, p) group, with the group's compound, pressure, speeds and T0 (K)
    assert len(spy) == len(PRESSURES)
    assert sorted(c["kw"]["pressure"] for c in spy) == list(PRESSURES)
    T0 = T0_C + 273.15
    for c in spy:
        assert c["scene"] is result.scene
        assert c["kw"]["compound"] == "tread_default"
        assert c["kw"]["T0"] == pytest.approx(T0, abs=1e-12)
        assert list(c["kw"]["v_fe"]) == list(VELOCITIES)
        curves, notes = c["out"]
        assert [cv.model for cv in curves] == ["persson-1d"]  # a sine: line spectrum only
        assert curves[0].v[0] == pytest.approx(VELOCITIES[0] / 3)
        assert curves[0].v[-1] == pytest.approx(VELOCITIES[-1] * 3)
        assert any("only persson-1d applies" in n for n in notes)
        # the pressure is given per group: no "scene lists 2 pressures ... picks another" note
        assert not any("picks another" in n for n in notes)

    # the theory lines are on the mu(v) axes, in the colour of their FE group, labelled
    ax = spy[0]["ax"]
    for p in PRESSURES:
        fe = [c.lines[0] for c in ax.containers
              if c.get_label() == f"tread_default, p = {p:g} MPa"]
        th = [ln for ln in ax.lines if ln.get_label().startswith("theory: Persson")
              and f"(tread_default, p = {p:g} MPa)" in ln.get_label()]
        assert len(fe) == 1 and len(th) == 1
        assert th[0].get_color() == fe[0].get_color()
        assert np.min(th[0].get_xdata()) < VELOCITIES[0] < VELOCITIES[-1] < np.max(
            th[0].get_xdata())

    # the summary gives the theory at the FE speeds: the exact full-contact result at T0
    text = (result.output / "summary.txt").read_text()
    for p in PRESSURES:
        m = re.search(rf"theory: tread_default, p = {p:g} MPa, T0 = 313.15 K: at v = 1, 50 "
                      r"mm/s: persson-1d mu = ([0-9.e+-]+), ([0-9.e+-]+)", text)
        assert m, text
        got = [float(m.group(1)), float(m.group(2))]
        for g, v in zip(got, VELOCITIES):
            assert g == pytest.approx(closed_form(p, v, T0), rel=1e-3)
            assert g != pytest.approx(closed_form(p, v, None), rel=0.05)  # T0 matters here


def test_report_without_theory(tmp_path: Path, spy) -> None:
    from rubberfriction.driver.multiscale.report import write_report

    result = fake_result(tmp_path)
    write_report(result, quiet=True, theory=False)
    assert spy == []
    assert (result.output / "mu_v.png").is_file()
    assert "theory:" not in (result.output / "summary.txt").read_text()


def test_theory_failure_never_breaks_the_report(tmp_path: Path, monkeypatch) -> None:
    """An unexpected error inside the theory, and a profile file gone since the scene was
    loaded: the report is written, the summary says why the curves are missing."""
    from rubberfriction.driver.multiscale import baseline
    from rubberfriction.driver.multiscale.report import write_report

    def broken(*args, **kw):
        raise RuntimeError("boom")

    with monkeypatch.context() as m:
        m.setattr(baseline, "evaluate", broken)
        result = fake_result(tmp_path / "a")
        write_report(result, quiet=True)
    text = (result.output / "summary.txt").read_text()
    assert (result.output / "mu_v.png").is_file()
    assert text.count("theory curves not drawn: RuntimeError: boom") == len(PRESSURES)

    prof = tmp_path / "road.txt"
    x = np.linspace(0.0, 40.0, 4001)
    np.savetxt(prof, np.column_stack([x, 0.05 * np.sin(2 * math.pi * x / 4.0)]))
    scene = SCENE.replace(
        f'source = "sines"\namplitudes = [{AMPLITUDE}]\nwavelengths = [{WAVELENGTH}]',
        f'source = "files"\nfiles = ["{prof.name}"]\nedges = [8.0, 1.0, 0.1]')
    result = fake_result(tmp_path, scene)
    prof.unlink()
    write_report(result, quiet=True)
    text = (result.output / "summary.txt").read_text()
    assert (result.output / "mu_v.png").is_file()
    assert text.count("theory curves not drawn") == len(PRESSURES), text
    assert "road.txt" in text


def test_theory_request_from_a_loaded_scene() -> None:
    """A loaded Scene gives the theory its surface, analysis range, compound, conditions."""
    from rubberfriction.driver.multiscale.baseline import request_from_scene
    from rubberfriction.driver.scenes import load_scene

    got = request_from_scene(load_scene("captif_stress"))
    assert got.surface == "default" and got.edges == (20.0, 3.0, 0.3, 0.04, 0.003)
    assert (got.lambda_max, got.lambda_min) == (20.0, 0.003) and not got.files and not got.sines
    assert got.compound == "tread_default" and got.pressure == 0.3
    assert got.velocities == (10.0, 100.0, 1000.0)
    # the theory sees the scales the cut-off rule kept, as the FE does
    got = request_from_scene(load_scene("default"))
    assert got.edges == (20.0, 3.0, 0.3) and got.lambda_min == 0.3
    got = request_from_scene(load_scene("four_scale"))  # its own road, not the default one
    assert got.surface == "four_scale" and got.lambda_min == 0.003
    assert got.T0 == pytest.approx(293.15) and got.adhesion is None and got.notes == ()


def test_bench_theory_json(tmp_path: Path, capsys) -> None:
    """``rubberfriction bench theory`` prints its table and writes the same figures as JSON
    (FE side off here: it is a few seconds; ``--fe`` is the default)."""
    import json

    from rubberfriction.driver.bench.theory import REFERENCE_CASE, main

    out = tmp_path / "bench.json"
    assert main(["--n", "5", "--repeat", "1", "--no-fe", "--fe-seconds", "60",
                 "--json", str(out)]) == 0
    text = capsys.readouterr().out
    fig = json.loads(out.read_text())
    assert fig["n_speeds"] == 5 and "fe_single_run" not in fig
    t1 = fig["theory"][REFERENCE_CASE]["time_s"]
    assert 0 < t1 < math.inf  # a measured time: no bound on the speed
    assert fig["fe_point"] == {"command": None, "status": "given", "time_s": 60.0}
    assert f"{REFERENCE_CASE}: 5-speed curve" in text
    assert f"costs {60.0 / t1:.3g} x the whole 5-speed 1D curve" in text


def test_cli_run_no_theory(tmp_path: Path, monkeypatch, spy) -> None:
    """``rubberfriction run --no-theory``: the campaign's own report is skipped and the report is
    written without the baselines (the campaign is a stand-in here)."""
    from rubberfriction.driver.multiscale import campaign
    from rubberfriction.driver.cli.main import main

    calls = []

    def fake_run_scene(scene, **kw):
        calls.append(kw)
        return fake_result(tmp_path)

    monkeypatch.setattr(campaign, "run_scene", fake_run_scene)
    scene = tmp_path / "tiny.toml"
    scene.write_text(SCENE)
    assert main(["run", str(scene), "--quiet", "--no-theory"]) == 0
    assert calls[-1]["report"] is False and spy == []
    summary = tmp_path / "out" / "summary.txt"
    assert summary.is_file() and "theory:" not in summary.read_text()
    summary.unlink()
    assert main(["run", str(scene), "--quiet"]) == 0
    assert calls[-1]["report"] is True and not summary.exists()  # run_scene writes it
