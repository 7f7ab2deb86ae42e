"""Dissipation by depth in a campaign (thesis fig. 6.29 c): every run records it, and each
profile integrates to its run's dissipated energy.

For a frictionless run the window's viscous energy per mm slid and nominal area is mu_energy p
(eq. 2.8), and the stored profile d(z) (mJ/mm^3 per mm slid) integrates over the depth bins to it:
sum_b d_b dz_b = mu_energy p within 1e-6.  With friction in the contact (coarser scales) the
profile is the bulk's share only: it integrates to less than mu_energy p.

The same campaign's ``stationarity_<point>.csv``: the window periods of every run average to the
run's stored value.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from tiny_scenes import two_sines

from rubberfriction.driver.multiscale.campaign import run_scene
from rubberfriction.driver.multiscale.report import depth_edges
from rubberfriction.driver.scenes import parse_scene
from rubberfriction.driver.runtime.store import Store

SCENE = two_sines("diss", [100.0])


def test_every_scale_records_its_dissipation_by_depth(tmp_path: Path):
    scene = parse_scene(SCENE.replace('name = "diss"',
                                      f'name = "diss"\noutput = "{tmp_path / "out"}"'))
    result = run_scene(scene, quiet=True, report=True)
    assert result is not None and all(r.ok for r in result.points)
    store = Store(tmp_path / "out" / "store")
    checked = {"frictionless": 0, "friction": 0}
    for run in store.query(status="ok"):
        if run.label["branch"] != "up":
            continue
        z, d = run.dissipation_by_depth
        integral = float(np.sum(d * np.diff(depth_edges(z))))
        total = run.values["mu_energy"] * run.label["pressure_in"]
        if run.label["friction_in"] == 0.0:
            assert abs(integral - total) <= 1e-6 * total, (run.label, integral, total)
            checked["frictionless"] += 1
        else:
            assert 0.0 < integral < total
            checked["friction"] += 1
    assert checked == {"frictionless": 1, "friction": 1}
    (path,) = (tmp_path / "out").glob("dissipation_*.csv")
    assert (tmp_path / "out" / path.name.replace(".csv", ".png")).is_file()
    rows = list(csv.DictReader(open(path)))
    assert {r["scale_name"] for r in rows} == {"macro", "micro"}
    for name in ("macro", "micro"):
        share = sum(float(r["share"]) for r in rows if r["scale_name"] == name)
        assert abs(share - 1.0) < 1e-5  # the CSV carries 7 significant digits
    # the time homogenisation of the same point: every run's period means of what it waits for
    # (pressure branch: contact fraction; friction branch: mu), whose window periods average to
    # the run's stored value (whole periods of equal steps)
    (path,) = (tmp_path / "out").glob("stationarity_*.csv")
    assert (tmp_path / "out" / path.name.replace(".csv", ".png")).is_file()
    rows = list(csv.DictReader(open(path)))
    keys = {r["key"] for r in rows}
    assert len(keys) == 3  # macro down, micro up, macro up
    for key in keys:
        mine = [r for r in rows if r["key"] == key]
        run = store.load(key)
        quantity = mine[0]["quantity"]
        assert quantity == ("contact_fraction" if run.label["branch"] == "down" else "mu_force")
        window = [float(r["mean"]) for r in mine if r["in_window"] == "True"]
        assert len(window) >= 1 and len(mine) >= 2 * len(window) + 1  # run-in and the w before
        assert np.mean(window) == pytest.approx(run.values[quantity], rel=1e-5)  # 7 digits
