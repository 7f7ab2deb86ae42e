"""The hot-layer law mu(T_S) beyond its highest surface temperature (issue 44, thesis 8.5.3).

The macro run's friction law is a spline through the grid's mu(T_S) (``fit_mu_pvT``), clamped
beyond the grid: mu stays at mu(T_top) with zero slope.  That is no physics, so the point says
so: when the macro contact got hotter than the highest tabulated T_S, ``run_hot_layer`` adds a
warning to the result's notes (the ``loop_results.csv`` notes column and the log).  Nothing here
runs FE: the cascades and the macro run are stand-ins with known temperatures.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

from rubberfriction.driver.multiscale import thermal_loop as TL
from rubberfriction.driver.multiscale.results import Point

T0 = 293.15
MU = {0.0: 0.40, 10.0: 0.38, 20.0: 0.35}  # lower scales' mu at T0 + rise


@dataclass(frozen=True)
class Spec:
    friction: object = None


class Cascade:
    """One stand-in result per hot-layer partition: mu from MU at the partition's T_S."""

    point = Point("tread_default", 0.3, 1000.0)

    def many(self, partitions):
        out = []
        for part in partitions:
            T_S = part.layers[0][1]
            mu = MU[round(T_S - T0, 6)]
            out.append(SimpleNamespace(ok=True, mu=SimpleNamespace(mean=mu), wall_time=0.0))
        return out


def _run(monkeypatch: pytest.MonkeyPatch, T_contact_max: float):
    def macro(spec, rubber, thermal, wall_limit=0.0):
        macro.law = spec.friction
        T = np.array([T_contact_max - 1.0])
        return SimpleNamespace(ok=True, series={"T_contact": T, "T_active": T,
                                                "s": np.array([1.0])},
                               stats={"T_contact_max": T_contact_max})

    monkeypatch.setattr(TL, "run_thermal_macro", macro)
    settings = TL.HotLayerSettings(rises=tuple(MU), mu_const=0.6)
    res = TL.run_hot_layer(Spec(), None, SimpleNamespace(T0=T0), settings, Cascade())
    return res, macro.law


def test_within_the_grid_no_warning(monkeypatch: pytest.MonkeyPatch) -> None:
    res, law = _run(monkeypatch, T0 + 20.0)
    assert res.T_law_max == T0 + 20.0
    assert not any("hot-layer law" in n for n in res.notes), res.notes
    # the law interpolates linearly between the grid points (eq. 8.1's mu per T_S)
    assert float(law(0.3, 1000.0, T0 + 15.0)) == pytest.approx(0.6 + 0.365, rel=1e-12)


def test_beyond_the_grid_is_a_warning_with_the_numbers(monkeypatch: pytest.MonkeyPatch) -> None:
    res, law = _run(monkeypatch, T0 + 32.5)
    # the law is clamped there (the behaviour the warning reports) ...
    assert float(law(0.3, 1000.0, T0 + 32.5)) == pytest.approx(0.6 + 0.35, rel=1e-12)
    assert float(law.evaluate(0.3, 1000.0, T0 + 32.5)[3]) == 0.0  # dmu/dT
    # ... and the point says so, once, with the temperatures
    notes = [n for n in res.notes if "hot-layer law" in n]
    assert len(notes) == 1, res.notes
    assert notes[0].startswith("warning: the contact reached T0 +32.5 K, 12.5 K above the "
                               "hot-layer law's highest surface temperature T0 +20 K")
    assert "hot_layer_rises" in notes[0]
    assert res.ok  # the point keeps its number: the law is right wherever the contact was cooler


@pytest.mark.parametrize("T_seen, warns", [(T0 + 20.0, False), (T0 + 20.001, True),
                                           (float("nan"), False), (T0, False)])
def test_law_range_note(T_seen: float, warns: bool) -> None:
    assert bool(TL.law_range_note(T0 + 20.0, T_seen, T0)) is warns
