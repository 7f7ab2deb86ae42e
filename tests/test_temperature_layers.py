"""Temperature partitions over a block's height (thesis 8.3.3): WLF-shifted relaxation per layer.

Closed forms: the linear viscoelastic strip with layers (transfer matrices of the plane-strain
equations, ``sinusoid.layered_strip_pressure``) reduces to the half-space stiffness E*_eff k / 2
for a deep uniform block; FE sliding runs with layers reproduce it and the uniform closed form.
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.sliding.run import SlidingRun
from rubberfriction.driver.sliding.bodies import block_mesh, sliding_contact
from rubberfriction.driver.sliding.sinusoid import (
    closed_form_mu,
    effective_modulus,
    layered_strip_mu,
    layered_strip_pressure,
)
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.sliding.temperature import (
    MIN_ROW_FRACTION,
    cell_temperatures,
    check_layers,
    layer_levels,
    layer_temperatures,
    mesh_levels,
)
from rubberfriction.driver.verification.viscoelastic_sinusoid import simulate
from rubberfriction.forms.material_files import load_compound

TREAD = load_compound("tread_default")
T_REF = TREAD.wlf.T_ref


def test_layer_temperatures_and_levels():
    """Depth d in [0, 0.1) -> 330 K, [0.1, 0.3) -> 310 K, below -> background; bounds inside."""
    layers = ((0.1, 330.0), (0.2, 310.0))
    depth = np.array([0.0, 0.05, 0.1, 0.2999, 0.3001, 5.0])
    assert layer_temperatures(layers, 293.0, depth).tolist() == [330.0, 330.0, 310.0, 310.0,
                                                                 293.0, 293.0]
    assert layer_levels(layers, 1.0) == pytest.approx([0.1, 0.3])
    assert layer_levels(layers, 0.3) == pytest.approx([0.1])  # the top is not a level
    assert layer_levels(layers, 0.05) == []


def test_cell_temperatures_average_the_layers_over_each_cell():
    """A cell inside a layer gets its temperature exactly; a cell over [0, 0.4] with 0.1 mm at 330 K
    and 0.2 mm at 310 K over a 290 K background gets (0.1 * 330 + 0.2 * 310 + 0.1 * 290) / 0.4;
    a degenerate span takes the temperature at its depth."""
    layers = ((0.1, 330.0), (0.2, 310.0))
    lo = np.array([0.0, 0.12, 0.0, 0.05, 0.5, 0.2])
    hi = np.array([0.1, 0.3, 0.4, 0.15, 0.9, 0.2])
    T = cell_temperatures(layers, 290.0, lo, hi)
    expected = [330.0, 310.0, (0.1 * 330 + 0.2 * 310 + 0.1 * 290) / 0.4, 320.0, 290.0, 310.0]
    np.testing.assert_allclose(T, expected, rtol=1e-14)
    assert cell_temperatures((), 290.0, lo, hi).tolist() == [290.0] * 6


def test_layer_bounds_thinner_than_the_mesh_resolves_are_not_mesh_lines():
    """Bounds closer than min_row to the face, to the last kept bound or to the top are dropped."""
    layers = ((0.0225, 330.0), (0.0225, 320.0), (0.0225, 310.0), (0.0225, 300.0))
    assert mesh_levels(layers, 20.0, 0.125) == []  # the 20-3 mm band: contact spacing 0.5 mm
    assert mesh_levels(layers, 3.0, 0.0125) == pytest.approx([0.0225, 0.045, 0.0675, 0.09])
    assert mesh_levels(layers, 3.0, 0.03) == pytest.approx([0.045, 0.09])
    assert mesh_levels(layers, 0.1, 0.03) == pytest.approx([0.045])  # 0.09 is 0.01 below the top


def test_thin_layers_on_a_coarse_cell_average_into_its_rows():
    """The thesis' partitions (4 x 0.0225 mm) on a cell meshed with 0.25 mm contact elements: no
    element row is thinner than MIN_ROW_FRACTION of the contact spacing (before: 0.0225 mm, an
    aspect ratio of 11); only the bound at 0.0675 mm stays a mesh line.  Each cell carries the
    thickness-weighted mean temperature of the layers it spans, so the heat of the partitions is
    kept: over a column of cells, sum (T - T0) dz equals sum (T_i - T0) d_i to round-off."""
    x = np.linspace(0.0, 2.0, 129)[:-1]
    layers = ((0.0225, T_REF + 40.0), (0.0225, T_REF + 30.0), (0.0225, T_REF + 20.0),
              (0.0225, T_REF + 10.0))
    hc = 0.25
    spec = SlidingSpec(surface_x=x, surface_h=0.02 * np.cos(np.pi * x), period=2.0, pressure=0.1,
                       velocity=10.0, compound=TREAD, h_contact=hc, temperature_layers=layers,
                       temperature=T_REF)
    run = SlidingRun(spec, block_mesh, sliding_contact)
    run.build("mortar")
    assert mesh_levels(layers, run.H, MIN_ROW_FRACTION * hc) == pytest.approx([0.0675])
    z0 = float(np.max(spec.surface_h))
    lo, hi = run.sp.cell_bounds(axis=1) - z0
    assert (hi - lo).min() >= MIN_ROW_FRACTION * hc
    T = run.sp.history.T_cell
    np.testing.assert_allclose(T[lo < 1e-12], T_REF + 30.0, rtol=1e-14)  # [0, 0.0675]: 40, 30, 20
    x_lo = run.sp.cell_bounds(axis=0)[0]
    column = x_lo < x_lo.min() + 1e-9
    heat = sum(d * (t - T_REF) for d, t in layers)  # K mm above the background
    assert np.sum((T[column] - T_REF) * (hi - lo)[column]) == pytest.approx(heat, rel=1e-12)
    assert np.all(T[lo >= 0.09] == T_REF)


@pytest.mark.parametrize("layers,compound,message", [
    (((0.0, 300.0),), TREAD, r"temperature_layers\[0\]: thickness"),
    (((0.1, 100.0),), TREAD, r"temperature_layers\[0\]: temperature 100.0 K"),
    (((0.1, 300.0), (0.1,)), TREAD, "pairs"),
    (((0.1, 300.0),), load_compound("m3"), "no WLF data"),
])
def test_bad_layers_are_rejected_naming_the_field(layers, compound, message):
    with pytest.raises(ValueError, match=message):
        check_layers(layers, compound)
    x = np.linspace(0.0, 1.0, 17)[:-1]
    spec = SlidingSpec(surface_x=x, surface_h=0.002 * np.cos(2 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=compound)
    with pytest.raises(ValueError, match=message):
        SlidingRun(SlidingSpec(**{**spec.__dict__, "temperature_layers": layers}), block_mesh,
                   sliding_contact)


@pytest.mark.parametrize("velocity", [1.0, 1000.0])
def test_layered_strip_reduces_to_the_half_space(velocity):
    """Uniform deep strip (height 3 wavelengths): P = E*_eff(kv) k / 2 to 1e-9 (the exp(-k H)
    terms are 6e-9); one wavelength high: within 0.2 % (the finite-height correction)."""
    k = 2 * np.pi
    half_space = effective_modulus(TREAD, k * velocity) * k / 2
    assert abs(layered_strip_pressure(TREAD, 1.0, velocity, 3.0) / half_space - 1) < 1e-9
    assert abs(layered_strip_pressure(TREAD, 1.0, velocity, 1.0) / half_space - 1) < 2e-3
    # layers all at T equal the uniform strip at T (the layer split is exact)
    T = T_REF + 20.0
    split = layered_strip_pressure(TREAD, 1.0, velocity, 3.0, ((0.2, T), (0.5, T)), T)
    assert abs(split / layered_strip_pressure(TREAD, 1.0, velocity, 3.0, (), T) - 1) < 1e-12


def test_fe_cells_follow_the_layers():
    """Layer bounds are mesh lines, every cell lies in one layer and carries its temperature."""
    x = np.linspace(0.0, 1.0, 129)[:-1]
    layers = ((0.05, T_REF + 40.0), (0.1, T_REF + 20.0))
    spec = SlidingSpec(surface_x=x, surface_h=0.002 * np.cos(2 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=TREAD, h_contact=1.0 / 16,
                       temperature_layers=layers)
    run = SlidingRun(spec, block_mesh, sliding_contact)
    run.build("mortar")  # the 0.05 mm layer is thinner than h_contact: the first row follows it
    z0 = float(np.max(spec.surface_h))
    gd = run.mesh.geometry.dofmap.array.reshape(-1, 4)
    zc = run.mesh.geometry.x[gd, 1] - z0
    lo, hi = zc.min(axis=1), zc.max(axis=1)
    T = run.sp.history.T_cell
    for (a, b), t in (((0.0, 0.05), T_REF + 40.0), ((0.05, 0.15), T_REF + 20.0),
                      ((0.15, 1.0), T_REF)):
        inside = (lo >= a - 1e-12) & (hi <= b + 1e-12)
        assert np.all(T[inside] == t)
        assert inside.any()
    straddle = (lo < 0.05 - 1e-12) & (hi > 0.05 + 1e-12) | (lo < 0.15 - 1e-12) & (hi > 0.15 + 1e-12)
    assert not straddle.any()


def test_uniform_partitions_give_the_closed_form_at_their_temperature():
    """Issue 16: a cell whose partitions all carry T (two layers and the background at T = T_ref
    + 20 K) gives the full-contact sinusoid closed form at T (WLF-shifted E'') within 3 %; the
    shift is large (mu at T is 0.23 of mu at T_ref), so a run ignoring the layers fails."""
    T = T_REF + 20.0
    out = simulate(TREAD, amplitude=0.002, pressure=0.1, velocity=10.0, temperature=T,
                   layers=((0.3, T), (0.3, T)))
    res = out["result"]
    assert res.ok, res.reason
    exact = closed_form_mu(TREAD, 1.0, 0.002, 0.1, 10.0, T)
    assert exact < 0.3 * closed_form_mu(TREAD, 1.0, 0.002, 0.1, 10.0, T_REF)
    assert abs(res.mu_force - exact) < 0.03 * exact, (res.mu_force, exact)
    assert abs(res.mu_energy - exact) < 0.03 * exact, (res.mu_energy, exact)


def test_hot_bottom_partition_lies_between_cold_and_hot_and_matches_the_layered_strip():
    """Issue 16: a hot bottom partition (0.2 mm at T_ref + 20 K over a block at T_ref) gives mu
    strictly between the uniform closed forms at T_ref + 20 K and T_ref, and within 3 % of the
    layered strip's linear viscoelastic solution."""
    hot = T_REF + 20.0
    out = simulate(TREAD, amplitude=0.002, pressure=0.1, velocity=10.0, layers=((0.2, hot),))
    res = out["result"]
    assert res.ok, res.reason
    cold_mu = closed_form_mu(TREAD, 1.0, 0.002, 0.1, 10.0, T_REF)
    hot_mu = closed_form_mu(TREAD, 1.0, 0.002, 0.1, 10.0, hot)
    assert out["mu_bounds"] == pytest.approx((hot_mu, cold_mu))
    assert hot_mu < res.mu_force < cold_mu and hot_mu < res.mu_energy < cold_mu
    exact = layered_strip_mu(TREAD, 1.0, 0.002, 0.1, 10.0, 1.0, ((0.2, hot),), T_REF)
    assert out["mu_exact"] == exact
    assert abs(res.mu_force - exact) < 0.03 * exact, (res.mu_force, exact)
    assert abs(res.mu_energy - exact) < 0.03 * exact, (res.mu_energy, exact)
    # the hot layer matters: the strip without it differs by far more than the tolerance
    assert abs(exact - cold_mu) > 0.2 * cold_mu


def test_a_temperature_without_wlf_data_leaves_the_relaxation_alone():
    """m3 has a Prony series but no WLF constants: a run at T0 = 300 K is the run at the reference
    (it failed in set-up before); mu equal to the run without a temperature to 1e-12."""
    m3 = load_compound("m3")
    a = simulate(m3, amplitude=0.002, pressure=0.1, velocity=10.0, temperature=300.0, periods=1.0)
    b = simulate(m3, amplitude=0.002, pressure=0.1, velocity=10.0, periods=1.0)
    assert a["result"].ok and b["result"].ok, (a["result"].reason, b["result"].reason)
    assert abs(a["mu_force"] - b["mu_force"]) <= 1e-12 * abs(b["mu_force"])
