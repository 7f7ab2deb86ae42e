"""Multiscale homogenisation (thesis ch. 6.2, 6.3.2, 6.4.2).

Part 1, orchestration logic with a deterministic stand-in for the FE run (not physics): the
cascade passes the sample-averaged mean contact pressure down (eq. 6.11, 6.12) and the
sample-averaged mu up as the Coulomb coefficient of the next coarser scale (eq. 6.13), failed
samples are excluded visibly, adhesion enters on the macro scale (eq. 7.5-7.8), the statistics
are right, the separated variant fits its spline law (eq. 6.6) and hands it to the macro run.

Part 2, physics with the real FE runs (``run_sliding``):
* full contact on every scale: the cascade reproduces the sum of the closed-form viscoelastic
  contributions of the waves within 5 %;
* the thesis' two-sine case (eqs. 6.7, 6.8, fig. 6.4 b): the two-scale mu agrees with the
  single-scale reference within 5 % and is cheaper;
* serial and 2-rank MPI runs of a small scene store identical results.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from tiny_scenes import two_sines

from rubberfriction.driver.multiscale.scales import PeriodicSample, sine_sample
from rubberfriction.driver.runtime.farm import Executor, run_serial
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.multiscale.cascade import CampaignPlanner, RoughCascade
from rubberfriction.driver.multiscale.results import Point, ScaleSet
from rubberfriction.driver.multiscale.separated import SeparatedTwoScale
from rubberfriction.driver.multiscale.statistics import sample_count_study, sample_stats
from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec
from rubberfriction.driver.runtime.store import Store

ROOT = Path(__file__).resolve().parents[1]
COMPOUND = None


def _compound():
    global COMPOUND
    if COMPOUND is None:
        from rubberfriction.forms.material_files import load_compound

        COMPOUND = load_compound("tread_default")
    return COMPOUND


def make_spec(point: Point, scale: int, sample, pressure: float, friction,
              role: str) -> SlidingSpec:
    return SlidingSpec(surface_x=np.asarray(sample.x[:-1]), surface_h=np.asarray(sample.h[:-1]),
                       period=float(sample.period), pressure=float(pressure),
                       velocity=float(point.velocity),
                       compound=_compound(), friction=friction)


def _slope(spec: SlidingSpec) -> float:
    h, x = np.asarray(spec.surface_h), np.asarray(spec.surface_x)
    return float(np.sqrt(np.mean((np.diff(h) / np.diff(x)) ** 2)))


def toy(spec: SlidingSpec) -> SlidingResult:
    """Stand-in for the FE run: made-up, deterministic functions of the inputs (not physics)."""
    s = _slope(spec)
    mu0 = float(spec.friction or 0.0)
    if s > 0.5:
        return SlidingResult("failed", reason="sliding: element inversion (det F <= 0)")
    mu = mu0 + 0.5 * s * math.log10(spec.velocity + 1.0) / spec.pressure ** 0.25
    return SlidingResult("ok", mu_force=mu, mu_energy=mu0 + 0.4 * s,
                         mean_pressure=spec.pressure * (1.0 + 4.0 * s),
                         contact_fraction=1.0 / (1.0 + 4.0 * s))


def scales_with_distinct_samples(n_samples: int) -> list[ScaleSet]:
    out = []
    for i, lam in enumerate((4.0, 0.5, 0.06)):
        smp = [sine_sample([0.002 * lam * (1 + 0.5 * k)], [lam], lam, 32) for k in range(n_samples)]
        out.append(ScaleSet(f"s{i}", (lam, lam / 8), tuple(smp)))
    return out


def run(planner, store: Store, runner=toy):
    run_serial(planner, Executor(store, runner))
    return planner


# ----------------------------------------------------------------------------------------------
# part 1: logic
# ----------------------------------------------------------------------------------------------


def test_cascade_passes_pressure_down_and_friction_up(tmp_path: Path):
    sets = scales_with_distinct_samples(3)
    pt = Point("tread_default", 0.3, 100.0)
    casc = RoughCascade("t", pt, sets, make_spec, k=2, j=3)
    assert casc.total() == 2 * 2 + 3 * 3
    run(CampaignPlanner([casc]), Store(tmp_path / "s"))
    r = casc.result
    assert r.ok and len(r.runs) == 5  # down 0, down 1, up 2, up 1, up 0

    def outcomes(stage):
        return [o for _, o in r.runs[stage]]

    # eq. (6.12): the pressure of scale i+1 is the mean over k samples of eq. (6.11) on scale i
    for i in (0, 1):
        mp = [o.value("mean_pressure") for o in outcomes(f"down:{i}")]
        assert len(mp) == 2 and r.scales[i + 1].pressure == pytest.approx(np.mean(mp), rel=1e-15)
        assert all(t.label["pressure_in"] == r.scales[i].pressure for t, _ in r.runs[f"down:{i}"])
        assert all(t.payload.friction is None for t,
                   _ in r.runs[f"down:{i}"])  # frictionless branch
    assert r.scales[0].pressure == 0.3
    # eq. (6.13): scale i's friction runs use the sample mean of scale i+1 as Coulomb mu
    assert all(t.payload.friction is None for t,
               _ in r.runs["up:2"])  # the finest scale: frictionless
    for i in (1, 0):
        mu_below = np.mean([o.value("mu_force") for o in outcomes(f"up:{i + 1}")])
        assert r.scales[i].friction_in == pytest.approx(mu_below, rel=1e-15)
        assert all(t.payload.friction == pytest.approx(mu_below, rel=1e-15) for t,
                   _ in r.runs[f"up:{i}"])
        assert all(t.payload.pressure == r.scales[i].pressure for t, _ in r.runs[f"up:{i}"])
        assert len(r.runs[f"up:{i}"]) == 3
    assert r.mu.mean == pytest.approx(np.mean([o.value("mu_force") for o in outcomes("up:0")]),
                                      rel=1e-15)
    assert r.mu.n_used == 3 and r.mu.n_failed == 0
    # eq. (7.5): A_r is the product of the per-scale contact fractions (macro: frictionless runs)
    fr = [np.mean([o.value("contact_fraction") for o in outcomes("down:0")])] + \
         [np.mean([o.value("contact_fraction") for o in outcomes(f"up:{i}")]) for i in (1, 2)]
    assert r.area_ratio == pytest.approx(np.prod(fr), rel=1e-12)
    assert [s.area_ratio for s in r.scales] == pytest.approx(np.cumprod(fr), rel=1e-12)


def test_failed_samples_are_excluded_visibly_and_scales_flagged(tmp_path: Path):
    sets = scales_with_distinct_samples(4)
    # make sample 3 of the finest scale too steep for the toy run: it fails
    fine = list(sets[2].samples)
    fine[3] = sine_sample([0.06 * 0.06 * 3], [0.06], 0.06, 32)
    sets[2] = ScaleSet("s2", sets[2].band, tuple(fine))
    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=4,
                        max_failed_fraction=0.2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"))
    r = casc.result
    fine_mu = r.scales[2].mu
    assert r.ok and fine_mu.n_used == 3 and fine_mu.n_failed == 1 and math.isnan(fine_mu.values[3])
    assert fine_mu.mean == pytest.approx(np.nanmean(fine_mu.values), rel=1e-15)
    assert r.scales[2].flagged and not r.scales[1].flagged  # 1 of 4 > 20 %
    assert any("1 of 4 samples failed" in n for n in r.scales[2].notes)
    from rubberfriction.driver.multiscale.report import scale_rows

    row = [x for x in scale_rows([r]) if x["scale"] == 2][0]
    assert row["mu_n_used"] == 3 and row["mu_n_failed"] == 1 and row["flagged"]


def test_samples_and_summary_say_which_fallback_attempt_gave_each_result(tmp_path: Path):
    sets = scales_with_distinct_samples(2)

    def runner(spec: SlidingSpec) -> SlidingResult:
        res = toy(spec)
        steep = _slope(spec) > 0.011  # sample 1 of each scale (rms slope 0.013, sample 0: 0.009)
        res.stats = {"attempt": "nts x2 mesh" if steep else "mortar"}
        return res

    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"), runner)
    from rubberfriction.driver.multiscale.report import attempts_used, sample_rows

    rows = sample_rows([casc.result])
    assert {r["attempt"] for r in rows} == {"mortar", "nts x2 mesh"}
    assert all(r["attempt"] == "nts x2 mesh" for r in rows if r["sample"] == 1)
    assert attempts_used([casc.result]) == {
        "mortar": sum(r["sample"] == 0 for r in rows),
        "nts x2 mesh": sum(r["sample"] == 1 for r in rows)}


def test_a_scale_where_every_sample_fails_fails_the_point(tmp_path: Path):
    sets = scales_with_distinct_samples(1)
    sets[1] = ScaleSet("s1", sets[1].band, (sine_sample([0.5 * 0.5], [0.5], 0.5, 32),))
    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=1)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"))
    assert casc.result.status == "failed" and "scale s1" in casc.result.reason
    assert "element inversion" in casc.result.reason


def test_adhesion_enters_on_the_macro_scale(tmp_path: Path):
    sets = scales_with_distinct_samples(2)
    law = BellLaw(tau0=3.0, c=0.15, v0=20.0, alpha=0.7)
    pt = Point("tread_default", 0.3, 100.0)
    casc = RoughCascade("t", pt, sets, make_spec, k=2, j=2, adhesion=law)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"))
    r = casc.result
    A_r = np.prod([r.scales[0].contact.mean, r.scales[1].contact.mean, r.scales[2].contact.mean])
    tau_A = 3.0 * math.exp(-0.15 * math.log10(100.0 / 20.0) ** 2)  # eq. (7.6), decadic log
    mu_A = tau_A * A_r / 0.3  # eq. (7.7)
    assert r.mu_adhesion == pytest.approx(0.7 * mu_A, rel=1e-12)
    assert r.scales[0].friction_in == pytest.approx(r.scales[1].mu.mean + 0.7 * mu_A,
                                                    rel=1e-12)  # eq. (7.8)
    assert r.scales[1].friction_in == pytest.approx(r.scales[2].mu.mean,
                                                    rel=1e-15)  # no adhesion below


def test_cost_model_counts_mesh_nodes_times_time_steps():
    """(n_x + 1)(n_z + 1)(sliding + compression steps)(1 + rms slope), counted by hand: a 1 mm
    cell with 0.1 mm contact elements has 10 columns; uniform rows (grading 1) give 10 rows,
    graded by 1.2 the smallest n with 0.1 (1.2^n - 1) / 0.2 >= 1 is n = 7; 3 mm of sliding in
    0.05 mm steps; a saw tooth of rise 0.25 over 0.5 mm has slope 0.5 everywhere."""
    from rubberfriction.driver.sliding.spec import cost_model, rms_slope

    x = np.linspace(0.0, 1.0, 64, endpoint=False)
    saw = 0.25 - 0.5 * np.abs(x - 0.5)  # slope +-0.5, periodic
    spec = SlidingSpec(surface_x=x, surface_h=saw, period=1.0,
                       pressure=0.3, velocity=10.0, compound=_compound(), h_contact=0.1,
                       step_length=0.05, grading=1.0, compression_steps=10)
    assert rms_slope(spec) == pytest.approx(0.5, rel=1e-12)
    assert cost_model(spec) == pytest.approx(11 * 11 * 70 * 1.5)
    assert cost_model(dataclasses.replace(spec, grading=1.2)) == pytest.approx(11 * 8 * 70 * 1.5)
    assert cost_model(dataclasses.replace(spec, grading=1.2, slide_distance=1.5)) == \
        pytest.approx(11 * 8 * 40 * 1.5)


def test_plans_list_the_stages_the_planners_run(tmp_path: Path):
    """plan() (for the campaign's time estimate) names every stage a planner hands out, in order,
    with its number of runs and the model weight of its scale."""
    from rubberfriction.driver.runtime.progress import stage_key
    from rubberfriction.driver.sliding.spec import cost_model

    sets = scales_with_distinct_samples(3)
    pt = Point("tread_default", 0.3, 100.0)
    casc = RoughCascade("t", pt, sets, make_spec, k=2, j=3)
    plan = casc.plan()
    assert [(st.key[1], st.key[2], st.runs) for st in plan] == [
        ("down", 0, 2), ("down", 1, 2), ("up", 2, 3), ("up", 1, 3), ("up", 0, 3)]
    assert sum(st.runs for st in plan) == casc.total() and {st.chain for st in plan} == {pt.id}
    for st in plan:
        i = st.key[2]
        assert st.group == (st.key[1], f"s{i}")
        assert st.weight == cost_model(make_spec(pt, i, sets[i].samples[0], 0.3, None, "down"))
    run(CampaignPlanner([casc]), Store(tmp_path / "s"))
    counts: dict[tuple, int] = {}
    for runs in casc.result.runs.values():
        for t, _ in runs:
            counts[stage_key(t.label)] = counts.get(stage_key(t.label), 0) + 1
    assert counts == {st.key: st.runs for st in plan}

    macro = ScaleSet("macro", (5.0, 0.5), (sine_sample([0.05], [5.0], 5.0, 64),))
    micro = ScaleSet("micro", (0.5, 0.05), (sine_sample([0.01], [0.5], 0.5, 64),))
    full = sine_sample([0.05, 0.01], [5.0, 0.5], 5.0, 256)
    sep = SeparatedTwoScale("t", pt, macro, micro, full, make_spec,
                            pressure_factors=(0.5, 1.0, 2.0), velocity_factors=(1.0, 2.0))
    plan = sep.plan()
    assert [(st.key[1], st.runs) for st in plan] == [("macro0", 1), ("micro", 6), ("macro", 1),
                                                     ("reference", 1)]
    assert sum(st.runs for st in plan) == sep.total()
    assert len({st.chain for st in plan}) == 2  # the reference runs beside the chain


def test_sample_statistics():
    st = sample_stats([0.10, 0.12, float("nan"), 0.14])
    assert (st.n_used, st.n_failed) == (3, 1) and st.mean == pytest.approx(0.12)
    assert st.std == pytest.approx(0.02)
    assert st.ci95 == pytest.approx(4.302652729911275 * 0.02 / math.sqrt(3))  # t(0.975, 2)
    one = sample_stats([0.2])
    assert one.mean == 0.2 and math.isnan(one.std) and math.isnan(one.ci95)


def test_sample_count_study_matches_drawing_without_replacement():
    rng = np.random.default_rng(3)
    mu = 0.3 + 0.05 * rng.standard_gamma(2.0, 40)  # skewed, like fig. 6.13 a
    study = sample_count_study(np.append(mu, np.nan), orders=4000, seed=1)
    assert study.n_failed == 1 and study.values.size == 40
    assert study.mean_ref == pytest.approx(mu.mean())
    assert study.S[-1] == pytest.approx(0.0,
                                        abs=1e-12)  # all samples: every order gives the same mean
    # Monte Carlo S(n) vs sigma/sqrt(n) sqrt((N-n)/(N-1)); the std of a std estimate over 4000
    # orders is ~1.1 % -> 5 % is > 4 sigma
    N, n = mu.size, np.arange(1, mu.size + 1)
    S_exact = mu.std(ddof=0) / np.sqrt(n) * np.sqrt((N - n) / (N - 1))  # n of N without replacement
    np.testing.assert_allclose(study.S[:-1], S_exact[:-1], rtol=0.05)
    np.testing.assert_allclose(study.S_exact, S_exact, rtol=1e-12)  # what the report prints
    assert study.S[9] < study.S[0] / 2.5  # what ten samples buy (thesis: 0.047 -> 0.015)


def test_separated_variant_fits_the_law_and_hands_it_to_the_macro_run(tmp_path: Path):
    import rubberfriction._contact  # noqa: F401  (the C++ core: a broken build must fail)
    macro = ScaleSet("macro", (5.0, 5.0), (sine_sample([0.075], [5.0], 5.0, 32),))
    micro = ScaleSet("micro", (0.5, 0.5), (sine_sample([0.01], [0.5], 0.5, 32),))
    full = sine_sample([0.075, 0.01], [5.0, 0.5], 5.0, 32)
    pt = Point("tread_default", 0.3, 500.0)

    def micro_law(p, v):
        return 0.05 + 0.02 * p + 0.01 * np.log10(v)

    def runner(spec: SlidingSpec) -> SlidingResult:
        if spec.period == 0.5:  # micro: a smooth made-up mu(p, v)
            return SlidingResult("ok", mu_force=micro_law(spec.pressure, spec.velocity),
                                 mu_energy=0.0,
                                 mean_pressure=spec.pressure, contact_fraction=0.5)
        mu = 0.0 if spec.friction is None else float(spec.friction(spec.pressure, spec.velocity))
        return SlidingResult("ok", mu_force=mu + 0.01, mu_energy=0.0, mean_pressure=0.6,
                             contact_fraction=0.4)

    sep = SeparatedTwoScale("t", pt, macro, micro, full, make_spec,
                            pressure_factors=(0.25, 0.5, 1.0, 2.0, 4.0),
                            velocity_factors=(0.5, 1.0, 2.0), reference=True)
    assert sep.total() == 1 + 15 + 1 + 1
    run(CampaignPlanner([sep]), Store(tmp_path / "s"), runner)
    r = sep.result
    assert r.ok
    np.testing.assert_allclose(r.extra["grid_p"],
                               0.6 * np.array([0.25, 0.5, 1.0, 2.0, 4.0]))  # around p_macro
    np.testing.assert_allclose(r.extra["grid_v"], [250.0, 500.0, 1000.0])
    macro_task = r.runs["macro"][0][0]
    law = macro_task.payload.friction
    P, V = np.meshgrid(r.extra["grid_p"], r.extra["grid_v"], indexing="ij")
    np.testing.assert_allclose(law(P, V), micro_law(P, V),
                               rtol=1e-10)  # the spline interpolates its data
    assert r.mu.mean == pytest.approx(micro_law(0.3, 500.0) + 0.01, rel=1e-6)
    assert pickle.loads(pickle.dumps(law)).to_dict() == law.to_dict()  # MPI sends laws to workers
    assert r.extra["relative_difference"] == pytest.approx((r.mu.mean - 0.01) / 0.01)
    assert r.extra["time_multiscale"] >= 0 and "time_reference" in r.extra


# ----------------------------------------------------------------------------------------------
# part 2: physics with the real FE runs
# ----------------------------------------------------------------------------------------------

TOY_COMPOUND = textwrap.dedent("""
    # Soft toy compound for the full-contact cascade: one Maxwell term (tau = 0.01 s), nearly
    # incompressible (K = 2/D1 = 500 MPa = 1000 mu), so E* = 3 G* and the closed form holds.
    kind = "compound"
    name = "toy_soft"
    description = "soft toy compound, one Maxwell term"
    source = "tests/test_multiscale.py"
    [units]
    length = "mm"
    time = "s"
    mass = "t"
    force = "N"
    stress = "MPa"
    energy = "mJ"
    temperature = "K"
    [hyperelastic]
    model = "mooney_rivlin"
    form = "split"
    C10 = 0.25
    C01 = 0.0
    D1 = 0.004
    [prony]
    gamma = [0.5]
    tau = [0.01]
""")


def full_contact_scene(tmp_path: Path) -> tuple[Path, float]:
    """Two waves, lambda 2 and 0.2 mm, slope amplitude k h0 = 0.1 each, v = 10 mm/s (omega tau
    = 0.31 and 3.1: both waves dissipate), p = 2 x the larger full-contact pressure, and the sum
    of the closed-form contributions mu_i = (k_i h_i)^2 E''(k_i v) / (4 (1 - nu^2) p)."""
    from rubberfriction.driver.theory.persson import (
        full_contact_pressure_sinusoid,
        mu_full_contact_sinusoid,
    )
    from rubberfriction.forms.material_files import load_compound

    (tmp_path / "toy_soft.toml").write_text(TOY_COMPOUND)
    c = load_compound(tmp_path / "toy_soft.toml")
    nu, v = c.hyperelastic.nu, 10.0
    waves = [(2.0, 0.1 / (2 * np.pi / 2.0)), (0.2, 0.1 / (2 * np.pi / 0.2))]
    p_full = max(full_contact_pressure_sinusoid(2 * np.pi / lam, h0,
                                                complex(c.complex_modulus(2 * np.pi / lam * v)), nu)
                 for lam, h0 in waves)
    p = 2.0 * p_full
    mu_sum = sum(mu_full_contact_sinusoid(2 * np.pi / lam, h0,
                                          complex(c.complex_modulus(2 * np.pi / lam * v)), p, nu)
                 for lam, h0 in waves)
    (tmp_path / "fc.toml").write_text(textwrap.dedent(f"""
        name = "full_contact"
        [surface]
        source = "sines"
        amplitudes = [{waves[0][1]!r}, {waves[1][1]!r}]
        wavelengths = [2.0, 0.2]
        points_per_wavelength = 64
        [samples]
        pressure = 1
        friction = 1
        [conditions]
        compounds = ["toy_soft.toml"]
        pressures = [{p!r}]
        velocities = [{v!r}]
        [numerics]
        elements_per_wavelength = 16
        grading = 1.15
        slide_periods = 3.0
        window_start = 0.334
        step_per_element = 0.5
        run_timeout = 1500
    """))
    return tmp_path / "fc.toml", mu_sum


def test_full_contact_cascade_reproduces_the_sum_of_closed_form_contributions(tmp_path: Path):
    from rubberfriction.driver.multiscale.campaign import run_scene
    from rubberfriction.driver.scenes import load_scene

    path, mu_sum = full_contact_scene(tmp_path)
    res = run_scene(load_scene(path), output=tmp_path / "out", quiet=True)
    r = res.points[0]
    assert r.ok, r.reason
    # full contact everywhere: the mean contact pressure passed down equals the nominal one
    assert r.scales[1].pressure == pytest.approx(r.point.pressure, rel=0.02)
    assert all(s.contact.mean > 0.98 for s in r.scales)
    print(f"cascade mu = {r.mu.mean:.5g}, sum of closed forms = {mu_sum:.5g}")
    assert r.mu.mean == pytest.approx(mu_sum, rel=0.05)


@pytest.mark.slow
def test_two_sine_multiscale_agrees_with_the_reference_and_is_cheaper(tmp_path: Path):
    from rubberfriction.driver.multiscale.campaign import run_scene
    from rubberfriction.driver.scenes import load_scene

    res = run_scene(load_scene("two_sine"), output=tmp_path / "out", quiet=True)
    r = res.points[0]
    assert r.ok, r.reason
    e = r.extra
    print(f"two-sine: mu multiscale = {r.mu.mean:.5g}, reference = {e['mu_reference']:.5g} "
          f"({100 * e['relative_difference']:+.2f} %); wall time multiscale "
          f"{e['time_multiscale']:.1f} s, "
          f"reference {e['time_reference']:.1f} s")
    assert abs(e["relative_difference"]) < 0.05  # thesis fig. 6.4 b
    # thesis fig. 6.4 c, cheaper: counted as work (Newton iterations x dofs of the final attempt
    # of every run), not wall time; achieved 0.95e6 vs 35.7e6 (the reference has 23x the dofs)
    work: dict[str, float] = {}
    for run_ in Store(tmp_path / "out" / "store").query(status="ok"):
        branch = run_.label["branch"]
        work[branch] = work.get(branch, 0.0) + run_.stats["newton_iterations"] * run_.stats["dofs"]
    assert set(work) == {"macro0", "micro", "macro", "reference"}, work
    multiscale = work["macro0"] + work["micro"] + work["macro"]
    assert 0.0 < multiscale < 0.25 * work["reference"], work
    assert (tmp_path / "out" / "comparison.png").is_file()


SMALL_SCENE = two_sines("small", [10.0, 100.0], run_timeout=600)


@pytest.mark.mpi
def test_serial_and_two_rank_runs_of_a_small_scene_store_identical_results(tmp_path: Path):
    (tmp_path / "small.toml").write_text(SMALL_SCENE)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMP_NUM_THREADS="1")
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [sys.executable, "-m", "rubberfriction", "run", str(tmp_path / "small.toml"), "--quiet"]
    serial = subprocess.run(cmd + ["--out", str(tmp_path / "serial")], env=env, capture_output=True,
                            text=True,
                            timeout=1800)
    assert serial.returncode == 0, serial.stderr[-3000:]
    par = subprocess.run(["mpirun", "-n", "2"] + cmd + ["--out", str(tmp_path / "mpi")], env=env,
                         capture_output=True, text=True, timeout=1800)
    assert par.returncode == 0, par.stderr[-3000:]
    a, b = Store(tmp_path / "serial" / "store"), Store(tmp_path / "mpi" / "store")
    assert a.keys() == b.keys() and len(a) == 6  # 2 points x (1 down + 2 up)
    for key in a.keys():
        ra, rb = a.load(key), b.load(key)
        assert ra.status == rb.status == "ok", ra.reason
        np.testing.assert_equal(ra.values, rb.values)  # NaN where a value does not apply
        for name in ra.series:
            np.testing.assert_array_equal(ra.series[name], rb.series[name])
    assert len({b.load(k).provenance["pid"] for k in b.keys()}) == 2
    assert (tmp_path / "serial" / "results.csv").read_text().split("wall_time")[0] == \
        (tmp_path / "mpi" / "results.csv").read_text().split("wall_time")[0]


def test_sine_samples_are_exact_periods():
    s = sine_sample([0.01, 0.002], [1.0, 0.25], 1.0, 16)
    assert isinstance(s, PeriodicSample) and s.x.size == 16 * 4 + 1 and s.h[0] == s.h[-1]
    exact = 0.01 * np.sin(2 * np.pi * s.x) + 0.002 * np.sin(2 * np.pi * s.x / 0.25)
    np.testing.assert_allclose(s.h, exact, atol=1e-15)


def test_samples_and_summary_report_the_energy_balance(tmp_path: Path):
    """energy_balance = mu_energy / mu_force - 1 per run in samples.csv; the summary counts the
    runs beyond ENERGY_BALANCE_TOL and names the largest.  The toy runner's sample 1 dissipates
    1.5 x its friction work, sample 0 exactly its friction work."""
    from rubberfriction.driver.multiscale.report import (
        ENERGY_BALANCE_TOL,
        energy_balance_by_scale,
        energy_balance_line,
        sample_rows,
        scale_rows,
    )

    sets = scales_with_distinct_samples(2)

    def runner(spec: SlidingSpec) -> SlidingResult:
        res = toy(spec)
        res.mu_energy = res.mu_force * (1.5 if _slope(spec) > 0.011 else 1.0)
        return res

    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"), runner)
    rows = sample_rows([casc.result])
    for r in rows:
        assert r["energy_balance"] == pytest.approx(0.5 if r["sample"] == 1 else 0.0, abs=1e-12)
    line = energy_balance_line([casc.result])
    n_off = sum(r["sample"] == 1 for r in rows)
    assert f"{n_off} of {len(rows)} runs beyond {100 * ENERGY_BALANCE_TOL:.0f} %" in line
    assert "largest 50 %" in line and "sample 1" in line and "not energy-consistent" in line
    by_scale = energy_balance_by_scale([casc.result])
    for name in {r["scale_name"] for r in rows}:
        here = [r["energy_balance"] for r in rows if r["scale_name"] == name]
        n_off, n, mean, big = by_scale[name]
        assert (n_off, n) == (sum(b > ENERGY_BALANCE_TOL for b in here), len(here))
        assert mean == pytest.approx(np.mean(here)) and big == pytest.approx(max(here))
        assert f"{name} {n_off} of {n} (mean" in line
    scales = scale_rows([casc.result])
    assert all(math.isfinite(r["energy_balance_max"]) for r in scales)


def test_samples_and_summary_report_the_stabilisation_share(tmp_path: Path):
    """stabilisation_share per run goes through the store into samples.csv; the summary counts the
    runs with stabilised sub-steps and those above STABILISATION_TOL and names the largest; those
    are not averaged, with a note per scale.  The toy runner's sample 1 has a share of 8 %,
    sample 0 none; without any, no line."""
    from rubberfriction.driver.multiscale.report import sample_rows, stabilisation_line
    from rubberfriction.driver.multiscale.statistics import STABILISATION_TOL

    sets = scales_with_distinct_samples(2)

    def runner(spec: SlidingSpec) -> SlidingResult:
        res = toy(spec)
        res.stabilisation_share = 0.08 if _slope(spec) > 0.011 else 0.0
        return res

    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"), runner)
    rows = sample_rows([casc.result])
    for r in rows:
        assert r["stabilisation_share"] == (0.08 if r["sample"] == 1 else 0.0)
    n = sum(r["sample"] == 1 for r in rows)
    line = stabilisation_line([casc.result])
    assert f"{n} of {len(rows)} runs have stabilised sub-steps" in line and "8 %" in line
    assert f"{n} above {100 * STABILISATION_TOL:.0f} %, not averaged" in line and "sample 1" in line
    # above the tolerance a run is not averaged: every friction mean is sample 0's alone
    for sc in casc.result.scales:
        assert sc.mu.n_used == 1 and math.isnan(sc.mu.values[1]), sc.mu
        assert sc.mu.mean == sc.mu.values[0]
        assert any("1 of 2 samples carried more than 5 % of their friction work by stabilisation"
                   in note for note in sc.notes), sc.notes
    casc0 = RoughCascade("t", Point("tread_default", 0.3, 10.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc0]), Store(tmp_path / "s0"), toy)
    assert stabilisation_line([casc0.result]) == ""


def test_samples_scales_and_summary_report_the_road_resolution(tmp_path: Path):
    """road_intrusion per run goes through the store into samples.csv; scales.csv has each scale's
    deepest; the summary counts the runs at INTRUSION_TOL or more (by scale) and names the deepest,
    and marks those scales.  The toy runner's sample 1 has the road 3.5 elements deep, sample 0
    0.4 (resolved); with none at the tolerance, no line."""
    from rubberfriction.driver.multiscale.campaign import CampaignResult
    from rubberfriction.driver.multiscale.report import (
        INTRUSION_TOL,
        resolution_line,
        sample_rows,
        scale_intrusion,
        scale_rows,
        summary_text,
    )
    from rubberfriction.driver.scenes import parse_scene

    sets = scales_with_distinct_samples(2)

    def runner(spec: SlidingSpec) -> SlidingResult:
        res = toy(spec)
        res.road_intrusion = 3.5 if _slope(spec) > 0.011 else 0.4
        return res

    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"), runner)
    rows = sample_rows([casc.result])
    assert {r["road_intrusion"] for r in rows} == {3.5, 0.4}
    deepest = {i: max(r["road_intrusion"] for r in rows if r["scale"] == i)
               for i in range(len(sets))}
    assert scale_intrusion(casc.result) == deepest
    for row in scale_rows([casc.result]):
        assert row["road_intrusion_max"] == deepest[row["scale"]]
    n = sum(r["road_intrusion"] >= INTRUSION_TOL for r in rows)
    line = resolution_line([casc.result])
    assert f"{n} of {len(rows)} runs have road peaks >= 1 contact element" in line
    assert "deepest 3.5 elements" in line and "sample 1" in line and "depend on the mesh" in line
    text = summary_text(CampaignResult(parse_scene('name = "t"\n[surface]\nsource = "sines"\n'
                                                   'amplitudes = [0.01]\nwavelengths = [5.0]\n',
                                                   "<test>", tmp_path),
                                       tmp_path, [casc.result], {}, None, 1.0, 1, "now",
                                       Store(tmp_path / "s")))
    assert line in text and text.count("road unresolved (3.5 elements deep)") == len(sets)
    casc0 = RoughCascade("t", Point("tread_default", 0.3, 10.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc0]), Store(tmp_path / "s0"), toy)
    assert resolution_line([casc0.result]) == ""


def test_a_point_without_usable_samples_says_why(tmp_path: Path):
    """Every friction sample of the last scale succeeded but is left out (stabilisation share
    above the tolerance): the point fails, and its reason names the share of each sample instead
    of a failure that did not happen."""
    sets = scales_with_distinct_samples(2)

    def runner(spec: SlidingSpec) -> SlidingResult:
        res = toy(spec)
        if spec.friction is None and spec.period == pytest.approx(sets[-1].samples[0].period):
            res.stabilisation_share = 0.2
        return res

    casc = RoughCascade("t", Point("tread_default", 0.3, 100.0), sets, make_spec, k=1, j=2)
    run(CampaignPlanner([casc]), Store(tmp_path / "s"), runner)
    assert casc.result.status == "failed"
    assert casc.result.reason.startswith(f"scale {sets[-1].name}: no usable friction sample of 2 (")
    why = "stabilisation carried 20 % of the friction work (tolerance 5 %)"
    assert casc.result.reason.count(why) == 2
