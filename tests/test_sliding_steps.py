"""Step-size control of a sliding run (`StepControl.solve`) on a scripted solver.

The Newton solver is replaced by a script (converged or not, iterations), so the sequence of
sub-step lengths is known exactly: halving on failure, doubling after EASY_STREAK easy sub-steps
in a row (inside a step too, not only from one step to the next), failure below
dt / 2**max_cutbacks, and the length carried over between sliding steps.
"""

from __future__ import annotations

import time
from types import SimpleNamespace

import numpy as np

from rubberfriction.driver.sliding.run import EASY_STREAK, SlidingRun
from rubberfriction.driver.sliding.steps import StepControl
from rubberfriction.driver.sliding.spec import (
    MESH_REFINEMENT,
    SOFT_TANGENT,
    SlidingResult,
    SlidingSpec,
    refined,
    softened,
)


class ScriptedNewton:
    """converged(h) decides each solve; records the sub-step lengths tried."""

    def __init__(self, converged, iterations: int = 3):
        self.converged, self.iterations, self.tried = converged, iterations, []
        self.h = 0.0

    def solve(self):
        self.tried.append(self.h)
        ok = self.converged(len(self.tried), self.h)
        return SimpleNamespace(converged=ok, iterations=self.iterations,
                               reason="" if ok else "scripted failure")


def scripted_control(newton: ScriptedNewton, max_cutbacks: int = 8) -> StepControl:
    """The step control of a run whose solid, contact and solver are scripted."""
    model = SimpleNamespace()
    model.sp = SimpleNamespace(w=SimpleNamespace(x=SimpleNamespace(array=np.zeros(3))),
                               prepare_step=lambda h: setattr(newton, "h", h),
                               commit_step=lambda: 0.0)
    model.contact = SimpleNamespace(set_time_step=lambda h: None, commit=lambda: None,
                                    state=lambda: {})
    model.newton, model.trust, model.inverted = newton, None, lambda: False
    model.iterate_det_F = float("nan")
    run = SimpleNamespace(model=model, _deadline=float("inf"),
                          spec=SimpleNamespace(max_cutbacks=max_cutbacks, stabilisation=0.0))
    control = StepControl(run, start_candidates=("last",))  # Newton starts where it is
    control.h_next = 1.0
    return control


def test_sub_steps_grow_back_within_a_step():
    assert EASY_STREAK == 2
    newton = ScriptedNewton(lambda call, h: call > 3)  # the first three attempts fail
    control = scripted_control(newton)
    ok, _, cutbacks = control.solve(0.0, 1.0, lambda t: None)
    assert ok and cutbacks == 3
    assert newton.tried[:3] == [1.0, 0.5, 0.25]
    # 1/8, 1/8, then doubled to 1/4, 1/4, and the remaining 1/4 (not eight steps of 1/8)
    assert newton.tried[3:] == [0.125, 0.125, 0.25, 0.25, 0.25]


def test_step_fails_below_the_smallest_sub_step():
    newton = ScriptedNewton(lambda call, h: False)
    control = scripted_control(newton, max_cutbacks=4)
    ok, reason, cutbacks = control.solve(0.0, 2.0, lambda t: None)
    assert not ok and reason == "scripted failure" and cutbacks == 5
    assert newton.tried == [2.0, 1.0, 0.5, 0.25, 0.125]  # 2 / 2**4 is the last length tried


def test_sliding_steps_carry_the_reduced_length_over():
    newton = ScriptedNewton(lambda call, h: h <= 0.25, iterations=12)  # hard: no growth
    control = scripted_control(newton)
    assert control.solve(0.0, 1.0, lambda t: None, adaptive=True)[0]
    assert control.h_next == 0.25
    newton.tried.clear()
    assert control.solve(1.0, 1.0, lambda t: None, adaptive=True)[0]
    assert newton.tried == [0.25] * 4  # no repeated failures at 1 and 1/2


def test_sliding_steps_grow_back_to_the_full_step_after_a_cut_back():
    """A doubling earned at a step's first half-step is kept although the step's second half is
    clipped to what is left: after two early cut-backs and easy sub-steps the run returns to
    whole steps.  (Before 0.27.0 it stayed at two half-steps per step for the rest of the run,
    which halved its time step: the default road's macro pressure run at 100 mm/s slid 179 of
    its 240 steps in two sub-steps, docs/performance.md.)"""
    calls = iter(range(1, 100))
    newton = ScriptedNewton(lambda call, h: next(calls) > 2)  # two attempts fail, then easy
    control = scripted_control(newton)
    control.easy = 0
    assert control.solve(0.0, 1.0, lambda t: None, adaptive=True)[0]
    assert newton.tried == [1.0, 0.5, 0.25, 0.25, 0.5]  # doubled after two easy quarter-steps
    tried = []
    for k in range(1, 6):
        newton.tried.clear()
        assert control.solve(float(k), 1.0, lambda t: None, adaptive=True)[0]
        tried.append(list(newton.tried))
    # the easy streak completed at the second step's first half carries the doubling on
    assert tried == [[0.5, 0.5], [1.0], [1.0], [1.0], [1.0]]
    assert control.h_next == 1.0


class ScriptedAttempts(SlidingRun):
    """A run whose attempts are scripted: ok(spec, formulation, step_factor) -> bool; each takes
    `seconds` of wall time and plans a load history of `planned` seconds of model time."""

    def __init__(self, spec, ok, wall_limit=0.0, seconds=0.0, planned=0.0):
        super().__init__(spec, wall_limit=wall_limit)
        self.ok_if, self.log, self.seconds, self.planned = ok, [], seconds, planned

    def _attempt(self, formulation, step_factor):
        self.log.append((formulation, step_factor, self.spec.h_contact))
        self.t_planned = self.planned
        time.sleep(self.seconds)
        if self.ok_if(self.spec, formulation, step_factor):
            return SlidingResult("ok")
        reached = [1.0, 3.0, 0.0, 2.0, 1.0, 0.5][len(self.log) - 1]
        return SlidingResult("failed", reason=f"scripted {len(self.log)}", t_reached=reached)


def small_spec(**kw) -> SlidingSpec:
    x = np.linspace(0.0, 1.0, 64, endpoint=False)
    return SlidingSpec(surface_x=x, surface_h=0.01 * np.sin(2 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=None, h_contact=0.05,
                       elements_per_wavelength=8, **kw)


def test_fallback_chain_ends_with_refined_contact_elements():
    """mortar, nts, nts with 1/4 steps, then contact elements MESH_REFINEMENT times shorter."""
    spec = small_spec()
    run = ScriptedAttempts(spec, lambda s, f, k: s.h_contact < spec.h_contact and f == "nts")
    res = run.run()
    assert res.ok
    h = spec.h_contact
    assert run.log == [("mortar", 1.0, h), ("nts", 1.0, h), ("nts", 0.25, h),
                       ("mortar", 1.0, h / MESH_REFINEMENT), ("nts", 1.0, h / MESH_REFINEMENT)]
    assert res.stats["fallback_level"] == 4 and res.stats["mesh_refinement"] == MESH_REFINEMENT
    assert res.stats["attempt"] == f"nts x{MESH_REFINEMENT} mesh"
    assert run.spec is spec  # the run's own spec again after the refined attempts


def test_frictional_runs_try_a_softer_tangential_penalty_second():
    """With friction: mortar, then mortar with c_T SOFT_TANGENT times softer (stick/slip cycling),
    then the frictionless chain; the soft attempt's spec carries the softer c_T, the others not."""
    spec = small_spec(friction=0.9)
    seen = []
    run = ScriptedAttempts(spec, lambda s, f, k: seen.append(s.tangential_penalty) or False)
    res = run.run()
    h = spec.h_contact
    assert [entry[:2] for entry in run.log] == [("mortar", 1.0), ("mortar", 1.0), ("nts", 1.0),
                                                ("nts", 0.25), ("mortar", 1.0), ("nts", 1.0)]
    assert [entry[2] for entry in run.log] == [h] * 4 + [h / MESH_REFINEMENT] * 2
    c_T = spec.tangential_penalty
    assert seen == [c_T, SOFT_TANGENT * c_T, c_T, c_T, c_T, c_T]
    assert "mortar c_T x0.1: scripted 2" in res.stats["attempts"]
    ok = ScriptedAttempts(spec, lambda s, f, k: s.tangential_penalty < c_T).run()
    assert ok.ok and ok.stats["attempt"] == "mortar c_T x0.1"
    assert ok.stats["tangential_penalty"] == SOFT_TANGENT * c_T
    assert softened(spec, 1.0) is spec
    assert ScriptedAttempts(small_spec(friction=0.0), None).attempts()[1].formulation == "nts"


def test_refined_spec_keeps_the_penalty_frequency():
    spec = small_spec(step_length=0.02)
    fine = refined(spec, 2)
    assert fine.h_contact == 0.025 and fine.step_length == 0.01
    assert (fine.elements_per_wavelength * fine.h_contact
            == spec.elements_per_wavelength * spec.h_contact)
    assert refined(spec, 1) is spec


def test_failed_run_reports_the_attempt_that_got_furthest():
    run = ScriptedAttempts(small_spec(), lambda s, f, k: False)
    res = run.run()
    assert res.status == "failed"
    assert res.reason == "scripted 2 (the furthest of 5 attempts)"  # reached t = 3
    assert res.stats["attempts"].count("scripted") == 5 and "x2 mesh" in res.stats["attempts"]


def test_refined_attempts_that_cannot_finish_in_time_are_skipped():
    """0.05 s per attempt for at most 3/300 of the load history: a whole unrefined attempt takes
    about 5 s, a refined one 4 x 5 s, far beyond the 2 s wall limit, so the run ends after the
    three unrefined attempts."""
    run = ScriptedAttempts(small_spec(), lambda s, f, k: False, wall_limit=2.0, seconds=0.05,
                           planned=300.0)
    res = run.run()
    assert res.status == "failed" and len(run.log) == 3
    assert res.stats["attempts"].count("skipped (needs about") == 2
