"""`rubberfriction bench cutoff`: the scene cut at each max_slope from the stated edges, and the
table builder's theory columns on exactly the kept spectrum."""

from __future__ import annotations

import math

import pytest

from rubberfriction.driver.bench.cutoff import cut_scene, point_rows
from rubberfriction.driver.scenes import load_scene, override

EDGES = (20.0, 3.0, 0.3, 0.04, 0.003, 0.0002)


def test_cut_scenes_keep_more_scales_for_larger_limits_and_the_theory_follows() -> None:
    base = override(load_scene("four_scale"), conditions={"velocities": (100.0,)})
    lo, mid, hi = (cut_scene(base, m, EDGES) for m in (1.0, 1.3, 2.0))
    assert lo.surface.names == ("macro", "meso", "micro1", "micro2")
    assert hi.surface.names == ("macro", "meso", "micro1", "micro2", "micro3")
    assert lo.surface.edges[-1] > mid.surface.edges[-1] == 0.003 > hi.surface.edges[-1]
    rows = {m: point_rows(s, m, None)[0] for m, s in ((1.0, lo), (2.0, hi))}
    assert math.isnan(rows[1.0]["mu_fe"]) and rows[1.0]["scales"] == 4
    # Persson's hysteresis grows with the spectrum it is given (more slope, more dissipation)
    assert rows[2.0]["mu_persson-2d"] > rows[1.0]["mu_persson-2d"] > 0
    assert rows[2.0]["cumulative_slope"] == pytest.approx(2.0, rel=1e-3)
