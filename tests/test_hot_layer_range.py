"""The hot-layer law mu(T_S) beyond its highest surface temperature (issue 44, thesis 8.5.3).

The macro run's friction law is a spline through the grid's mu(T_S) (``fit_mu_pvT``), which would
hold mu(T_top) beyond the grid: no physics.  So the law is never used there: when the macro
contact's hottest node got hotter than the highest tabulated T_S, ``run_hot_layer`` adds a
cascade at twice the largest rise and redoes the macro run with the extended law, at most
``MAX_LAW_EXTENSIONS`` times; a run still beyond it refuses the point with a one-line reason,
unless the load on the nodes beyond bounds their effect on mu within ``LAW_TAIL_TOL``.
Nothing here runs FE: the cascades and the macro run are stand-ins with known temperatures.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

from rubberfriction.driver.multiscale import thermal_loop as TL
from rubberfriction.driver.multiscale.results import Point

T0 = 293.15
# lower scales' mu at T0 + rise: the grid (0, 10, 20) and its doublings (40, 80)
MU = {0.0: 0.40, 10.0: 0.38, 20.0: 0.35, 40.0: 0.31, 80.0: 0.25}
GRID = (0.0, 10.0, 20.0)


@dataclass(frozen=True)
class Spec:
    friction: object = None


class Cascade:
    """One stand-in result per hot-layer partition: mu from MU at the partition's T_S (nan where
    ``fail`` holds that rise); records the rises of every call."""

    point = Point("tread_default", 0.3, 1000.0)

    def __init__(self, fail: tuple[float, ...] = ()):
        self.calls: list[list[float]] = []
        self.fail = fail

    def many(self, partitions):
        out, rises = [], []
        for part in partitions:
            rise = round(part.layers[0][1] - T0, 6)
            rises.append(rise)
            mu = float("nan") if rise in self.fail else MU[rise]
            out.append(SimpleNamespace(ok=mu == mu, mu=SimpleNamespace(mean=mu), wall_time=0.0,
                                       reason="stand-in failure"))
        self.calls.append(rises)
        return out


def _run(monkeypatch: pytest.MonkeyPatch, seen: list[float], fail: tuple[float, ...] = (),
         hot_share: float | None = None, mean_rise: float = 10.0):
    """run_hot_layer with a macro stand-in whose k-th run's hottest contact node is seen[k]
    (the last value repeats); returns the result, the laws the macro runs got and the cascade.
    The stand-in slides 10 mm in 100 steps with the contact at T0 + ``mean_rise``; with
    ``hot_share`` it also records its contact loads: that share of the load on one node at
    seen[k], the rest on nine nodes at T0 + 10 K."""
    laws: list = []

    def macro(spec, rubber, thermal, wall_limit=0.0):
        laws.append(spec.friction)
        T = seen[min(len(laws), len(seen)) - 1]
        s = np.linspace(0.1, 10.0, 100)
        Tc = np.full(s.size, T0 + mean_rise)
        out = SimpleNamespace(ok=True, series={"T_contact": Tc, "T_active": Tc, "s": s},
                              stats={"T_contact_max": T}, contact_loads={})  # as the real one
        if hot_share is not None:
            nodes_T = np.r_[T, np.full(9, T0 + 10.0)]
            load = np.r_[hot_share, np.full(9, (1.0 - hot_share) / 9.0)]
            out.contact_loads = {"T": np.tile(nodes_T, (s.size, 1)),
                                 "load": np.tile(load, (s.size, 1))}
        return out

    monkeypatch.setattr(TL, "run_thermal_macro", macro)
    cascade = Cascade(fail)
    settings = TL.HotLayerSettings(rises=GRID, mu_const=0.6)
    res = TL.run_hot_layer(Spec(), None, SimpleNamespace(T0=T0), settings, cascade)
    return res, laws, cascade


def test_within_the_grid_the_law_and_the_run_are_unchanged(monkeypatch: pytest.MonkeyPatch):
    res, laws, cascade = _run(monkeypatch, [T0 + 20.0])
    assert len(laws) == 1 and cascade.calls == [list(GRID)]  # one macro run, the grid's cascades
    np.testing.assert_array_equal(res.temperatures, T0 + np.array(GRID))
    assert res.T_law_max == T0 + 20.0 and not res.error and res.ok
    assert not any("hot-layer law" in n for n in res.notes), res.notes
    # the law interpolates linearly between the grid points (eq. 8.1's mu per T_S)
    assert float(laws[0](0.3, 1000.0, T0 + 15.0)) == pytest.approx(0.6 + 0.365, rel=1e-12)


def test_a_hotter_contact_extends_the_law_and_redoes_the_macro_run(monkeypatch):
    """The first macro run reaches T0 + 32.5 K (beyond T0 + 20): the grid gains T0 + 40 K, the
    macro run is redone with the extended law and stays within it (T0 + 30 K)."""
    res, laws, cascade = _run(monkeypatch, [T0 + 32.5, T0 + 30.0])
    assert cascade.calls == [list(GRID), [40.0]]
    assert len(laws) == 2
    np.testing.assert_array_equal(res.temperatures, T0 + np.array([*GRID, 40.0]))
    np.testing.assert_array_equal(res.mu_lower, [MU[r] for r in (*GRID, 40.0)])
    assert len(res.cascades) == 4
    assert res.T_law_max == T0 + 40.0 and not res.error and res.ok
    assert res.law is laws[1]
    # the extended law interpolates to the new point, where the first one was held at mu(T0 + 20)
    assert float(laws[1](0.3, 1000.0, T0 + 30.0)) == pytest.approx(0.6 + 0.33, rel=1e-12)
    assert float(laws[0](0.3, 1000.0, T0 + 30.0)) == pytest.approx(0.6 + 0.35, rel=1e-12)
    assert any(n.startswith("the hot-layer law was extended to T0 +40 K: the contact had "
                            "reached T0 +32.5 K") for n in res.notes), res.notes


def test_a_contact_beyond_the_extended_law_refuses_the_point(monkeypatch: pytest.MonkeyPatch):
    """Every macro run reaches T0 + 500 K: two extensions (T0 + 40, + 80 K), three macro runs,
    then the point is refused (mu nan, status failed) with the temperatures and the key."""
    res, laws, cascade = _run(monkeypatch, [T0 + 500.0])
    assert cascade.calls == [list(GRID), [40.0], [80.0]]
    assert len(laws) == 1 + TL.MAX_LAW_EXTENSIONS == 3
    np.testing.assert_array_equal(res.temperatures, T0 + np.array([*GRID, 40.0, 80.0]))
    assert res.T_law_max == T0 + 80.0
    assert res.error == ("refused: the contact reached T0 +500 K, above the hot-layer law's "
                         "highest surface temperature T0 +80 K after 2 extensions (T0 +40, +80 "
                         "K); add higher [thermal].hot_layer_rises values; no contact-load "
                         "history, a bound of inf on mu, above 1 % of it")
    assert "\n" not in res.error and res.error in res.notes
    assert not res.ok and np.isnan(res.mu) and np.isnan(res.mu_end)


def test_a_hot_node_with_little_load_is_bounded_and_accepted(monkeypatch: pytest.MonkeyPatch):
    """The hottest node (T0 + 500 K, beyond the extended law's T0 + 80 K) carries 2 % of the
    load.  There the macro run held mu_const + 0.25 (the law's top), the true value lies
    between mu_const and that (the law falls at its top, hysteresis >= 0): the point's mu
    (0.6 + 0.38 at T0 + 10 K) moves by at most 0.02 x 0.25 = 0.005, 0.51 % < 1 %: accepted,
    and the note states the share and the bound."""
    res, laws, _ = _run(monkeypatch, [T0 + 500.0], hot_share=0.02)
    assert len(laws) == 3 and not res.error and res.ok
    assert res.mu == pytest.approx(0.98, rel=1e-12)
    note = next(n for n in res.notes if "of the normal load" in n)
    assert note.startswith("2 % of the normal load over the averaging window lay on contact "
                           "nodes hotter than the law's T0 +80 K")
    assert "at most 0.005 (0.51 %, accepted within 1 %)" in note


def test_a_hot_node_with_much_load_refuses_the_point(monkeypatch: pytest.MonkeyPatch):
    """The same with 10 % of the load on the hot node: bound 0.025, 2.5 % of mu > 1 %."""
    res, _, _ = _run(monkeypatch, [T0 + 500.0], hot_share=0.1)
    assert res.error.startswith("refused: the contact reached T0 +500 K")
    assert res.error.endswith("10 % of the normal load over the averaging window lay on contact "
                              "nodes hotter than the law's T0 +80 K, where the macro run held "
                              "its top value, a bound of 0.025 on mu, above 1 % of it")
    assert not res.ok and np.isnan(res.mu)


def test_a_mean_contact_beyond_the_law_refuses_the_point(monkeypatch: pytest.MonkeyPatch):
    """On the flat road the point's mu is the law at eq. 8.1's mean contact temperature: when
    that mean itself lies beyond the extended law (here T0 + 90 K > T0 + 80 K), no load share
    can save the point."""
    res, _, _ = _run(monkeypatch, [T0 + 500.0], hot_share=0.001, mean_rise=90.0)
    assert res.error.endswith("the point's own contact temperature (eq. 8.1) reached T0 +90 K "
                              "in the averaging window")
    assert not res.ok


def test_the_tail_bound_needs_a_law_falling_at_its_top() -> None:
    """|d mu| <= share x m_top only when the lower scales' mu falls between its two hottest
    grid points; a law rising there gives no bound (inf), nor does an unknown share."""
    assert TL.law_tail_bound(0.04, np.array([0.5, 0.3, 0.2])) == pytest.approx(0.008)
    assert TL.law_tail_bound(0.04, np.array([0.5, 0.2, 0.3])) == float("inf")
    assert TL.law_tail_bound(float("nan"), np.array([0.5, 0.3])) == float("inf")


def test_a_failed_extension_refuses_the_point(monkeypatch: pytest.MonkeyPatch):
    res, laws, cascade = _run(monkeypatch, [T0 + 32.5], fail=(40.0,))
    assert cascade.calls == [list(GRID), [40.0]] and len(laws) == 1
    assert res.error.startswith("refused: the contact reached T0 +32.5 K, above the hot-layer "
                                "law's highest surface temperature T0 +20 K, and the cascade "
                                "extending it to T0 +40 K failed (stand-in failure)")
    assert "hot_layer_rises" in res.error and not res.ok


@pytest.mark.parametrize("T_seen, beyond", [(T0 + 20.0, False), (T0 + 20.001, True),
                                            (float("nan"), False), (T0, False)])
def test_law_exceeded(T_seen: float, beyond: bool) -> None:
    assert TL.law_exceeded(T0 + 20.0, T_seen) is beyond
