"""One single-scale sliding run: a viscoelastic block pressed onto a rigid surface and slid over it.

The building block of every multiscale loop (thesis 6.2.1, 6.2.2, 6.4).  The run is a pure function
of its `SlidingSpec`: same inputs, same result.

Load history (thesis 6.2.2):
1. initial contact: the block (bottom at the highest asperity) is pushed down by a small prescribed
   displacement of its top edge until it carries load;
2. compression: the top edge becomes one vertical unknown (all its u_z tied) loaded by the force
   F_z = p l, ramped from the contact load to p over `compression_time`, by default l/(2 pi v) with
   l the cell (period) length: the rubber is loaded at the rate it is excited by sliding over the
   cell's longest wave, so the contact area at the end of compression is that of steady sliding
   (the criterion of thesis 6.1 after De Lorenzis & Wriggers 2013, which the thesis tuned by hand).
   A slower compression lets the rubber creep around the asperities; sliding then starts from a
   larger contact and mu(t) carries a long transient (stats `compression_contact_fraction`);
3. sliding at v with p held: the master surface translates by -v t (periodic micro cell, the block
   stays) while the top edge is held in x; the friction force is the x-reaction of the top edge.

A warm start (``spec.initial_state``, an earlier run's final state on the same mesh: the thermal
loop's next homogenisation point) skips 1 and 2: the run slides on from that state, the road at
its offset then, under its own load, temperatures and friction, and its first period is no
run-in (``window.converged_window``).  ``spec.keep_state`` returns the final state for that.

Micro cell: periodic boundary conditions x_r - x_l = X_r - X_l on the left/right edges (eq. 6.5)
with the periodic master, so the cell slides over many periods.  Macro block: non-periodic.

Failure handling (``driver.sliding.steps``): a step that does not converge (or inverts an
element) is retried with half the step (cut-back), steps grow again after easy successes; a
sub-step that still fails after STABILISE_AFTER cut-backs (or at the last one) is retried with
viscous stabilisation (``driver.fe.stabilisation``, thesis 6.3.3: dashpots resisting the motion
within the sub-step, their work and force reported as ``stabilisation_share``); when the step gets
too small the run starts again with the next fallback (`SlidingRun.attempts`): a softer
tangential penalty (frictional runs), node-to-segment contact, smaller sliding steps, then contact
elements twice as short.  A run that still fails returns `status="failed"` with the reason of the
attempt that got furthest and the time reached (stats ``attempts`` lists every failed attempt's
reason, also on a run that succeeded after them).  Nothing is raised through the caller.

The parts: ``attempts`` (input checks, the fallback chain), ``model`` (an attempt's FE model:
block, constraints, contact, solvers), ``steps`` (sub-steps, cut-backs, Newton starts), ``periods``
(a periodic cell slid over whole periods: the converged-window rule at each period end, the
steady-state history jump, the period start of the Newton solves) and ``result``.

Outputs (``driver.sliding.result``): mu(t) = F_x/F_z (eq. 6.2) and mu from dissipated energy
(eq. 2.8: viscous (+ frictional) energy per sliding distance over F_z), their averages over the
homogenisation window, the mean contact pressure over contact nodes and steps (eq. 6.11), the
contact length (area per unit depth) and its average (7.4), dissipation by depth.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable

import numpy as np

from rubberfriction.driver.fe.newton import FACTOR_REUSE, LINEAR_SOLVERS
from rubberfriction.driver.sliding import shortcut, steps
from rubberfriction.driver.sliding.attempts import (
    NEWTON_METHODS,
    Attempt,
    check_inputs,
    fallback_chain,
)
from rubberfriction.driver.sliding.bodies import block_mesh, sliding_contact
from rubberfriction.driver.sliding.model import SlidingModel
from rubberfriction.driver.sliding.outputs import DissipationByDepth
from rubberfriction.driver.sliding.periods import Periods, sliding_step
from rubberfriction.driver.sliding.progress import StepReporter
from rubberfriction.driver.sliding.slowmode import FaceCreep, SlowModeExtrapolation
from rubberfriction.driver.sliding.result import (
    assemble,
    pooled_contact_pressure,
    stabilisation_share,
)
from rubberfriction.driver.sliding.spec import (
    STABILISE_AFTER,
    InitialState,
    SlidingResult,
    SlidingSpec,
    refined,
    softened,
)
from rubberfriction.driver.sliding.steps import EASY_STREAK, StepControl, WallLimit

__all__ = ["Attempt", "EASY_STREAK", "NEWTON_METHODS", "SlidingRun", "block_mesh",
           "pooled_contact_pressure", "run_sliding", "sliding_contact", "sliding_runner",
           "stabilisation_share"]


def _of_model(name: str) -> property:
    """A part of the current attempt's model (``driver.sliding.model``), read on the run."""
    return property(lambda run: getattr(run.model, name),
                    doc=f"``model.{name}`` of the current (or last) attempt")


def _of_steps(name: str) -> property:
    """A counter of the current attempt's step control, read on the run (observers, benches)."""
    return property(lambda run: getattr(run.steps, name),
                    doc=f"``steps.{name}`` of the current (or last) attempt")


class SlidingRun:
    """Load history and fallback attempts of one sliding run; `run()` returns a SlidingResult.
    Each attempt has its FE model (``model``), its step control (``steps``), its periods
    (``periods``) and its result (``driver.sliding.result``)."""

    #: Newton start candidates, extrapolation guard and unseen starts of the step control
    #: (``driver.sliding.steps``); an instance may set ``start_candidates``,
    #: ``extrapolation_guard`` and ``unseen_after`` before ``run()``
    START_CANDIDATES = steps.START_CANDIDATES
    EXTRAPOLATION_GUARD = steps.EXTRAPOLATION_GUARD
    UNSEEN_AFTER = steps.UNSEEN_AFTER

    cutbacks = _of_steps("cutbacks")
    newton_iterations = _of_steps("newton_iterations")
    predictor_used = _of_steps("predictor_used")
    extrapolation_used = _of_steps("extrapolation_used")
    period_used = _of_steps("period_used")
    column_used = _of_steps("column_used")
    guard_rejections = _of_steps("guard_rejections")
    stabilised_steps = _of_steps("stabilised_steps")
    min_det_F = _of_steps("min_det_F")
    #: energies of the sliding step just solved (on_step observers)
    step_energy = _of_steps("step_energy")
    step_friction_energy = _of_steps("step_friction_energy")

    def __init__(self, spec: SlidingSpec, mesh_factory=None, contact_factory=None, progress=None,
                 observers=(), wall_limit: float = 0.0, linear_solver: str = "petsc",
                 factor_reuse: int = FACTOR_REUSE):
        check_inputs(spec)  # bad input raises here
        self.base_spec = spec
        self.spec = spec  # the current attempt's spec (base_spec, or a refined copy)
        self.refine = 1  # the current attempt's mesh refinement (InitialState.refine)
        self.start_candidates = self.START_CANDIDATES
        self.extrapolation_guard = self.EXTRAPOLATION_GUARD
        self.unseen_after = self.UNSEEN_AFTER
        # wall_limit > 0: seconds after which the run stops with a structured failure (failure
        # kind "wall_limit"; no further fallbacks). A machine-dependent control, so not in the spec.
        self.wall_limit = float(wall_limit)
        if not (np.isfinite(self.wall_limit) and self.wall_limit >= 0.0):
            raise ValueError(f"wall_limit: expected seconds >= 0 (0: no limit), got {wall_limit!r}")
        self._deadline = float("inf")
        # LU package of the Newton solves (driver.fe.newton.LINEAR_SOLVERS): the results agree to
        # round-off, so it is a machine choice, not part of the spec
        if linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"linear_solver = {linear_solver!r}: expected one of "
                             f"{tuple(LINEAR_SOLVERS)}")
        self.linear_solver = linear_solver
        # GMRES iterations on a reused factorisation before refactorising (NewtonSettings;
        # MUMPS ignores it): Newton's iterates to KRYLOV_RTOL, a solver choice like the
        # package (where a cell's path forks, any change of the linear solves can move it:
        # docs/performance.md, "Factorisations reused")
        if not (isinstance(factor_reuse, (int, np.integer)) and factor_reuse >= 0):
            raise ValueError(f"factor_reuse: expected an integer >= 0 (0: factorise at every "
                             f"Newton iteration), got {factor_reuse!r}")
        self.factor_reuse = int(factor_reuse)
        self.t_planned = 0.0  # model time of the current attempt's whole load history
        self.progress = progress
        # observers: objects with optional on_start(run), on_step(run, k, t), on_finish(run,
        # result) methods (outputs such as fields and time series; see driver.sliding.outputs).
        # on_start comes when sliding begins (run.t_start, run.slide_distance, run.dt_slide and
        # run.n_slide_steps are set), on_step after each converged sliding step, on_finish after
        # every attempt, also one that failed in set-up (then run.sp may be missing). An observer
        # that raises is reported with a warning and dropped for the rest of the run: outputs never
        # fail a run.
        self.observers = list(observers)
        self.stabilise_after = STABILISE_AFTER  # cut-backs before a sub-step is stabilised
        self._mesh_factory = mesh_factory
        self.model: SlidingModel | None = None  # the current attempt's FE model (build)
        self.steps: StepControl | None = None  # the current attempt's step control
        self.periods: Periods | None = None  # and its sliding periods
        self._contact_factory = contact_factory

    # --- set-up ------------------------------------------------------------------------------
    def build(self, contact_formulation: str) -> None:
        """This attempt's model (``driver.sliding.model``) with the contact formulation."""
        self.model = SlidingModel(self.spec, self._mesh_factory, self._contact_factory,
                                  self.linear_solver, self.factor_reuse)
        self.model.build(contact_formulation)

    #: the current attempt's model, read on the run by observers and tests
    mesh = _of_model("mesh")
    sp = _of_model("sp")
    contact = _of_model("contact")
    L = _of_model("L")
    H = _of_model("H")
    hc = _of_model("hc")
    top_z_dof = _of_model("top_z_dof")
    fext = _of_model("fext")
    newton = _of_model("newton")
    trust = _of_model("trust")
    problem = _of_model("problem")
    stabiliser = _of_model("stabiliser")

    # --- observers and the wall clock ------------------------------------------------------------
    def exclude_from_wall_limit(self, seconds: float) -> None:
        """Time spent outside the run's own work (an observer's lower-scale cascades in the thermal
        loop) does not count against ``wall_limit``: the deadline moves by ``seconds``."""
        self._deadline += max(float(seconds), 0.0)
        if self.periods is not None:  # nor against a period's pace
            self.periods.exclude(seconds)

    def _notify(self, event: str, *args) -> None:
        for obs in list(self.observers):
            fn = getattr(obs, event, None)
            if fn is None:
                continue
            try:
                fn(self, *args)
            except Exception as err:  # noqa: BLE001 -- an output must not fail the physics
                warnings.warn(f"sliding observer {type(obs).__name__}.{event} failed and is "
                              f"dropped for this run: {type(err).__name__}: {err}", stacklevel=2)
                self.observers.remove(obs)

    # --- the run -------------------------------------------------------------------------------
    def attempts(self) -> list[Attempt]:
        """The fallback chain of this run's spec (``attempts.fallback_chain``)."""
        return fallback_chain(self.base_spec)

    def run(self) -> SlidingResult:
        """The attempts in turn until one succeeds.  Under a wall-time limit a refined attempt that
        would not finish in the time left is skipped: it is estimated as MESH_REFINEMENT**2 times a
        whole unrefined attempt, extrapolated linearly in model time from each failed unrefined
        attempt (the smallest extrapolation, so a doubtful case is tried)."""
        wall0 = time.perf_counter()
        failures: list[str] = []
        best = None
        full = None  # estimated wall time of a complete unrefined attempt (unit step factor)
        if self.wall_limit > 0.0:
            self._deadline = wall0 + self.wall_limit
        try:
            for i, att in enumerate(self.attempts()):
                formulation, step_factor, refine, label = (att.formulation, att.step_factor,
                                                           att.refine, att.label)
                left = self._deadline - time.perf_counter()
                if refine > 1 and full is not None and full * refine**2 > left:
                    failures.append(f"{label}: skipped (needs about {full * refine**2:.0f} s, "
                                    f"{left:.0f} s left)")
                    continue
                self.spec = softened(refined(self.base_spec, refine), att.tangent)
                self.refine = refine
                self.t_planned = 0.0
                t_attempt = time.perf_counter()
                try:
                    result = self._attempt(formulation, step_factor)
                except WallLimit as stop:
                    why = (f": {stop.projected}" if stop.projected
                           else f" reached at t = {stop.t:.4g} s")
                    why = f"wall-time limit of {self.wall_limit:g} s{why}"
                    result = SlidingResult("failed", reason=f"{why} ({label})", t_reached=stop.t)
                    result.stats.update(failure="wall_limit", cutbacks=self.cutbacks,
                                        newton_iterations=self.newton_iterations)
                result.stats["fallback_level"] = i
                result.stats["attempt"] = label
                result.stats["contact_formulation"] = formulation
                result.stats["mesh_refinement"] = refine
                result.stats["tangential_penalty"] = self.spec.tangential_penalty
                result.stats["wall_time"] = time.perf_counter() - wall0
                self._notify("on_finish", result)
                if result.ok:
                    if failures:  # what failed before this attempt
                        result.stats["attempts"] = " | ".join(failures)
                    return result
                if result.stats.get("failure") == "wall_limit":
                    result.stats["attempts"] = " | ".join(failures)
                    return result
                failures.append(f"{label}: {result.reason}")
                if best is None or result.t_reached >= best.t_reached:
                    best = result  # the attempt that got furthest explains the failure best
                done = result.t_reached / self.t_planned if self.t_planned > 0 else 0.0
                if refine == 1 and done > 0.0:
                    est = (time.perf_counter() - t_attempt) * step_factor / min(done, 1.0)
                    full = est if full is None else min(full, est)
        finally:
            self.spec = self.base_spec
        best.stats["attempts"] = " | ".join(failures)
        best.reason = f"{best.reason} (the furthest of {len(failures)} attempts)"
        return best

    def _attempt(self, formulation: str, step_factor: float) -> SlidingResult:
        """One attempt: set-up, the load from rest (or the warm start), sliding, the result."""
        s = self._begin_attempt()
        try:
            self.build(formulation)
        except (ValueError, RuntimeError) as err:
            return SlidingResult("failed", reason=f"set-up: {err}")
        m = self.model
        if s.period > 0 and hasattr(m.contact, "slave") and hasattr(m.contact, "offset"):
            self.intrusion = 0.0  # a periodic cell on the rigid road: measured (-1: not)
        F_target = s.pressure * m.L
        # a periodic cell's default step is half its mesh's column (L / ceil(L / h_contact)),
        # so that two steps move the road by one column (the "column" Newton start)
        shift = steps.column_shift(m.sp, m.L) if s.period > 0 else None
        column = shift.h if shift is not None else m.hc
        step_len = sliding_step(s, m.L, (s.step_length or 0.5 * column) * step_factor)
        t_p = s.compression_time or m.L / (2.0 * np.pi * s.velocity)
        distance = s.slide_distance or 3.0 * (s.period if s.period > 0 else m.L)
        warm = self._warm_state()
        self.t_planned = (0.0 if warm else t_p) + distance / s.velocity  # w/o initial contact
        if warm is not None:  # slide on from an earlier run's final state (spec.InitialState)
            m.restore(warm, F_target)
            t, offset0 = 0.0, warm.offset
        else:
            t, failed = self._load_from_rest(t_p, t_p / s.compression_steps, F_target)
            if failed is not None:
                return failed
            offset0 = 0.0
        self.steps.column_shift = shift
        return self._slide(t, offset0, step_len, distance, warm is not None)

    def _begin_attempt(self) -> SlidingSpec:
        """Fresh per-attempt state: the step control with the run's start settings, counters."""
        self.steps = StepControl(self, self.start_candidates, self.extrapolation_guard,
                                 self.unseen_after, self.stabilise_after)
        self.periods = None
        self._cpu_start = time.process_time()
        self.compression_contact = float("nan")
        self.intrusion = -1.0  # deepest road vertex inside the rubber face over the sliding steps
        self.warm_started = False  # slid on from spec.initial_state (_warm_state)
        return self.spec

    def _slide(self, t: float, offset0: float, step_len: float, distance: float,
               warm: bool) -> SlidingResult:
        """Load history phase 3: sliding at v with p held, from time t and road offset offset0,
        until the distance is slid or the periods say stop; the attempt's result."""
        s, m, control = self.spec, self.model, self.steps
        dt_slide = step_len / s.velocity
        nsteps = int(np.ceil(distance / step_len))
        t_s = t
        keep = m.fext.copy()
        predict = (steps.translation_predictor(m.sp, m.L, m.H, s.velocity)
                   if s.period > 0 else None)
        control.past.clear()
        self.t_start, self.slide_distance, self.dt_slide, self.n_slide_steps = (
            t_s, distance, dt_slide, nsteps)
        self._notify("on_start")
        control.h_next, control.easy = dt_slide, 0
        # the contact face's creep (the one-period windows' guard) and, only under the converged
        # window rule, which judges the periods after it, the creep's extrapolation
        face = FaceCreep(m.sp) if s.period > 0 and s.converge_tol > 0 else None
        slow = (SlowModeExtrapolation(m.sp, face) if s.period_extrapolation and s.steady_state
                and face is not None and s.friction is None
                and m.sp.history is not None else None)

        def equilibrate(shift: float) -> bool:
            return self._equilibrate(offset0 + periods.road_shift + shift
                                     - s.velocity * (t - t_s), dt_slide)

        periods = self.periods = Periods(s, m.L, step_len, nsteps, m.sp.history, warm,
                                         self.wall_limit, slow, equilibrate, face)
        rows: list[tuple] = []
        for k in range(1, nsteps + 1):
            control.begin_step()

            def load(tk):
                m.fext[:] = keep
                road = offset0 + periods.road_shift - s.velocity * (tk - t_s)
                m.contact.set_master_offset(road, 0.0)

            ok, reason, _ = control.solve(t, dt_slide, load, predict, adaptive=True,
                                          period_guess=periods.guess(k))
            if not ok:
                return assemble(self, rows, distance, "failed", f"sliding: {reason}", t)
            t += dt_slide
            periods.record(k, m.sp.w.x.array)
            rows.append(self._row(t, s.velocity * (t - t_s)))
            if self.intrusion >= 0.0:
                self.intrusion = max(self.intrusion, m.road_intrusion())
            self._notify("on_step", k, t)
            if self.progress:
                self.progress(k, nsteps)
            if periods.end_of_step(k, rows, t, self._deadline):
                break
        res = assemble(self, rows, distance, "ok", periods.out_of_reach, t)
        if s.keep_state:
            road = offset0 + periods.road_shift - s.velocity * (t - t_s)
            res.final_state = m.final_state(road, self.refine)
        return res

    def _equilibrate(self, offset: float, dt: float) -> bool:
        """Equilibrium with the road at ``offset``, the histories as they are and a step of
        vanishing length (the glassy response): whether it converges without inverted elements.
        Keeps the converged state (else the start); nothing is committed."""
        m = self.model
        x0 = m.sp.w.x.array.copy()
        m.contact.set_master_offset(offset, 0.0)
        m.sp.prepare_step(1e-9 * dt)
        m.contact.set_time_step(1e-9 * dt)
        res = m.newton.solve()
        self.steps.newton_iterations += res.iterations
        ok = bool(res.converged) and not m.inverted()
        if not ok:
            m.sp.w.x.array[:] = x0
        return ok

    def _row(self, t: float, slid: float) -> tuple:
        """The sliding step's row of the series (result.COLUMNS)."""
        st, c = self.model.contact.state(), self.steps
        return (t, slid, st["Fx"], st["Fz"], st["contact_length"], c.step_energy,
                c.step_friction_dissipation, st["mean_pressure"], c.step_stabilisation_energy,
                c.step_stabilisation_impulse, c.step_interface_energy)

    @property
    def converged(self) -> float:
        """The converged window rule of the last attempt: 1 stationary, 0 not (yet), NaN n/a."""
        return self.periods.converged if self.periods is not None else math.nan

    @property
    def window_used(self) -> int:
        """Periods averaged once stationary (driver.sliding.window); 0 before."""
        return self.periods.window_used if self.periods is not None else 0

    def _load_from_rest(self, t_p: float, dt_p: float, F_target: float
                        ) -> tuple[float, SlidingResult | None]:
        """Load history phases 1 and 2 (module docstring): the initial contact under displacement
        control, then the compression to F_target over t_p.  Returns the time reached and None,
        or the failed result."""
        s, m, t = self.spec, self.model, 0.0
        # 1. initial contact under displacement control
        delta, Fz = 0.0, 0.0
        ddelta = 1e-4 * m.H
        for _ in range(60):
            target = delta + ddelta

            # loads are linear in time over the step, so a cut-back sub-step takes a part of it
            def load(tk, t0=t, lo=delta, hi=target):
                m.cmap.update_value(m.top_z_dof, -(lo + (hi - lo) * (tk - t0) / dt_p))

            ok, reason, _ = self.steps.solve(t, dt_p, load)
            if not ok:
                return t, SlidingResult("failed", reason=f"initial contact: {reason}", t_reached=t)
            t, delta = t + dt_p, target
            Fz = -m.top_reaction()
            if Fz >= 0.02 * F_target:
                break
            ddelta *= 2.0
        else:
            return t, SlidingResult("failed", reason="initial contact: no load after 60 increments",
                                    t_reached=t)
        # 2. compression to p over t_p under force control
        m.switch_to_force_control()
        F0 = min(Fz, F_target)
        for k in range(1, s.compression_steps + 1):

            def load(tk, t0=t, k=k):
                Fk = F0 + (F_target - F0) * (k - 1 + (tk - t0) / dt_p) / s.compression_steps
                m.fext[:] = 0.0
                m.fext[m.top_z_dof] = -Fk

            ok, reason, _ = self.steps.solve(t, dt_p, load)
            if not ok:
                return t, SlidingResult("failed", reason=f"compression: {reason}", t_reached=t)
            t += dt_p
        self.compression_contact = m.contact.state()["contact_length"] / m.L
        return t, None

    def _warm_state(self) -> InitialState | None:
        """The spec's initial state if this attempt's mesh is the one it was computed on (a
        refined fallback attempt starts from rest); stats ``warm_start`` 1 or 0."""
        state = self.spec.initial_state
        self.warm_started = self.model.fits(state)
        return state if self.warm_started else None


def run_sliding(spec: SlidingSpec, progress=None, observers=(),
                wall_limit: float = 0.0, factor_reuse: int = FACTOR_REUSE) -> SlidingResult:
    """Run one sliding run with the default mesh and contact; never raises for a failed run.

    ``wall_limit`` > 0 stops a run that is still going after that many seconds with a structured
    failure (``stats["failure"] == "wall_limit"``), e.g. for sweeps over extreme settings.
    With ``spec.shortcut`` a run that ``driver.sliding.shortcut.check`` admits (frictionless,
    full contact, small slopes) is the linear viscoelastic closed form, not an FE run.
    ``factor_reuse``: GMRES iterations on a reused factorisation (0: a factorisation at every
    Newton iteration; ``driver.fe.newton.FACTOR_REUSE``).
    """
    if spec.shortcut:
        admitted = shortcut.check(spec)
        if admitted.admitted:
            return shortcut.closed_form_result(spec, admitted)
    try:
        return SlidingRun(spec, block_mesh, sliding_contact, progress=progress,
                          observers=observers, wall_limit=wall_limit,
                          factor_reuse=factor_reuse).run()
    except Exception as err:  # a campaign never dies of one run; the reason is recorded
        return SlidingResult("failed", reason=f"{type(err).__name__}: {err}")


def sliding_runner(wall_limit: float = 0.0, progress: Callable[[dict], None] | None = None
                   ) -> Callable[[SlidingSpec], SlidingResult]:
    """The run function of a campaign: :func:`run_sliding` with the scene's per-run wall-time
    limit (``wall_limit`` > 0: a run still going after that many seconds stops itself with a
    structured failure, stored as 'timeout'), the window's dissipation by depth
    (``outputs.DissipationByDepth``, stored as ``dissipation_by_depth``) and, with ``progress``, a
    :class:`~rubberfriction.driver.sliding.progress.StepReporter` calling it after every sliding
    step with a dict of where the run is (the campaign's progress line)."""
    limit = float(wall_limit)

    def runner(spec: SlidingSpec) -> SlidingResult:
        # dissipation by depth of the window (thesis fig. 6.29 c): stored with every run
        observers = [DissipationByDepth()]
        if progress is not None:
            observers.append(StepReporter(progress))
        return run_sliding(spec, observers=observers, wall_limit=limit)

    return runner
