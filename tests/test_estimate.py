"""Wall-time estimate of ``run --check`` (driver/multiscale/estimate.py, issue 45 item 5).

Exact properties of the estimate, not its accuracy (that is measured in docs/performance.md):
the plan holds exactly the runs ``runs_per_point`` counts; without stored runs a run costs
SECONDS_PER_UNIT x ``cost_model`` of its scale's first sample; a stored run of the current
version with the same label costs nothing, the other samples and points of that branch and
scale get the measured mean, the other scales the model weight times the measured ratio
(``CostEstimate``); the wall time is max(CPU / ranks, critical path).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from rubberfriction.driver.multiscale.campaign import check_scene, runs_per_point
from rubberfriction.driver.multiscale.specs import points
from rubberfriction.driver.multiscale.estimate import SECONDS_PER_UNIT, estimate_wall_time
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.sliding.spec import cost_model


def _weight(scene, scales, i: int) -> float:
    """cost_model of scale i's first sample, as RoughCascade.plan weighs its stages."""
    pt = points(scene)[0]
    spec = SpecBuilder(scene, load_compounds(scene))(pt, i, scales.sets[i].samples[0],
                                                     pt.pressure, None, "down")
    return cost_model(spec)


def test_the_model_is_the_cascade_weight_in_seconds() -> None:
    scene = load_scene("default")
    scales = check_scene(scene)
    est = estimate_wall_time(scene, scales)
    for i, sc in enumerate(scales.sets):
        runs = [r for r in est.runs if r.scale == sc.name]
        expected = SECONDS_PER_UNIT * _weight(scene, scales, i)
        assert runs and all(r.seconds == pytest.approx(expected, rel=1e-12) for r in runs)


def test_the_plan_holds_the_runs_of_the_scene() -> None:
    scene = load_scene("default")
    scales = check_scene(scene)
    est = estimate_wall_time(scene, scales, ranks=2)
    per, _ = runs_per_point(scene)
    assert len(est.runs) == per * len(points(scene))
    assert est.count("model") == len(est.runs)
    assert est.wall_seconds == pytest.approx(max(est.cpu_seconds / 2, est.critical_path))
    assert 0 < est.critical_path <= est.cpu_seconds
    one = estimate_wall_time(scene, scales, ranks=1)
    assert one.wall_seconds == pytest.approx(one.cpu_seconds)


def test_stored_runs_are_reused_or_measured(tmp_path: Path) -> None:
    scene = load_scene("default")
    scales = check_scene(scene)
    pt = points(scene)[0]
    store = Store(tmp_path / "store")
    ok = SimpleNamespace(status="ok", reason="")
    label = {"campaign": scene.name, "point": pt.id, "branch": "up", "scale": 1,
             "scale_name": scales.sets[1].name, "sample": 0}
    store.put("a" * 64, None, ok, wall_time=30.0, label=label)
    est = estimate_wall_time(scene, scales, ranks=1, store=store)
    by = {(r.point, r.branch, r.scale, r.sample): r for r in est.runs}
    assert by[(pt.id, "up", scales.sets[1].name, 0)].basis == "stored"
    assert by[(pt.id, "up", scales.sets[1].name, 0)].seconds == 0.0
    # the other friction sample of that scale, and the same scale at other points: measured
    others = [r for r in est.runs if r.branch == "up" and r.scale == scales.sets[1].name
              and r.basis != "stored"]
    assert others and all(r.basis == "measured" and r.seconds == 30.0 for r in others)
    # the other scale: its model weight times the measured seconds per weight
    ratio = 30.0 / _weight(scene, scales, 1)
    macro = [r for r in est.runs if r.scale == scales.sets[0].name]
    assert all(r.basis == "measured" for r in macro)
    assert all(r.seconds == pytest.approx(_weight(scene, scales, 0) * ratio, rel=1e-12)
               for r in macro)


def test_run_check_prints_the_estimate() -> None:
    out = subprocess.run([sys.executable, "-m", "rubberfriction", "run", "default", "--check"],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "estimated wall time:" in out.stdout
