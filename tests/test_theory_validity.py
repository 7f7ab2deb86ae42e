"""Plausibility flags of the analytical baselines (driver/theory/validity.py, issue 45 item 7).

Each check is an explicit inequality on a computed curve: mu <= 3, 0 <= A/A0 <= 1, Persson's
cumulative rms slope <= 1.3, Klüppel-Heinrich's Hurst exponent in (0, 1) and penetration depth
<z_p> <= xi_perp.  The tests build curves with values on both sides of each bound, and evaluate
the real theories once: a small sinusoid (slope 0.06, mu well below 1) carries no flag; the
shipped default road, whose measured bands reach an rms slope of about 2, flags Persson 2D.
"""

from __future__ import annotations

import numpy as np

from rubberfriction.driver.multiscale.baseline import TheoryRequest, evaluate
from rubberfriction.driver.theory.curves import TheoryCurve
from rubberfriction.driver.theory.validity import MU_PLAUSIBLE, SLOPE_PERSSON, validity_flags


def _curve(model: str, mu: list[float], area: list[float] | None = None,
           **extra: object) -> TheoryCurve:
    v = np.array([1.0, 10.0, 100.0])
    return TheoryCurve(model=model, label=model, v=v, mu=np.array(mu), mu_hysteresis=np.array(mu),
                       area=None if area is None else np.array(area), extra=dict(extra))


def test_mu_above_the_plausible_bound_is_flagged_with_its_speeds() -> None:
    ok = _curve("persson-1d", [0.1, 1.0, MU_PLAUSIBLE], slope_rms=0.5)
    assert validity_flags(ok) == []
    high = _curve("kluppel-heinrich", [0.1, 3.5, 5.1], H=0.8, xi_perp_mm=1.0, z_p_mm=0.1)
    flags = validity_flags(high)
    assert [f.quantity for f in flags] == ["mu"]
    assert "5.1 > 3" in flags[0].message and "v = 10..100 mm/s" in flags[0].message


def test_contact_fraction_outside_zero_one_is_flagged() -> None:
    assert validity_flags(_curve("persson-2d", [0.1] * 3, [0.0, 0.5, 1.0], slope_rms=1.0)) == []
    flags = validity_flags(_curve("persson-2d", [0.1] * 3, [0.2, 1.2, 0.5], slope_rms=1.0))
    assert [f.quantity for f in flags] == ["area"] and "v = 10 mm/s" in flags[0].message


def test_persson_slope_bound() -> None:
    assert validity_flags(_curve("persson-2d", [0.1] * 3, slope_rms=SLOPE_PERSSON)) == []
    flags = validity_flags(_curve("persson-2d", [0.1] * 3, slope_rms=2.1))
    assert [f.quantity for f in flags] == ["slope"] and "2.1 > 1.3" in flags[0].message


def test_kluppel_heinrich_hurst_and_penetration_bounds() -> None:
    fine = _curve("kluppel-heinrich", [0.1] * 3, H=0.8, xi_perp_mm=1.0,
                  z_p_mm=np.array([0.2, 0.5, 1.0]))
    assert validity_flags(fine) == []
    bad = _curve("kluppel-heinrich", [0.1] * 3, H=1.2, xi_perp_mm=1.0,
                 z_p_mm=np.array([0.2, 1.5, 2.0]))
    flags = validity_flags(bad)
    assert [f.quantity for f in flags] == ["hurst", "penetration"]
    assert "v = 10..100 mm/s" in flags[1].message


def test_the_theories_are_flagged_where_their_assumptions_fail() -> None:
    # small sinusoid: full-contact line roughness, slope k h0 = 2 pi 0.01 / 1 = 0.063
    sine = evaluate(TheoryRequest(sines=((0.01, 1.0),), velocities=(1.0, 100.0)))
    assert all(validity_flags(c) == [] for c in sine.curves)
    # the default road: measured bands with a cumulative 2D rms slope of about 2 (> 1.3)
    road = evaluate(TheoryRequest(surface="default", velocities=(1.0, 100.0),
                                  models=("persson-2d",)))
    (curve,) = road.curves
    assert curve.extra["slope_rms"] > SLOPE_PERSSON
    assert "slope" in [f.quantity for f in validity_flags(curve)]


def test_flags_are_computed_where_curves_are_made_and_written() -> None:
    # the default road without a cut-off (--surface default): Persson 2D's cumulative rms slope
    # is far above 1.3, so the curve made by theory_curves carries the slope flag
    road = evaluate(TheoryRequest(surface="default", velocities=(1.0, 100.0),
                                  models=("persson-2d",)))
    (curve,) = road.curves
    assert [f.to_dict() for f in curve.flags] == [f.to_dict() for f in validity_flags(curve)]
    doc = curve.to_dict()
    assert "slope" in [f["quantity"] for f in doc["flags"]]
    assert all(f["model"] == "persson-2d" and f["message"] for f in doc["flags"])
    assert road.to_dict()["curves"][0]["flags"] == doc["flags"]
    # an unflagged curve writes an empty list
    sine = evaluate(TheoryRequest(sines=((0.01, 1.0),), velocities=(1.0, 100.0)))
    assert sine.curves[0].to_dict()["flags"] == []


def test_theory_command_prints_each_flag_under_its_model(capsys) -> None:
    from rubberfriction.driver.cli.main import main

    assert main(["theory", "--surface", "default", "--velocities", "1", "100"]) == 0
    out = capsys.readouterr().out.splitlines()
    start = next(i for i, line in enumerate(out) if line.startswith("  persson-2d:"))
    below = []
    for line in out[start + 1:]:
        if not line.startswith("    "):
            break
        below.append(line)
    assert any(line.startswith("    outside validity: cumulative rms slope") for line in below)
    # the surface line states the road and where it stops
    (surface,) = [line for line in out if line.startswith("surface: ")]
    # without a scene the shipped road takes the default rule, as the default scene does
    assert "cut at 0.3 mm" in surface and 'cutoff = "slope"' in surface


def test_a_flagged_curve_is_faded_and_labelled_in_plots() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rubberfriction.driver.theory.curves import OUTSIDE_ALPHA, add_to_axes

    ok = _curve("persson-1d", [0.1, 0.2, 0.3], [0.5, 0.4, 0.3], slope_rms=0.5).flagged()
    bad = _curve("persson-2d", [0.1, 0.2, 0.3], [0.5, 0.4, 0.3], slope_rms=2.1).flagged()
    assert ok.flags == [] and [f.quantity for f in bad.flags] == ["slope"]
    fig, (ax_mu, ax_area) = plt.subplots(1, 2)
    add_to_axes([ok, bad], ax_mu, ax_area)
    labels = {line.get_label(): line.get_alpha() for line in ax_mu.lines}
    assert labels == {"persson-1d": 1.0, "persson-2d (outside validity)": OUTSIDE_ALPHA}
    legend = [t.get_text() for t in ax_mu.get_legend().get_texts()]
    assert "persson-2d (outside validity)" in legend
    assert [line.get_label() for line in ax_area.lines] == ["persson-1d",
                                                            "persson-2d (outside validity)"]
    plt.close(fig)


def test_report_notes_carry_the_flags() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rubberfriction.driver.multiscale.baseline import draw_beside_fe
    from rubberfriction.driver.scenes import load_scene

    fig, ax = plt.subplots()
    curves, notes = draw_beside_fe(ax, load_scene("default"), v_fe=[1.0, 100.0],
                                   models=("persson-2d",), n=5)
    (curve,) = curves
    assert curve.flags  # the default scene's measured bands: cumulative 2D slope about 2
    assert [n for n in notes if "outside validity" in n] == [
        f"persson-2d outside validity: {f.message}" for f in curve.flags]
    plt.close(fig)
