"""Thermomechanical macro run (``driver.thermal.macro``): a viscoelastic block (4 x 2 mm, 16 contact
elements) sliding 8 mm over a flat rigid road at p = 0.3 MPa with a friction law that falls with
temperature, mu(T) = 0.6 - 0.003 (T - T0) (clipped at 0.1), kappa = 1, h_c = 1e6, staggered
heat steps.  Each test states what it checks and its tolerance."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from rubberfriction.driver.fe.friction_law import fit_mu_pvT
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.fe.contact import ThermalSettings
from rubberfriction.driver.thermal.macro import THESIS_INTERFACE, MacroSettings, run_thermal_macro
from rubberfriction.forms.material_files import load_compound, load_road
from rubberfriction.validation import InputError

T0 = 293.15
COMPOUND = load_compound("tread_default")
ROAD = load_road("r1").thermal
_T = np.linspace(273.0, 473.0, 11)
LAW = fit_mu_pvT([0.0, 10.0], [1e-6, 1e5], _T,
                 np.broadcast_to(np.clip(0.6 - 0.003 * (_T - T0), 0.1, None),
                                 (2, 2, _T.size)).copy(), degree=1)
SETTINGS = MacroSettings(road=ROAD, T0=T0, road_depth=4.0, road_behind=4.0, road_ahead=1.0)


def _spec(velocity: float, step: float = 0.125) -> SlidingSpec:
    return SlidingSpec(surface_x=np.array([-40.0, 60.0]), surface_h=np.array([0.0, 0.0]),
                       period=0.0, pressure=0.3, velocity=velocity, compound=COMPOUND,
                       block_length=4.0, block_height=2.0, friction=LAW, h_contact=0.25,
                       slide_distance=8.0, step_length=step)


@pytest.fixture(scope="module")
def fast():
    res = run_thermal_macro(_spec(1000.0), COMPOUND.thermal, SETTINGS)
    assert res.ok, (res.sliding.reason, res.stats)
    return res


def _law_at_profile(res) -> float:
    """Pressure x weight averaged law at the final nodal block surface temperatures."""
    p = res.profiles
    w = np.full(len(p["x"]), 0.25)
    w[[0, -1]] = 0.125
    pw = p["pressure"] * w
    return float(pw @ LAW(np.full(len(pw), 0.3), 1000.0, p["T_block"]) / pw.sum())


def test_coupled_mu_is_the_law_at_the_computed_surface_temperature(fast):
    """At 1 m/s the contact heats by > 5 K (measured 7.6 K); the steady contact mu (-F_x/F_z of
    the contact, last step) equals the pressure-weighted law at the computed surface temperatures
    within 0.5 % (the one-step lag of the staggered scheme included), and lies > 2 % below mu(T0)
    = 0.6."""
    s = fast.series
    assert s["T_contact"][-1] > T0 + 5.0
    assert abs(s["mu"][-1] - _law_at_profile(fast)) <= 0.005 * _law_at_profile(fast)
    assert s["mu"][-1] < 0.98 * 0.6


def test_heat_input_is_the_contact_dissipation_and_is_stored(fast):
    """The heat put into the bodies is the contact's frictional dissipation (1e-10 relative); until
    heated road reaches the outflow face (road moved < 4 mm) it is all stored (1e-6 relative:
    the block top at T0 is reached by diffusion only after ~h^2/chi = 30 s, the run lasts 10 ms)."""
    s = fast.series
    assert fast.sliding.stats["cutbacks"] == 0
    assert fast.stats["max_power_rescale"] < 1e-10
    np.testing.assert_allclose(s["friction_energy"], s["contact_dissipation"], rtol=1e-10)
    early = (s["s"] < 2.0) & (s["friction_energy"] > 0)
    stored = s["heat_block"][early] + s["heat_road"][early]
    np.testing.assert_allclose(stored, s["friction_energy"][early], rtol=1e-5)


def test_contact_loads_carry_the_block_and_the_law_sees_their_temperatures(fast):
    """The per-step contact record behind the hot-layer law's tail rule: one row per series row;
    the loads of the slave nodes in contact add up to the applied normal load p l = 1.2 N/mm
    (equilibrium, 1e-4 relative every step after the first; measured 4e-5, nodal pressure times
    weight against the mortar's integrated force); the hottest recorded node is the run's
    ``T_contact_max``."""
    T, load = fast.contact_loads["T"], fast.contact_loads["load"]
    assert T.shape == load.shape and T.shape[0] == len(fast.series["s"])
    np.testing.assert_allclose(load[1:].sum(axis=1), 0.3 * 4.0, rtol=1e-4)
    assert np.max(np.where(load > 0.0, T, -np.inf)) == fast.stats["T_contact_max"]


def test_staggered_scheme_converges_with_the_sliding_step(fast):
    """Halving the sliding step (0.125 -> 0.0625 mm) changes the final contact temperature rise by
    < 1 % and mu by < 0.2 %: the one-step lag of the coupling is small at the default step."""
    half = run_thermal_macro(_spec(1000.0, step=0.0625), COMPOUND.thermal, SETTINGS)
    assert half.ok
    rise, rise_h = fast.series["T_contact"][-1] - T0, half.series["T_contact"][-1] - T0
    assert abs(rise - rise_h) < 0.01 * rise_h
    assert abs(fast.series["mu"][-1] - half.series["mu"][-1]) < 0.002 * half.series["mu"][-1]
    assert half.stats["max_step_dT"] < fast.stats["max_step_dT"]


def test_slow_sliding_reproduces_the_isothermal_run():
    """At v = 1 um/s the frictional power is ~1e-4 mW/mm^2, the contact stays within 0.01 K of T0,
    and mu_force equals that of the isothermal run with the same law at T0 within 1e-4."""
    spec = _spec(1e-3)
    hot = run_thermal_macro(spec, COMPOUND.thermal, SETTINGS)
    assert hot.ok
    assert np.nanmax(hot.series["T_max"]) - T0 < 0.01
    iso = run_sliding(replace(spec, temperature=T0))
    assert iso.ok
    assert abs(hot.sliding.mu_force - iso.mu_force) <= 1e-4 * iso.mu_force


def test_one_interface_type_with_the_thesis_default():
    """The macro scale's interface is the contact's ThermalSettings; its default is thesis 8.3.1
    (kappa = 1, h_c = 1e6 mW/(mm^2 K)), and the type itself has no default heat share."""
    assert MacroSettings(road=ROAD).interface == THESIS_INTERFACE
    assert (THESIS_INTERFACE.kappa, THESIS_INTERFACE.h0, THESIS_INTERFACE.h1) == (1.0, 1.0e6, 0.0)
    with pytest.raises(TypeError, match="kappa"):
        ThermalSettings(h0=1.0)


def test_bad_thermal_input_names_the_field():
    with pytest.raises(InputError, match=r"thermal\.interface\.kappa"):
        MacroSettings(road=ROAD, interface=ThermalSettings(h0=1.0e6, kappa=1.2))
    with pytest.raises(InputError, match=r"thermal\.interface\.h0"):
        MacroSettings(road=ROAD, interface=ThermalSettings(h0=-1.0, kappa=1.0))
    with pytest.raises(InputError, match=r"thermal\.interface: h1 = 2"):
        MacroSettings(road=ROAD, interface=ThermalSettings(h0=1.0, kappa=1.0, h1=2.0))
    with pytest.raises(InputError, match="thermal.road_depth"):
        MacroSettings(road=ROAD, road_depth=0.0)
    with pytest.raises(InputError, match="period"):
        run_thermal_macro(replace(_spec(1.0), period=4.0), COMPOUND.thermal, SETTINGS)
    with pytest.raises(ValueError, match="thermal.road"):
        MacroSettings(road=None)


def test_repeated_slides_carry_the_block_temperature_through_pauses():
    """Thesis 8.5.2: slides with pauses, the block lifted (conduction only, top at T0) and the road
    fresh each slide.  A short pause (1 ms) carries the heat: the second slide ends hotter than the
    first; the surface cools monotonically during a pause; after a pause much longer than the
    block's diffusion time h^2/chi = 32 s (2000 s) the block is back at T0 (0.01 K) and the second
    slide repeats the first (end contact rise within 1 %, mu within 1e-3)."""
    from rubberfriction.driver.thermal.macro import run_thermal_slides

    spec = replace(_spec(1000.0), slide_distance=4.0)
    short = run_thermal_slides(spec, COMPOUND.thermal, SETTINGS, (1e-3,))
    assert short.ok and len(short.slides) == 2
    first, second = (r.series["T_contact"][-1] - T0 for r in short.slides)
    assert second > first + 0.1
    long = run_thermal_slides(spec, COMPOUND.thermal, SETTINGS, (2000.0,))
    assert long.ok
    h = long.history
    pause = h["slide"] == 0
    assert np.all(np.diff(h["T_surface"][pause]) <= 1e-9)  # K, round-off near T0
    assert h["T_surface"][pause][-1] - T0 < 0.01
    a, b = long.slides
    assert abs((b.series["T_contact"][-1] - T0) - (a.series["T_contact"][-1] - T0)) < 0.01 * (
        a.series["T_contact"][-1] - T0)
    assert abs(b.series["mu"][-1] - a.series["mu"][-1]) < 1e-3
    assert np.all(np.diff(h["t"]) > 0)
    with pytest.raises(InputError, match="pause"):
        run_thermal_slides(spec, COMPOUND.thermal, SETTINGS, (-1.0,))


def test_bulk_relaxation_follows_the_heat_field(fast):
    """Thermo-viscoelastic bulk: the cell temperatures come from the heat field (bilinear at the
    centroids, so bounded by the nodal values: above T0 and below the hottest surface node; the
    first cell row's centroids lie 0.125 mm deep, below most of the 10 ms heat penetration depth
    sqrt(chi t) ~ 0.03 mm, so the rise there is small: measured 0.011 K) and the map reproduces a
    bilinear field exactly (1e-12)."""
    from rubberfriction.driver.thermal.macro import _bilinear_map

    assert fast.stats["bulk_wlf"] == 1.0
    assert T0 + 1e-3 < fast.stats["bulk_T_max"] < fast.series["T_max"].max()
    xs, zs = np.linspace(0.0, 4.0, 17), np.array([0.0, 0.01, 0.03, 0.1, 0.5, 2.0])
    rng = np.random.default_rng(1)
    x, z = rng.uniform(0, 4, 50), rng.uniform(0, 2, 50)
    f = lambda a, b: 300.0 + 2.0 * a - 7.0 * b + 0.5 * a * b  # noqa: E731
    W = _bilinear_map(xs, zs, x, z)
    np.testing.assert_allclose(W @ f(xs[:, None], zs[None, :]).ravel(), f(x, z), atol=1e-12)


def test_rounded_leading_edge(fast):
    """A 1 mm rounded front edge (arc nodes lumped onto the heat interface node below them): the
    heat input is still the contact's dissipation (1e-10), the steady contact mu is the law at the
    computed surface temperatures (0.5 %), and the square corner's hot spot (pressure peak at zero
    contact time) is gone: the hottest surface node is cooler than the square block's (measured
    +9.2 K against +9.9 K)."""
    res = run_thermal_macro(replace(_spec(1000.0), edge_radius=1.0), COMPOUND.thermal, SETTINGS)
    assert res.ok, (res.sliding.reason, res.stats)
    s = res.series
    np.testing.assert_allclose(s["friction_energy"], s["contact_dissipation"], rtol=1e-10)
    assert abs(s["mu"][-1] - _law_at_profile(res)) <= 0.005 * _law_at_profile(res)
    assert s["T_contact"][-1] > T0 + 5.0
    assert s["T_max"][-1] < fast.series["T_max"][-1]
