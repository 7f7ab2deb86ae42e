"""The mesh check of a campaign (``run SCENE --mesh-check``, driver.multiscale.mesh_check).

* The refined run is the stored run's inputs with contact elements ``factor`` times shorter:
  its spec in the store has h_contact / 2, elements_per_wavelength x 2 and the step / 2, and
  the same pressure, friction input and sample as the campaign's run.
* Physics: the two-sine scene's macro friction run (a 2 mm sine, 20 um high, in full contact
  at 0.3 MPa: a smooth field that 8 elements per wavelength resolve; the full-contact sinusoid
  is within 0.5 % of its closed form at 16, docs/verification.md) moves by less than the
  check's own 2 % tolerance when its contact elements are halved (measured +1.2 %), so the
  summary calls it converged.  The micro sine (0.2 mm, 2 um) is in partial contact (A/A0 0.49,
  patches of about 4 contact elements at 8 per wavelength): its mu moves by +15 % (measured),
  beyond the tolerance, and the summary says that scale is not mesh-converged.
* The check reuses its refined runs from the store on a second call (resumable like a
  campaign) and replaces its summary block rather than appending a second one.
* Selections and refusals are one line naming the option.
"""

from __future__ import annotations

import csv
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tiny_scenes import two_sines

import rubberfriction as rf

from rubberfriction.driver.cli.main import main
from rubberfriction.driver.multiscale.mesh_check import (
    MESH_TOL,
    MeshRow,
    mesh_lines,
    mesh_selection,
    with_mesh_lines,
)
from rubberfriction.driver.multiscale.report.summary import MESH_NOT_CHECKED
from rubberfriction.driver.multiscale.rerun import load_stored
from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.scenes import SceneError, parse_scene


def _scene_file(tmp_path: Path) -> Path:
    path = tmp_path / "mesh.toml"
    text = two_sines("mesh", [100.0])
    path.write_text(text.replace('name = "mesh"', f'name = "mesh"\noutput = "{tmp_path / "out"}"'))
    return path


def _row(change: float, scale: str = "macro", point: str = "p", factor: int = 2) -> MeshRow:
    return MeshRow(point=point, branch="up", scale_name=scale, sample=0, factor=factor,
                   h_contact=0.5, key="k", key_fine="kf", attempt="mortar", attempt_fine="mortar",
                   status_fine="ok", reason_fine="", mu=0.2, mu_fine=0.2 * (1 + change),
                   contact=0.1, contact_fine=0.1, energy_balance=0.0, energy_balance_fine=0.0,
                   wall=1.0, wall_fine=3.0)


def test_run_mesh_check_refines_the_stored_inputs_and_reports_the_change(tmp_path, capsys):
    scene_file = _scene_file(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--mesh-check", "--no-theory"]) == 0
    printed = capsys.readouterr().out
    with open(out / "mesh_check.csv") as f:
        rows = {r["scale_name"]: r for r in csv.DictReader(f)}
    assert set(rows) == {"macro", "micro"}  # sample 0 of each scale's friction run
    store = Store(out / "store")
    for name, r in rows.items():
        coarse = load_stored(store, r["key"]).spec
        fine = load_stored(store, r["key_fine"]).spec
        assert fine.h_contact == pytest.approx(float(r["h_contact"]) / 2, rel=1e-12)
        assert fine.elements_per_wavelength == 2 * coarse.elements_per_wavelength
        assert fine.step_length == pytest.approx(coarse.step_length / 2, rel=1e-12)
        assert (fine.pressure, fine.velocity) == (coarse.pressure, coarse.velocity)
        assert np.array_equal(fine.surface_h, coarse.surface_h)
        assert fine.friction == coarse.friction  # the scale below's mu, as handed up
        assert int(r["factor"]) == 2 and r["status_fine"] == "ok"
    # the smooth macro sine is resolved: within the check's tolerance, hence "converged"
    macro = rows["macro"]
    assert macro["attempt_fine"] == "mortar"
    assert abs(float(macro["change"])) < MESH_TOL
    assert math.isclose(float(macro["change"]),
                        float(macro["mu_fine"]) / float(macro["mu"]) - 1, rel_tol=1e-4)  # 6 digits
    # the micro sine in partial contact (A/A0 0.49: patches of 4 contact elements) is not:
    # its mu moves by +15 % (measured), beyond the tolerance, and the summary says so
    micro = rows["micro"]
    assert 0.3 < float(micro["contact"]) < 0.7
    assert float(micro["change"]) > MESH_TOL
    summary = (out / "summary.txt").read_text()
    assert MESH_NOT_CHECKED not in summary
    assert "mesh (runs again with contact elements 2x shorter" in summary
    assert "up   macro    mu changes by" in summary and "converged" in summary
    assert "up   micro    mu changes by" in summary and "1 of 1 beyond" in summary
    assert "not mesh-converged" in summary
    assert "mesh check: 2 run(s) again" in printed
    assert (out / "mesh_check.png").is_file()

    # again: the refined runs come from the store, and the summary keeps one mesh block
    assert main(["run", str(scene_file), "--mesh-check", "--no-theory", "--quiet"]) == 0
    summary2 = (out / "summary.txt").read_text()
    assert summary2.count("mesh (runs again") == 1
    with open(out / "mesh_check.csv") as f:
        again = {r["scale_name"]: r for r in csv.DictReader(f)}
    assert again["macro"]["mu_fine"] == macro["mu_fine"]

    # the Python API is the same check: the same rows, from the store
    scene = rf.load_scene(str(scene_file))
    rows_api = rf.mesh_check(scene, rf.run(scene, quiet=True), quiet=True)
    by_scale = {r["scale_name"]: r for r in rows_api}
    assert by_scale["macro"]["mu_fine"] == pytest.approx(float(macro["mu_fine"]), rel=1e-5)
    assert by_scale["macro"]["converged"] == 1 and by_scale["micro"]["converged"] == 0


def test_campaign_without_the_check_says_so(tmp_path: Path):
    scene_file = _scene_file(tmp_path)
    assert main(["run", str(scene_file), "--no-theory", "--quiet"]) == 0
    assert MESH_NOT_CHECKED in (tmp_path / "out" / "summary.txt").read_text()


def test_mesh_lines_count_the_runs_beyond_the_tolerance():
    rows = [_row(0.01, point="a"), _row(0.17, point="b"), _row(-0.005, "meso", "a")]
    lines = mesh_lines(rows)
    assert lines[0].startswith("  mesh (runs again with contact elements 2x shorter")
    macro = next(ln for ln in lines if "macro" in ln)
    assert "+9.0 % on average" in macro and "largest +17.0 %" in macro
    assert "(0.2 -> 0.234, b)" in macro and "1 of 2 beyond" in macro
    meso = next(ln for ln in lines if "meso" in ln)
    assert meso.endswith("converged")
    assert "not mesh-converged" in lines[-1]
    # first-order estimate of the fine run's own error: change / (factor - 1)
    assert _row(0.17, factor=2).fine_error == pytest.approx(0.17)
    assert _row(0.3, factor=4).fine_error == pytest.approx(0.1)
    assert mesh_lines([]) == ["  mesh: no run checked (none selected, or none succeeded)"]
    closed = replace(_row(0.0, "micro"), attempt="closed form", attempt_fine="closed form")
    assert "closed form (driver.sliding.shortcut): no mesh" in mesh_lines([closed])[1]


def test_with_mesh_lines_replaces_the_block_or_appends_it():
    new = ["  mesh (new):", "    up   macro    x"]
    summary = ["head", "  stationarity", MESH_NOT_CHECKED, "  tail line"]
    assert with_mesh_lines(summary, new) == ["head", "  stationarity", *new, "  tail line"]
    earlier = ["head", "  mesh (old):", "    up   macro    y", "    not mesh-converged", "  end"]
    assert with_mesh_lines(earlier, new) == ["head", *new, "  end"]
    assert with_mesh_lines(["head"], new) == ["head", *new]


def test_mesh_selection_default_grammar_and_refusals(tmp_path: Path):
    scene = parse_scene(two_sines("sel", [100.0]))
    (item,) = mesh_selection("", scene)
    assert (item.branch, item.scale, item.sample) == ("up", None, 0)
    (item,) = mesh_selection("down:macro", scene)
    assert (item.branch, item.scale, item.sample) == ("down", "macro", None)
    with pytest.raises(SceneError, match="--mesh-check 'up:nano:0': no scale 'nano'"):
        mesh_selection("up:nano:0", scene)
    with pytest.raises(SceneError, match=r"mesh factor 1 \(--mesh-factor"):
        mesh_selection("", scene, 1)
    scene_file = _scene_file(tmp_path)
    assert main(["run", str(scene_file), "--mesh-check", "--mesh-factor", "1"]) == 2
