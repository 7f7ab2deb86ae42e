"""Thermal scenes (``[physics].thermal = true`` with a ``[thermal]`` table): validation with errors
that name the field, and one small scene end to end through ``rubberfriction run``."""

from __future__ import annotations

import csv
import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.driver.scenes import SceneError, load_scene, parse_scene
from rubberfriction.driver.multiscale.thermal_scene import friction_of

BASE = """
name = "hot"
[conditions]
compounds = ["tread_default"]
pressures = [0.3]
velocities = [1000.0]
[physics]
thermal = true
[thermal]
"""
SMALL = ("mu = 0.5\nblock_length = 4.0\nblock_height = 2.0\nslide_distance = 4.0\n"
         "road_depth = 3.0\nroad_ahead = 1.0\nroad_behind = 3.0\nprobes_x = [2.0]\n"
         "probes_z = [-0.05]\n")


def _parse(extra: str, base: Path = Path(".")):
    return parse_scene(BASE + extra, "t.toml", base)


@pytest.mark.parametrize("extra, field", [
    ("mu = 0.5\nkappa = 1.5\n", r"\[thermal\]\.kappa"),
    ("mu = 0.5\nh_c = -1.0\n", r"\[thermal\]\.h_c"),
    ("mu = 0.5\npauses = [10.0]\n", r"\[thermal\]\.pauses.*a pause without a slide"),
    ("mu = 0.5\nslides = 3\npauses = [10.0]\n", r"slides without pauses"),
    ("mu = 0.5\nslides = 2\npauses = [-1.0]\n", r"\[thermal\]\.pauses"),
    ("mu = 0.5\nedge_radius = 0.3\n",
     r"\[thermal\]\.edge_radius = 0.3 mm: expected 0 \(square\) or a whole"),
    ("mu = 0.5\nedge_radius = 0.5\n", r"at least 3 of them"),
    ("mu = 0.5\nmu_curve_T = [300.0, 400.0]\nmu_curve_mu = [0.5, 0.4]\n", r"exactly one of mu"),
    ("", r"exactly one of mu"),
    ("mu_curve_T = [300.0, 400.0]\nmu_curve_mu = [0.5]\n", r"mu_curve_T has 2 values"),
    ("mu_curve_T = [400.0, 300.0]\nmu_curve_mu = [0.5, 0.4]\n", r"increasing"),
    ("mu = 0.5\nblock_length = 20.1\n", r"\[thermal\]\.block_length"),
    ("mu = 0.5\nprobes_x = [1.0]\n", r"probes_x"),
    ("mu = 0.5\nkapa = 1.0\n", r"unknown key \[thermal\]\.kapa"),
])
def test_bad_thermal_tables_name_the_field(extra, field):
    with pytest.raises(SceneError, match=field):
        _parse(extra)


def test_repeated_slides_scene_writes_each_slide_and_the_history(tmp_path):
    """slides = 2 with one pause: a folder per slide, history.csv with the pause rows (slide 0)."""
    from rubberfriction.driver.multiscale.thermal_scene import run_thermal_scene

    small = SMALL.replace("slide_distance = 4.0", "slide_distance = 2.0")
    scene = _parse(small + "slides = 2\npauses = [0.5]\n").with_output(tmp_path)
    (row,) = run_thermal_scene(scene, quiet=True)
    assert row.ok
    run = tmp_path / "thermal" / "tread_default_p0.3_v1000"
    h = np.genfromtxt(run / "history.csv", delimiter=",", names=True)
    assert set(np.unique(h["slide"])) == {0.0, 1.0, 2.0} and np.all(np.diff(h["t"]) > 0)
    for k in (1, 2):
        assert (run / f"slide_{k}" / "series.csv").is_file()


def test_given_mu_with_adhesion_is_refused():
    """A given mu is the whole macro friction: a bell law on top would be silently dropped."""
    text = BASE.replace("[physics]\nthermal = true", "[physics]\nthermal = true\nadhesion = true")
    text += "mu = 0.5\n[adhesion]\ntau0 = 1.0\nc = 0.1\nv0 = 10.0\n"
    with pytest.raises(SceneError, match=r"mode = 'given' with \[physics\]\.adhesion = true"):
        parse_scene(text, "t.toml", Path("."))


def test_thermal_true_needs_a_thermal_table():
    text = BASE.replace("[thermal]\n", "")
    with pytest.raises(SceneError, match=r"expected a \[thermal\] table"):
        parse_scene(text, "t.toml", Path("."))


def test_mu_curve_becomes_a_law_linear_in_temperature():
    """mu_curve (T, mu) pairs -> a spline linear between them, constant beyond (clamped)."""
    scene = _parse("mu_curve_T = [300.0, 400.0, 500.0]\nmu_curve_mu = [0.9, 0.5, 0.4]\n")
    law = friction_of(scene)
    T = np.array([250.0, 300.0, 350.0, 450.0, 600.0])
    np.testing.assert_allclose(law(np.full(5, 0.3), np.full(5, 100.0), T),
                               [0.9, 0.9, 0.7, 0.45, 0.4], atol=1e-12)


def test_shipped_thermal_scene_loads():
    scene = load_scene("thermal_macro")
    assert scene.physics.thermal and scene.thermal.mu_curve and scene.thermal.kappa == 1.0


def test_default_road_flash_scenes_differ_only_where_they_say():
    """thermal_road (coupled) and thermal_road_hot_layer (thesis 8.5.3) are captif_stress's road,
    compound, pressure, velocities and numerics with three of its four scales, one sample per scale
    and branch (thesis 8.5.3), twice the slide periods and wall clock per run, and the thermal
    tables; the two differ only in the thermal mode."""
    # captif_stress: the default scene up to 0.16.0 (four scales of the default road, three speeds)
    default, coupled, hot = (load_scene(n)
                             for n in ("captif_stress", "thermal_road", "thermal_road_hot_layer"))
    assert coupled.surface.edges == default.surface.edges[:-1] == (20.0, 3.0, 0.3, 0.04)
    assert ((coupled.surface.source, coupled.surface.seed)
            == (default.surface.source, default.surface.seed))
    assert coupled.conditions == default.conditions
    assert (coupled.samples.pressure, coupled.samples.friction) == (1, 1)
    assert coupled.numerics.max_slide_periods == 2 * default.numerics.max_slide_periods
    assert coupled.numerics.run_timeout == 2 * default.numerics.run_timeout
    assert dataclasses.replace(coupled.numerics, scales=default.numerics.scales,
                               max_slide_periods=default.numerics.max_slide_periods,
                               run_timeout=default.numerics.run_timeout) == default.numerics
    assert coupled.thermal.mode == "coupled" and hot.thermal.mode == "hot-layer"
    assert (coupled.thermal.kappa, coupled.thermal.h_c, coupled.thermal.mu_const) == (0.8, 1.6, 0.0)
    assert dataclasses.replace(hot.thermal, mode="coupled") == coupled.thermal
    assert (hot.surface, hot.samples, hot.conditions, hot.numerics, hot.physics) == \
        (coupled.surface, coupled.samples, coupled.conditions, coupled.numerics, coupled.physics)


def test_missing_thermal_data_of_the_compound_or_road(tmp_path):
    from rubberfriction.driver.multiscale.thermal_scene import run_thermal_scene

    scene = _parse(SMALL).with_output(tmp_path)
    no_thermal = parse_scene((BASE + SMALL).replace('"tread_default"', '"c1"'), "t.toml", Path("."))
    with pytest.raises(SceneError, match=r"compound 'c1' has no \[thermal\]"):
        run_thermal_scene(no_thermal.with_output(tmp_path), quiet=True)
    road = tmp_path / "bare_road.toml"
    road.write_text('kind = "road"\nname = "bare"\nsource = "test"\n[units]\nlength = "mm"\n'
                    'time = "s"\nmass = "t"\nforce = "N"\nstress = "MPa"\nenergy = "mJ"\n'
                    'temperature = "degC"\n'
                    '[elastic]\nE = 1000.0\nnu = 0.2\n')
    bare = _parse(SMALL + f'road = "{road}"\n').with_output(tmp_path)
    with pytest.raises(SceneError, match=r"\[thermal\]\.road"):
        run_thermal_scene(bare, quiet=True)
    assert scene.thermal.probes == ((2.0, -0.05),)


def test_small_thermal_scene_end_to_end(tmp_path):
    """``rubberfriction run`` on a thermal scene with constant mu = 0.5 (4 x 2 mm block, 1 m/s,
    0.3 MPa): exit 0, one ok row; the contact heats (T_C > T0); the series stores the heat put in
    (stored = frictional energy within 1e-5 while no heat can have left); the probe in the road
    under the block warms; the field is written for ParaView and the plots exist; the surface
    history ends with the final interface profile."""
    scene = tmp_path / "hot.toml"
    scene.write_text(BASE + SMALL)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "rubberfriction", "run", str(scene),
                           "--out", str(out)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "[thermal] run 1/1" in proc.stdout
    rows = list(csv.DictReader(open(out / "thermal" / "thermal_results.csv")))
    assert len(rows) == 1 and rows[0]["status"] == "ok"
    assert 0.0 <= float(rows[0]["mu_error"]) < 0.05  # the window average states how steady it is
    # the viscous stabilisation is reported: no stabilised sub-step, no share; the block is whole
    stabilised, share = float(rows[0]["stabilised_steps"]), float(rows[0]["stabilisation_share"])
    assert stabilised >= 0 and (share == 0.0 if stabilised == 0 else share > 0.0)
    assert 0.5 < float(rows[0]["min_det_F"]) <= 1.0 + 1e-9
    T0 = 293.15
    assert float(rows[0]["T_contact"]) > T0 + 1.0
    run = out / "thermal" / "tread_default_p0.3_v1000"
    series = np.genfromtxt(run / "series.csv", delimiter=",", names=True)
    early = (series["s"] < 1.5) & (series["friction_energy"] > 0)
    np.testing.assert_allclose(series["heat_block"][early] + series["heat_road"][early],
                               series["friction_energy"][early], rtol=1e-5)
    assert series["probe_0"][-1] > T0 + 0.1
    for name in ("interface.csv", "temperature.xdmf", "temperature.h5", "thermal.png",
                 "surface_history.png"):
        assert (run / name).is_file(), name
    # the surface history's last row is the final interface profile (1e-7 K: printed digits)
    hist = np.genfromtxt(run / "surface_history.csv", delimiter=",", names=True, dtype=None,
                         encoding=None)
    itf = np.genfromtxt(run / "interface.csv", delimiter=",", names=True)
    last = (hist["s"] == hist["s"].max()) & (hist["body"] == "block")
    np.testing.assert_allclose(hist["x"][last], itf["x"], atol=1e-7)
    np.testing.assert_allclose(hist["T"][last], itf["T_block"], atol=1e-5)
    assert np.isclose(hist["s"].max(), series["s"][-1])


@pytest.mark.mpi
def test_thermal_runs_farmed_over_two_ranks_give_the_serial_table(tmp_path):
    """Given-mode thermal runs dealt out over 2 ranks: thermal_results.csv equals the serial one
    but for the wall times (two velocities, one per rank)."""
    import os

    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMP_NUM_THREADS="1")
    scene = tmp_path / "hot.toml"
    scene.write_text((BASE + SMALL).replace("velocities = [1000.0]",
                                            "velocities = [500.0, 1000.0]"))
    tables = []
    for name, prefix in (("serial", []), ("mpi", ["mpirun", "-n", "2"])):
        proc = subprocess.run(prefix + [sys.executable, "-m", "rubberfriction", "run", str(scene),
                                        "--out", str(tmp_path / name), "--quiet"],
                              env=env, capture_output=True, text=True, timeout=900)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        rows = list(csv.DictReader(open(tmp_path / name / "thermal" / "thermal_results.csv")))
        for r in rows:
            r.pop("wall")
            r.pop("cpu_heat"), r.pop("cpu_contact")
        tables.append(rows)
    assert len(tables[0]) == 2 and tables[0] == tables[1]
