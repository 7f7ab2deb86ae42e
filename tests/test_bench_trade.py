"""`rubberfriction bench trade`: each setting is the default scene at one point with one
discretisation choice changed, and the most converged setting refines all of them."""

from __future__ import annotations

import pytest

from rubberfriction.driver.bench.trade import SETTINGS, setting_scene
from rubberfriction.driver.scenes import load_scene


def test_settings_change_one_choice_and_the_converged_one_refines_all() -> None:
    base = load_scene("default")
    quick = setting_scene(base, "quick", 0.3, 100.0)
    assert quick.conditions.pressures == (0.3,) and quick.conditions.velocities == (100.0,)
    assert quick.numerics == base.numerics and quick.samples == base.samples
    step = setting_scene(base, "step2", 0.3, 100.0)
    assert step.numerics.step_per_element == pytest.approx(0.5 * base.numerics.step_per_element)
    assert step.numerics.elements_per_wavelength == base.numerics.elements_per_wavelength
    best = setting_scene(base, "converged", 0.3, 100.0)
    n, b = best.numerics, base.numerics
    assert n.elements_per_wavelength >= max(
        SETTINGS[k][1]["numerics"]["elements_per_wavelength"] for k in ("el6", "el12", "el24"))
    assert n.penalty_alpha == 100.0 and n.step_per_element < b.step_per_element
    assert n.convergence_tol == pytest.approx(0.5 * b.convergence_tol)
    assert best.samples.pressure == best.samples.friction == 10


def test_per_scale_table_measures_each_scale_from_the_finest_setting() -> None:
    from rubberfriction.driver.bench.trade import finest, scale_table

    def row(mu_macro: float, mu_micro: float) -> dict:
        return {"scales": {"macro": {"mu": mu_macro, "contact": 0.1, "pressure": 0.3,
                                     "cost_s": 10.0},
                           "micro": {"mu": mu_micro, "contact": 0.2, "pressure": 3.0,
                                     "cost_s": 20.0}}}

    rows = {"el6": row(0.50, 0.30), "el12": row(0.49, 0.27), "el24": row(0.48, 0.25)}
    assert finest(list(rows)) == "el24" and finest(["quick", "step2"]) == "step2"
    lines = scale_table(rows)
    micro6 = next(line for line in lines if line.startswith("micro") and " el6 " in line)
    assert micro6.rstrip().endswith("+20.0 %")  # 0.30 / 0.25 - 1
    macro12 = next(line for line in lines if line.startswith("macro") and " el12 " in line)
    assert macro12.rstrip().endswith("+2.1 %")  # 0.49 / 0.48 - 1
