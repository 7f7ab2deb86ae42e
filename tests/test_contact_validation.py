"""Bad input fails early with a message that names the problem."""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction import _contact
from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.fe.contact import (Contact, PenaltySettings, RigidMaster, SlaveSurface,
                                              ThermalSettings)

PEN = PenaltySettings(c_N=10.0)


def slave(n=5, X=None, segments=None, interior=None):
    x = np.linspace(0.0, 1.0, n)
    X = np.column_stack([x, np.zeros(n)]) if X is None else X
    seg = np.column_stack([np.arange(n - 1), np.arange(1, n)]) if segments is None else segments
    return SlaveSurface(X, np.arange(2 * n).reshape(n, 2), seg, interior_points=interior)


def flat():
    return RigidMaster(np.array([[-1.0, 0.0], [2.0, 0.0]]))


@pytest.mark.parametrize("vertices,period,match", [
    ([[0.0, 0.0], [np.nan, 0.1], [1.0, 0.0]], 0.0, "not finite"),
    ([[0.0, 0.0], [np.inf, 0.1]], 0.0, "not finite"),
    ([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]], 0.0, "zero length"),
    ([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, -1.0]], 0.0, "self-intersecting"),  # crosses itself
    ([[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]], 0.0, "self-intersecting"),  # folds back onto itself
    ([[0.0, 0.0], [0.5, 0.1], [1.0, 0.0]], 0.8, "does not match"),  # sample longer than the period
    # wrap segment far too long
    ([[0.0, 0.0], [0.1, 0.1], [0.2, 0.0], [0.3, 0.05]], 5.0, "does not match"),
    # last vertex at x0 + L but z differs
    ([[0.0, 0.0], [0.5, 0.1], [1.0, 0.3]], 1.0, "not periodic"),
    ([[0.0, 0.0], [1.0, 0.0]], -1.0, "period must be"),
])
def test_bad_polylines(vertices, period, match):
    with pytest.raises(ValueError, match=match):
        Contact(slave(), RigidMaster(np.array(vertices), period), penalty=PEN)


def test_periodic_sample_with_closing_vertex_is_accepted():
    x = np.linspace(0.0, 1.0, 11)
    c = Contact(slave(), RigidMaster(np.column_stack([x, np.sin(2 * np.pi * x)]), 1.0), penalty=PEN)
    r = c.report()["master"]
    assert r["dropped_closing_vertex"] and r["segments"] == 10


def test_periodic_fold_back_across_the_boundary():
    # the first segment runs back along the wrap-around segment of the previous period
    V = np.array([[0.0, 0.0], [-0.05, 0.0], [0.5, 0.2], [0.9, 0.0]])
    with pytest.raises(ValueError, match="self-intersecting"):
        Contact(slave(), RigidMaster(V, 1.0), penalty=PEN)


@pytest.mark.parametrize("kwargs,match", [
    ({"penalty": PenaltySettings(c_N=-1.0)}, "c_N = -1"),
    ({"penalty": PenaltySettings(c_N=0.0)}, "c_N = 0"),
    ({"penalty": PenaltySettings(c_N=10.0, c_T=-2.0)}, "c_T = -2"),
    ({"penalty": PenaltySettings(c_N=float("nan"))}, "c_N = nan"),
    ({"penalty": PenaltySettings(alpha=-5.0), "E_eff": 3.0}, "alpha = -5"),
    ({"penalty": PenaltySettings(), "E_eff": -3.0}, "E_eff = -3"),
    ({"penalty": PenaltySettings()}, "E_eff"),
    ({"penalty": PEN, "search_radius": -0.1}, "search radius"),
    ({"penalty": PEN, "thermal": ThermalSettings(h0=-1.0, kappa=0.5)}, "h0 = -1"),
    ({"penalty": PEN, "thermal": ThermalSettings(h0=1.0, kappa=1.5)}, "kappa = 1.5"),
    ({"penalty": PEN, "thermal": ThermalSettings(h0=1.0, kappa=0.5, beta=0.5)}, "beta = 0.5"),
    ({"penalty": PEN, "method": "lagrange"}, "method"),
])
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Contact(slave(), flat(), **kwargs)


@pytest.mark.parametrize("n", [0, 9, -1])
def test_gauss_points_outside_the_table(n):
    with pytest.raises(ValueError,
                       match=f"Gauss points per segment piece: got {n}, expected 1 to 8"):
        Contact(slave(), flat(), penalty=PEN, gauss_points=n)


def test_every_order_of_the_gauss_table_is_accepted():
    for n in range(1, 9):
        assert Contact(slave(), flat(), penalty=PEN, gauss_points=n).report()["gauss_points"] == n


def test_bad_slave_surfaces():
    with pytest.raises(ValueError, match="zero length"):
        Contact(slave(X=np.array([[0.0, 0], [0.5, 0], [0.5, 0], [0.8, 0], [1, 0]])), flat(),
                penalty=PEN)
    with pytest.raises(ValueError, match="non-finite"):
        Contact(slave(X=np.array([[0.0, 0], [0.5, 0], [np.nan, 0], [0.8, 0], [1, 0]])), flat(),
                penalty=PEN)
    # inconsistent orientation: node 2 starts two segments
    with pytest.raises(ValueError, match="counter-clockwise"):
        Contact(slave(segments=np.array([[0, 1], [2, 1], [2, 3], [3, 4]])), flat(), penalty=PEN)
    # consistently clockwise: detected with interior points (the body is above the bottom face)
    seg = np.column_stack([np.arange(1, 5), np.arange(0, 4)])
    with pytest.raises(ValueError, match="oriented clockwise"):
        Contact(slave(segments=seg, interior=np.full((4, 2), [0.5, 0.3])), flat(), penalty=PEN)
    with pytest.raises(ValueError, match="refers to a node"):
        Contact(slave(segments=np.array([[0, 1], [1, 7]])), flat(), penalty=PEN)
    with pytest.raises(ValueError, match="used twice"):
        Contact(SlaveSurface(np.array([[0.0, 0], [1, 0]]), np.array([[0, 1], [1, 2]]),
                             np.array([[0, 1]])),
                flat(), penalty=PEN)


def test_bad_runtime_input():
    c = Contact(slave(), flat(), penalty=PEN)
    with pytest.raises(ValueError, match="solution array has 4 entries"):
        c.evaluate(np.zeros(4))
    u = np.zeros(10)
    u[3] = np.nan
    with pytest.raises(ValueError, match="non-finite displacement"):
        c.evaluate(u)
    law, *_ = (fl.fit_mu_pv(np.linspace(0, 1, 4), np.logspace(-1, 1, 4), np.full((4, 4), 0.5)),)
    cv = Contact(slave(), flat(), penalty=PEN, friction=law)
    with pytest.raises(ValueError, match="dt must be > 0"):
        cv.evaluate(np.zeros(10))
    with pytest.raises(ValueError, match="friction needs a tangential penalty"):
        Contact(slave(), flat(), penalty=PenaltySettings(c_N=10.0, c_T=0.0),
                friction=0.3).evaluate(np.zeros(10))
    with pytest.raises(ValueError, match="temperature dofs"):
        Contact(slave(), flat(), penalty=PEN,
                thermal=ThermalSettings(h0=1.0, kappa=0.5)).evaluate(np.zeros(10))


def test_bad_friction_laws():
    with pytest.raises(ValueError, match="mu must be finite and >= 0"):
        _contact.ConstantFriction(-0.1)
    with pytest.raises(ValueError, match="coefficients"):
        fl.SplineLaw([np.r_[0, 0, 1, 1], np.r_[0, 0, 1, 1]], [1, 1], np.zeros(5))
    with pytest.raises(ValueError, match="non-decreasing"):
        fl.SplineLaw([np.r_[0, 0, 1, 0.5], np.r_[0, 0, 1, 1]], [1, 1], np.zeros(4))
    with pytest.raises(ValueError, match="log10 axis needs values > 0"):
        fl.fit_mu_pv([0.1, 0.2], [0.0, 1.0], np.ones((2, 2)))
    with pytest.raises(TypeError, match="friction"):
        Contact(slave(), flat(), penalty=PEN, friction="coulomb")
