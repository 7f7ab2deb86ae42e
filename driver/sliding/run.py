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

Failure handling: a step that does not converge (or inverts an element) is retried with half the
step (cut-back), steps grow again after easy successes; a sub-step that still fails after
STABILISE_AFTER cut-backs (or at the last one) is retried with viscous stabilisation
(``driver.fe.stabilisation``, thesis 6.3.3: dashpots resisting the motion within the sub-step,
their work and force reported as ``stabilisation_share``); when the step gets too small the run
starts again with the next fallback (`SlidingRun.attempts`): a softer tangential penalty (frictional
runs), node-to-segment contact, smaller sliding steps, then contact elements twice as short.  A
run that still fails returns `status="failed"` with the reason of the attempt that got furthest
and the time reached (stats ``attempts`` lists every failed attempt's reason, also on a run that
succeeded after them).  Nothing is raised through the caller.

Outputs: mu(t) = F_x/F_z (eq. 6.2) and mu from dissipated energy (eq. 2.8: viscous (+ frictional)
energy per sliding distance over F_z), their averages over the homogenisation window, the mean
contact pressure over contact nodes and steps (eq. 6.11), the contact length (area per unit depth)
and its average (7.4), dissipation by depth.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

import ufl

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import LINEAR_SOLVERS, NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.fe.stabilisation import ViscousStabilisation
from rubberfriction.driver.fe.trust_region import TrustRegionSolver
from rubberfriction.driver.sliding import shortcut
from rubberfriction.driver.sliding.bodies import block_mesh, sliding_contact
from rubberfriction.driver.sliding.intrusion import road_intrusion
from rubberfriction.driver.sliding.outputs import DissipationByDepth
from rubberfriction.driver.sliding.progress import StepReporter
from rubberfriction.driver.sliding.temperature import (
    MIN_ROW_FRACTION,
    cell_temperatures,
    check_layers,
    mesh_levels,
)
from rubberfriction.driver.sliding.spec import (
    MESH_REFINEMENT,
    SOFT_TANGENT,
    STABILISATION_LADDER,
    STABILISE_AFTER,
    STABILISED_ITERATIONS,
    STABILISED_STAGNATION,
    InitialState,
    SlidingResult,
    SlidingSpec,
    default_h_contact,
    has_friction,
    mesh_digest,
    penalty_modulus,
    refined,
    softened,
)
from rubberfriction.driver.sliding.window import (
    WINDOW_QUANTITIES,
    error_estimate,
    converged_window,
    earliest_convergence,
    period_means,
    step_lengths,
    window_drift,
)
from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient


#: a sub-step converging in at most this many Newton iterations counts as easy; EASY_STREAK easy
#: sub-steps in a row double the sub-step length (one would make it oscillate: double, fail, halve)
EASY_ITERATIONS = 6
EASY_STREAK = 2
#: after a rejected extrapolated start the next 1, 2, 4, ... (at most this many) sub-steps start
#: without it, until one from it converges within the guard again
MAX_BACKOFF = 32
#: trial steps (linear solves) a trust-region solve may take (driver.fe.trust_region)
TRUST_REGION_STEPS = 60
#: globalisations of the Newton solves (SlidingSpec.newton)
NEWTON_METHODS = ("line-search", "trust-region", "hybrid")


class Attempt(NamedTuple):
    """One attempt of the fallback chain (:meth:`SlidingRun.attempts`)."""

    formulation: str  # "mortar", "nts" or "surface" (driver.fe.contact.Contact)
    step_factor: float = 1.0  # sliding steps this many times the spec's
    refine: int = 1  # contact elements this many times shorter (spec.refined)
    tangent: float = 1.0  # c_T this many times the spec's (spec.softened)

    @property
    def label(self) -> str:
        """e.g. "mortar", "nts x0.25 step", "mortar x2 mesh", "mortar c_T x0.1"."""
        return (self.formulation
                + (f" x{self.step_factor:g} step" if self.step_factor != 1.0 else "")
                + (f" x{self.refine} mesh" if self.refine != 1 else "")
                + (f" c_T x{self.tangent:g}" if self.tangent != 1.0 else ""))


class _WallLimit(Exception):
    """The run's wall-time limit passed (raised between sub-steps, caught in SlidingRun.run)."""

    def __init__(self, t: float, projected: str = ""):
        super().__init__(t)
        self.t = t
        self.projected = projected  # why the limit will pass before the run can converge


class SlidingRun:
    """Set-up and time loop of one sliding run; `run()` returns a SlidingResult."""

    #: Newton starts a sliding sub-step chooses from (:meth:`_start_iterate`): the last state,
    #: the translation, the extrapolated last increment (guarded, :meth:`_guarded_solve`) and
    #: the state one period earlier at the same phase (periodic cells); an instance may set
    #: ``start_candidates`` and ``extrapolation_guard`` (0: unguarded); ``bench sliding --part
    #: start`` compares them
    START_CANDIDATES = ("last", "translation", "extrapolation", "period")
    #: Newton iterations an extrapolated start may take before the sub-step is solved again from
    #: the other starts
    EXTRAPOLATION_GUARD = 6
    #: extrapolated starts that won the residual comparison in a row, after which as many are
    #: taken without computing the starts' residuals (``unseen_after``, 0: always compared)
    UNSEEN_AFTER = 16

    def __init__(self, spec: SlidingSpec, mesh_factory=None, contact_factory=None, progress=None,
                 observers=(), wall_limit: float = 0.0, linear_solver: str = "petsc"):
        check_layers(spec.temperature_layers, spec.compound)  # bad input raises here
        if not (np.isfinite(spec.edge_radius) and spec.edge_radius >= 0.0):
            raise ValueError(f"edge_radius = {spec.edge_radius!r} mm: expected >= 0")
        if spec.edge_radius > 0.0 and spec.period > 0:
            raise ValueError("edge_radius: a periodic cell has no edges; round only a finite block "
                             "(period = 0)")
        if not (np.isfinite(spec.stabilisation) and spec.stabilisation >= 0.0):
            raise ValueError(f"stabilisation = {spec.stabilisation!r}: expected beta >= 0 (0: off)")
        if spec.window_quantity not in WINDOW_QUANTITIES:
            raise ValueError(f"window_quantity = {spec.window_quantity!r}: expected one of "
                             f"{tuple(WINDOW_QUANTITIES)}")
        if spec.newton not in NEWTON_METHODS:
            raise ValueError(f"newton = {spec.newton!r}: expected one of {NEWTON_METHODS}")
        if spec.newton != "line-search" and spec.element == "Q1P0s":
            raise ValueError(f"newton = {spec.newton!r} with element = 'Q1P0s': the trust region "
                             "eliminates the cell pressures, which the pressure-jump term couples; "
                             "expected element Q1P0 or Q1")
        if not 0.0 <= spec.min_jacobian < 1.0:
            raise ValueError(f"min_jacobian = {spec.min_jacobian!r}: expected 0 <= det F limit < 1")
        self.base_spec = spec
        self.spec = spec  # the current attempt's spec (base_spec, or a refined copy)
        self.refine = 1  # the current attempt's mesh refinement (InitialState.refine)
        self.start_candidates = self.START_CANDIDATES
        self.extrapolation_guard = self.EXTRAPOLATION_GUARD
        self._period_guess: np.ndarray | None = None  # the "period" start of the next step
        self.unseen_after = self.UNSEEN_AFTER
        # wall_limit > 0: seconds after which the run stops with a structured failure (failure
        # kind "wall_limit"; no further fallbacks). A machine-dependent control, so not in the spec.
        self.wall_limit = float(wall_limit)
        if not (np.isfinite(self.wall_limit) and self.wall_limit >= 0.0):
            raise ValueError(f"wall_limit: expected seconds >= 0 (0: no limit), got {wall_limit!r}")
        self._deadline = float("inf")
        self._period_wall = 0.0  # wall clock at the last period end (_project_wall_time)
        # LU package of the Newton solves (driver.fe.newton.LINEAR_SOLVERS): the results agree to
        # round-off, so it is a machine choice, not part of the spec
        if linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"linear_solver = {linear_solver!r}: expected one of "
                             f"{tuple(LINEAR_SOLVERS)}")
        self.linear_solver = linear_solver
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
        self._detF = None  # det F at the quadrature points, compiled on first use per attempt
        self._iterate_det_F = math.nan  # its smallest value at the last checked iterate
        self.converged = math.nan  # converged window rule: 1 stationary, 0 not (yet)
        self.window_used = 0  # periods averaged once stationary (driver.sliding.window)
        self._contact_factory = contact_factory

    # --- set-up ------------------------------------------------------------------------------
    def _geometry(self) -> tuple[float, float, float]:
        s = self.spec
        L = s.block_length or s.period
        if not L > 0:
            raise ValueError("block_length: needs a positive value (or a periodic surface)")
        H = s.block_height or L
        hc = s.h_contact or default_h_contact(s)
        return L, H, hc

    def build(self, contact_formulation: str) -> None:
        s = self.spec
        L, H, hc = self._geometry()
        self.L, self.H, self.hc = L, H, hc
        z0 = float(np.max(s.surface_h))  # block bottom rests on the highest asperity
        options = {}  # only what the spec uses: custom factories need not know the rest
        if s.temperature_layers:  # layer bounds become mesh lines where rows stay thick enough
            options["levels"] = mesh_levels(s.temperature_layers, H, MIN_ROW_FRACTION * hc)
        if s.edge_radius > 0.0:
            options["edge_radius"] = s.edge_radius
        body = self._mesh_factory(L, H, hc, s.grading, z0, **options)
        self.mesh, self.facet_tags = body.mesh, body.facet_tags
        # Q1P0s: the jump stabilisation scaled by the shear modulus at the run's excitation
        # frequency (E* ~ 4 G, nearly incompressible), the modulus the cell's deformation sees
        G_s = 0.25 * penalty_modulus(s) if s.element == "Q1P0s" else 0.0
        self.sp = SolidProblem(self.mesh, self.facet_tags, s.compound,
                               SolidSettings(element=s.element, stabilisation_modulus=G_s))
        if s.temperature_layers:  # partitions over the height (thesis 8.3.3)
            background = s.temperature if s.temperature is not None else s.compound.wlf.T_ref
            lower, upper = self.sp.cell_bounds(axis=1) - z0  # depth spans of the cells
            self.sp.set_temperature(cell_temperatures(s.temperature_layers, background, lower,
                                                      upper))
        elif s.temperature is not None and getattr(s.compound, "wlf", None) is not None:
            self.sp.set_temperature(s.temperature)  # (without WLF data the relaxation has no T)
        nfull = self.sp.W.dofmap.index_map.size_local * self.sp.W.dofmap.index_map_bs
        X, d = self.sp.node_X, self.sp.displacement_dofs()
        tol = 1e-9 * max(L, H)
        self.top = np.nonzero(np.abs(X[:, 1] - (z0 + H)) < tol)[0]
        spec = ConstraintSpec(nfull)
        spec.fix(d[self.top, 0], 0.0)  # held in x: F_x is the reaction here
        spec.tie(d[self.top, 1])
        self.top_z_dof = int(d[self.top[0], 1])
        if s.period > 0:
            left = np.nonzero(np.abs(X[:, 0] - X[:, 0].min()) < tol)[0]
            right = np.nonzero(np.abs(X[:, 0] - X[:, 0].max()) < tol)[0]
            left, right = left[np.argsort(X[left, 1])], right[np.argsort(X[right, 1])]
            if left.size != right.size or np.abs(X[left, 1] - X[right, 1]).max() > tol:
                raise RuntimeError("periodic cell: left and right edge nodes do not match")
            spec.equal(d[left, 0], d[right, 0])  # x_r - x_l = X_r - X_l, eq. (6.5)
            spec.equal(d[left, 1], d[right, 1])
        spec.fix(self.top_z_dof, 0.0)  # displacement control until contact carries load
        self.cspec = spec
        self.cmap = ConstraintMap(spec)
        self.contact = self._contact_factory(self.sp, s, contact_formulation)
        self.fext = np.zeros(nfull)
        # inactive until a sub-step needs it; not on the top row: its reaction is the load
        self.stabiliser = ViscousStabilisation(np.delete(d, self.top, axis=0), nfull)
        self._stabilised_x = np.isin(self.stabiliser.dofs, d[:, 0])  # its x-dofs (net force)
        self.problem = self.sp.nonlinear_problem(self.cmap,
                                                 hooks=[self.contact.hook, self.stabiliser],
                                                 extra_couplings=self.contact.couplings(),
                                                 external_force=self.fext)
        self.force_scale = s.pressure * L
        # strict backtracking (no residual growth accepted): with friction a full step from trial
        # slip can jump over the narrow stick cone into reverse slip and back (2-cycle); without,
        # on steep rough samples, it also pays (rms slope 2 micro sample at 10 mm/s, 0.1 MPa:
        # 10 200 -> 6 400 Newton iterations, 86 -> 57 s, same mu within 0.2 %).
        # stagnation: cycling active sets are cut back after 8 iterations instead of 25
        settings = NewtonSettings(rtol=1e-8, atol=1e-12 * self.force_scale, backtrack_growth=1.0,
                                  stagnation=8, linear_solver=self.linear_solver)
        self.trust = None  # the trust-region solver (newton = "trust-region" or "hybrid")
        if s.newton in ("trust-region", "hybrid"):  # every trial step counts: more per solve
            self.trust = TrustRegionSolver(
                self.problem, dataclasses.replace(settings, max_iterations=TRUST_REGION_STEPS),
                force_scale=self.force_scale, relax=self.sp.pressure_relaxation(),
                displacement_dofs=self.sp.umap)
        if s.newton == "trust-region":
            self.newton = self.trust
        else:
            self.newton = NewtonSolver(self.problem, settings, force_scale=self.force_scale)

    def _switch_to_force_control(self) -> None:
        """The tied top u_z becomes an unknown loaded by F_ext (compression phase)."""
        self.cspec.fixed.pop(self.top_z_dof)
        self.cmap = ConstraintMap(self.cspec)
        self.problem.set_constraints(self.cmap)  # the solver refactorises the new P^T A P

    # --- one step with cut-backs ---------------------------------------------------------------
    def _solve_step(self, t: float, dt: float, apply_load, predict=None,
                    adaptive: bool = False) -> tuple[bool, str, int]:
        """Advance from t to t + dt (sub-stepping on failure). Returns (ok, reason, cutbacks).

        predict(h), if given, moves the start iterate of a sub-step of length h (not the result);
        it is kept only where it lowers the start residual (see :meth:`_start_iterate`).
        The sub-step length halves on failure and doubles (up to dt) after EASY_STREAK sub-steps
        in a row that converged in at most EASY_ITERATIONS iterations; the step fails when it
        would fall below dt / 2**max_cutbacks. ``adaptive``: the sub-step length is also
        remembered from step to step (sliding phase), so a step after a hard one does not first
        repeat its failed attempts.
        """
        cutbacks, t_cur = 0, t
        h = min(dt, self._h_next) if adaptive else dt
        while t_cur < t + dt - 1e-12 * dt:
            if time.perf_counter() > self._deadline:
                raise _WallLimit(t_cur)
            h = min(h, t + dt - t_cur)
            x_saved = self.sp.w.x.array.copy()
            apply_load(t_cur + h)
            self.sp.prepare_step(h)
            self.contact.set_time_step(h)
            full = abs(h - dt) <= 1e-12 * dt and t_cur == t  # the whole step: its phase is known
            start = (self._start_iterate(predict, h, x_saved,
                                         period_guess=self._period_guess if full else None)
                     if adaptive else "last")
            hybrid = self.trust is not None and self.trust is not self.newton
            x_start = self.sp.w.x.array.copy() if hybrid else None
            if start == "extrapolation" and self.extrapolation_guard > 0:
                res, redo_start = self._guarded_solve(predict, h, x_saved)
                if hybrid and redo_start is not None:
                    x_start = redo_start
            else:
                res = self.newton.solve()
            self.newton_iterations += res.iterations
            if not res.converged and hybrid:
                # the sub-step again from the same start, with the trust region
                self.sp.w.x.array[:] = x_start
                res = self.trust.solve()
                self.newton_iterations += res.iterations
                self.trust_solves += 1
            ok, reason = res.converged, res.reason
            if ok and self._inverted():
                ok, reason = False, self._bad_element_reason()
            floor = dt * 0.5**self.spec.max_cutbacks * (1.0 - 1e-9)
            if not ok and self.spec.stabilisation > 0.0 and (cutbacks >= self.stabilise_after
                                                             or 0.5 * h < floor):
                ok, res = self._stabilised_solve(h, x_saved, predict, adaptive)
            if ok:
                if "extrapolation" in self.start_candidates:  # only then is it read
                    self._last_increment = (self.sp.w.x.array - x_saved, h)
                self.min_det_F = min(self.min_det_F, self._iterate_det_F)
                self.step_energy += self.sp.commit_step()
                self.contact.commit()
                self.step_friction_energy += float(self.contact.state().get("dissipation", 0.0))
                t_cur += h
                self._easy = self._easy + 1 if res.iterations <= EASY_ITERATIONS else 0
                if self._easy >= EASY_STREAK:
                    h, self._easy = min(dt, 2.0 * h), 0
                if adaptive:
                    self._h_next = h
                continue
            self.sp.w.x.array[:] = x_saved
            self._easy = 0
            cutbacks += 1
            self.cutbacks += 1
            h *= 0.5
            if h < floor:
                if adaptive:
                    self._h_next = dt
                return False, reason, cutbacks
            if adaptive:
                self._h_next = h
        return True, "", cutbacks

    def _stabilised_solve(self, h: float, x_saved: np.ndarray, predict,
                          sliding: bool = False) -> tuple[bool, object]:
        """The failed sub-step again with viscous stabilisation (driver.fe.stabilisation), beta
        up the ladder spec.stabilisation x STABILISATION_LADDER until Newton converges; the
        dashpots' work and net x-force are added to the step's (series ``stabilisation_energy``,
        ``stabilisation_impulse``).  The load of the sub-step is already applied."""
        plain = self.newton.settings
        self.newton.settings = dataclasses.replace(plain, max_iterations=STABILISED_ITERATIONS,
                                                   stagnation=STABILISED_STAGNATION)
        try:
            return self._stabilised_ladder(h, x_saved, predict, sliding)
        finally:
            self.newton.settings = plain
            self.stabiliser.deactivate()

    def _stabilised_ladder(self, h: float, x_saved: np.ndarray, predict,
                           sliding: bool = False) -> tuple[bool, object]:
        pb, damper = self.problem, self.stabiliser
        self.sp.w.x.array[:] = x_saved
        damper.deactivate()
        pb.constraints.set_prescribed(self.sp.w.x.array)
        pb.assemble(need_vector=False)
        diagonal = pb.A.getDiagonal().array.copy()  # of the tangent at u_n, for every rung
        res = None
        for factor in STABILISATION_LADDER:
            self.sp.w.x.array[:] = x_saved
            damper.activate(self.spec.stabilisation * factor, diagonal, x_saved)
            if sliding:  # not the extrapolation: unguarded, it may choose another branch
                self._start_iterate(predict, h, x_saved, exclude=("extrapolation",))
            res = self.newton.solve()
            self.newton_iterations += res.iterations
            if res.converged and not self._inverted():
                x = self.sp.w.x.array
                fx = float(np.sum(damper.forces(x)[self._stabilised_x]))
                self.step_stabilisation_energy += damper.energy(x)
                self.step_stabilisation_impulse += fx * h
                self.stabilised_steps += 1
                return True, res
        self.sp.w.x.array[:] = x_saved
        return False, res

    def _guarded_solve(self, predict, h: float, x_saved: np.ndarray
                       ) -> tuple[Any, np.ndarray | None]:
        """Newton from the extrapolated start, allowed ``extrapolation_guard`` iterations.  A
        start near the continuation of the path converges within them (micro2: 4 on average);
        one that needs more has left it and may be heading for another equilibrium (on the
        three-wave cell the unguarded starts that led off the other starts' path took 29 and 97
        iterations), so the sub-step is solved again from the other starts (the iterations of
        both count) and the next 1, 2, 4, ... MAX_BACKOFF sub-steps do without the extrapolation
        (where it does not pay, as on smooth cells where the translation converges in 3, its
        rejections would otherwise double their cost).  Returns Newton's result and, after a
        rejection, the start of the solve again (None when the extrapolated start converged)."""
        plain = self.newton.settings
        self.newton.settings = dataclasses.replace(plain, max_iterations=self.extrapolation_guard)
        try:
            res = self.newton.solve()
        finally:
            self.newton.settings = plain
        if res.converged:
            self._backoff = 0
            return res, None
        self.guard_rejections += 1
        self._streak = self._unseen = 0  # compare the starts again
        self._backoff = min(2 * self._backoff or 1, MAX_BACKOFF)
        self._skip = self._backoff
        self.newton_iterations += res.iterations
        self.sp.w.x.array[:] = x_saved
        self._start_iterate(predict, h, x_saved, exclude=("extrapolation",))
        redo_start = self.sp.w.x.array.copy()
        return self.newton.solve(), redo_start

    def _start_iterate(self, predict, h: float, x_saved: np.ndarray,
                       exclude: tuple[str, ...] = (),
                       period_guess: np.ndarray | None = None) -> str:
        """Newton start of a sliding sub-step of length h, returned by name: of the last converged
        state, the translation prediction (``predict``, periodic cells) and the extrapolation of
        the last converged sub-step's increment (unless backing off after a rejected one, see
        :meth:`_guarded_solve`), the one with the lowest residual (each costs one residual
        assembly); ``exclude`` leaves candidates out.  Once the extrapolation has won
        ``unseen_after`` comparisons in a row, as many next sub-steps take it unseen, then one
        comparison decides again (a rejection by the guard starts the count anew; unguarded, it
        is always compared): on micro cells it always wins and comparing cost 9 % of a micro2
        period; on meso cells the translation often wins and saves 10 % of the iterations.

        Extrapolation: x_n + (h / h_prev) (x_n - x_prev), the forward-Euler predictor of the
        displacement path: on steep micro cells the other starts are far from the solution
        (the translation interpolates contact nodes into the road's flanks and never wins there)
        and it cuts a micro2 period's Newton iterations 2.6x.  A start can choose the branch
        where the discrete equilibrium is not unique: unguarded, on the frictionless three-wave
        cell of ``tests/test_sliding.py`` it ends at mu 0.0243 against 0.0224 from the other
        starts, and where the stabilised sub-steps started from it too, in an equilibrium whose
        contact face travels with the road (mu -0.72); so it is used through the guard only and
        never in the stabilisation ladder (README "Start iterate").

        Period (``period_guess``, whole steps of a periodic cell from its second period on): the
        converged state one period earlier at the same phase plus the drift between the periods
        at the step before, x(t - T) + (x_n - x(t_n - T)).  In a periodic steady state it is the
        solution itself; while a run still settles it carries the active set of the last period.
        Always compared (never taken unseen)."""
        wanted = tuple(c for c in self.start_candidates if c not in exclude)
        candidates: list[tuple[str, Any]] = [("last", None)]
        if predict is not None and "translation" in wanted:
            candidates.append(("translation", predict))
        inc = self._last_increment
        if "extrapolation" in wanted and self._skip > 0:
            self._skip -= 1  # backing off after a rejected extrapolation (_guarded_solve)
        elif ("extrapolation" in wanted and inc is not None and inc[0].shape == x_saved.shape
                and inc[1] > 0.0):
            candidates.append(("extrapolation", x_saved + (h / inc[1]) * inc[0]))
        if "period" in wanted and period_guess is not None and period_guess.shape == x_saved.shape:
            candidates.insert(1, ("period", period_guess))
        if len(candidates) < 2:
            return "last"  # the last state (already the iterate): nothing to compare
        pb = self.problem
        x = self.sp.w.x.array
        best, best_r = "last", math.inf
        best_x = x_saved
        if (candidates[-1][0] == "extrapolation" and self._unseen > 0
                and candidates[1][0] != "period"):
            self._unseen -= 1  # it has won every comparison lately: take it unseen
            self.extrapolation_unseen += 1
            best, best_x = candidates[-1][0], candidates[-1][1]
            candidates = []
        for name, move in candidates:
            x[:] = x_saved
            if name == "translation":
                move(h)
            elif move is not None:
                x[:] = move
            pb.constraints.set_prescribed(x)
            pb.assemble(need_matrix=False)
            r = pb.br.norm()
            if np.isfinite(r) and r < best_r:
                best, best_r, best_x = name, r, x.copy()
        x[:] = best_x
        pb.constraints.set_prescribed(x)
        self.predictor_used += best == "translation"
        self.extrapolation_used += best == "extrapolation"
        self.period_used += best == "period"
        if candidates and candidates[-1][0] == "extrapolation":
            self._streak = self._streak + 1 if best == "extrapolation" else 0
            if 0 < self.unseen_after <= self._streak and self.extrapolation_guard > 0:
                self._unseen = self.unseen_after
        return best

    def _translation_predictor(self):
        """Start iterate for a sliding step of a periodic cell: steady sliding carries the
        deformation along with the surface, u_{n+1}(X) ~ u_n(X + v h) (periodic in x).  Nodes of
        the structured block lie on rows of equal z; each row is interpolated in numpy.  Only the
        Newton start changes; without it a step starts far from equilibrium on steep surfaces."""
        X, L, v = self.sp.node_X, self.L, self.spec.velocity
        d = self.sp.displacement_dofs()
        x0 = X[:, 0].min()
        rows = []
        for z in np.unique(np.round(X[:, 1], 12)):
            nodes = np.nonzero(np.abs(X[:, 1] - z) < 1e-9 * max(L, self.H))[0]
            nodes = nodes[np.argsort(X[nodes, 0])]
            data = nodes[:-1] if np.isclose(X[nodes[-1], 0] - X[nodes[0], 0], L) else nodes
            rows.append((nodes, data))  # the right-edge node is the left one's periodic image
        if sum(r[0].size for r in rows) < X.shape[0]:
            return None  # not a structured block: no predictor

        def predict(h: float) -> None:
            shift = v * h
            x = self.sp.w.x.array
            for nodes, data in rows:
                xd = X[data, 0] - x0
                xe = (X[nodes, 0] - x0 + shift) % L
                for c in (0, 1):
                    x[d[nodes, c]] = np.interp(xe, xd, x[d[data, c]], period=L)

        return predict

    def exclude_from_wall_limit(self, seconds: float) -> None:
        """Time spent outside the run's own work (an observer's lower-scale cascades in the thermal
        loop) does not count against ``wall_limit``: the deadline moves by ``seconds``."""
        self._deadline += max(float(seconds), 0.0)
        self._period_wall += max(float(seconds), 0.0)  # nor against a period's pace

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

    def _inverted(self) -> bool:
        """Whether the iterate has an inverted or collapsed element: a quadrature point with
        det F <= spec.min_jacobian (the smallest value is kept for the reason text)."""
        if self._detF is None:
            u, _ = self.sp.split()
            self._detF = jit.expression(ufl.det(deformation_gradient(u)), self.sp.rule.points)
            ncell = self.mesh.topology.index_map(2).size_local
            self._cells = np.arange(ncell, dtype=np.int32)
        self._iterate_det_F = float(self._detF.eval(self._cells).min())
        return self._iterate_det_F <= self.spec.min_jacobian

    def _bad_element_reason(self) -> str:
        j = self._iterate_det_F
        if not j > 0.0:
            return "element inversion (det F <= 0)"
        return f"element collapse (det F = {j:.3g} <= min_jacobian {self.spec.min_jacobian:g})"

    def _road_intrusion(self) -> float:
        """How deep the road reaches into the rubber face now (``intrusion.road_intrusion``)."""
        slave, s = self.contact.slave, self.spec
        x = slave.X + self.sp.w.x.array[slave.dofs]
        ox, oz = self.contact.offset
        return road_intrusion(x[:, 0], x[:, 1], np.asarray(s.surface_x) + ox,
                              np.asarray(s.surface_h) + oz, s.period)

    def _top_reaction(self) -> float:
        """Vertical force the tied top edge carries (internal force sum at its u_z dofs)."""
        d = self.sp.displacement_dofs()[self.top, 1]
        return float(self.problem.reaction(d).sum())

    # --- the run -------------------------------------------------------------------------------
    def attempts(self) -> list[Attempt]:
        """The fallback chain: contact formulation, sliding step factor, mesh refinement and
        tangential penalty factor of each attempt.

        Mortar, then (frictional runs) mortar with c_T SOFT_TANGENT times softer (stick/slip
        cycling at the first sliding steps, see ``spec.SOFT_TANGENT``; a finite block tries the
        soft one first), node-to-segment, smaller
        sliding steps (stabilisation), then contact elements MESH_REFINEMENT times shorter with
        each formulation: a slave bent over master features sharper than its elements (a peak
        poking through a contact element) has no smooth solution path at that resolution, and no
        step length fixes that.  A warm start whose state was computed on a refined mesh
        (``InitialState.refine``) begins with that mesh: the same slot at the previous
        temperature converged only there, and only there does its state fit.
        """
        base = self.base_spec.contact
        first = [Attempt(base)]
        if has_friction(self.base_spec):
            soft = Attempt(base, tangent=SOFT_TANGENT)
            # a finite block (macro scale) tries the soft stick first: its first sliding step puts
            # the nodes far outside the stick cone (measured: the 20 x 7 mm m2 block of thesis
            # 8.5.2, mu 1.0, 0.5 m/s, 2 mm: the spec's c_T fails after ~105 s, the soft one slides
            # in 8 s)
            first = [soft, Attempt(base)] if self.base_spec.period == 0 else [Attempt(base), soft]
        if base == "mortar":
            first.append(Attempt("nts"))
        chain = first + [Attempt(first[-1].formulation, step_factor=0.25)]
        formulations = dict.fromkeys(a.formulation for a in first)
        chain += [Attempt(f, refine=MESH_REFINEMENT) for f in formulations]
        state = self.base_spec.initial_state
        if state is not None and state.refine > 1:
            lead = first[0]._replace(refine=int(state.refine))
            chain = [lead] + [a for a in chain if a != lead]
        return chain

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
                except _WallLimit as stop:
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
        s = self.spec
        self.cutbacks, self.newton_iterations, self.predictor_used, self._easy = 0, 0, 0, 0
        self.extrapolation_used = 0  # sub-steps started from the extrapolated increment
        self.period_used = 0  # steps started from the state one period earlier
        self._period_guess: np.ndarray | None = None  # that start for the next step
        # extrapolated starts the guard rejected; sub-steps without it after rejections
        self.guard_rejections = self._backoff = self._skip = self._streak = self._unseen = 0
        self.extrapolation_unseen = 0  # of extrapolation_used: taken without comparing residuals
        self._last_increment: tuple[np.ndarray, float] | None = None  # (x_n - x_prev, h_prev)
        self._cpu_start = time.process_time()
        self.compression_contact = float("nan")
        self._detF = None
        self.step_energy = self.step_friction_energy = 0.0
        self.step_stabilisation_energy = self.step_stabilisation_impulse = 0.0
        self.stabilised_steps = 0
        self.min_det_F = math.inf
        self.intrusion = -1.0  # deepest road vertex inside the rubber face over the sliding steps
        self.trust_solves = 0  # hybrid: sub-steps handed to the trust region
        self.warm_started = False  # slid on from spec.initial_state (_warm_state)
        try:
            self.build(formulation)
        except (ValueError, RuntimeError) as err:
            return SlidingResult("failed", reason=f"set-up: {err}")
        if s.period > 0 and hasattr(self.contact, "slave") and hasattr(self.contact, "offset"):
            self.intrusion = 0.0  # a periodic cell on the rigid road: measured (-1: not)
        L, F_target = self.L, s.pressure * self.L
        step_len = (s.step_length or 0.5 * self.hc) * step_factor
        whole_periods = s.period > 0 and (s.converge_tol > 0 or s.steady_state)
        if whole_periods:  # steps end on every period boundary
            step_len = L / max(1, round(L / step_len))
        dt_slide = step_len / s.velocity
        t_p = s.compression_time or L / (2.0 * np.pi * s.velocity)
        dt_p = t_p / s.compression_steps
        distance = s.slide_distance or 3.0 * (s.period if s.period > 0 else L)
        warm = self._warm_state()
        self.t_planned = (0.0 if warm else t_p) + distance / s.velocity  # w/o initial contact
        rows, offset0 = [], 0.0
        if warm is not None:  # slide on from an earlier run's final state (spec.InitialState)
            self._restore(warm)
            self.fext[:] = 0.0
            self.fext[self.top_z_dof] = -F_target
            t, offset0 = 0.0, warm.offset
        else:
            t, failed = self._load_from_rest(t_p, dt_p, F_target)
            if failed is not None:
                return failed
        # 3. sliding at v with p held
        nsteps = int(np.ceil(distance / step_len))
        t_s = t
        keep = self.fext.copy()
        predict = self._translation_predictor() if s.period > 0 else None
        self.t_start, self.slide_distance, self.dt_slide, self.n_slide_steps = (
            t_s, distance, dt_slide, nsteps)
        self._notify("on_start")
        self._h_next, self._easy = dt_slide, 0
        per_period = round(L / step_len) if whole_periods else 0
        # converged states of the last period by phase (the "period" Newton start) and the
        # change of the state since one period earlier at the last step
        phase_x: list[np.ndarray | None] = [None] * per_period
        drift: np.ndarray | None = None
        history = self.sp.history if s.steady_state else None
        start = history.snapshot() if history is not None else None
        self.converged, self.window_used = math.nan, 0  # this attempt's window (see __init__)
        run_in = 0 if warm is not None else 1  # periods from rest the window rule leaves out
        out_of_reach = ""
        self._period_wall = time.perf_counter()  # wall clock at the last period end
        for k in range(1, nsteps + 1):
            self.step_energy = self.step_friction_energy = 0.0
            self.step_stabilisation_energy = self.step_stabilisation_impulse = 0.0

            def load(tk):
                self.fext[:] = keep
                self.contact.set_master_offset(offset0 - s.velocity * (tk - t_s), 0.0)

            slot = k % per_period if per_period else 0
            self._period_guess = (None if not per_period or phase_x[slot] is None or drift is None
                                  else phase_x[slot] + drift)
            ok, reason, _ = self._solve_step(t, dt_slide, load, predict, adaptive=True)
            self._period_guess = None
            if not ok:
                res = self._result(rows, distance, "failed", f"sliding: {reason}", t)
                return res
            t += dt_slide
            if per_period:  # the state at this phase, and its change since one period earlier
                x_now = self.sp.w.x.array
                drift = None if phase_x[slot] is None else x_now - phase_x[slot]
                phase_x[slot] = x_now.copy()
            st = self.contact.state()
            rows.append((t, s.velocity * (t - t_s), st["Fx"], st["Fz"], st["contact_length"],
                         self.step_energy, self.step_friction_energy, st["mean_pressure"],
                         self.step_stabilisation_energy, self.step_stabilisation_impulse))
            if self.intrusion >= 0.0:
                self.intrusion = max(self.intrusion, self._road_intrusion())
            self._notify("on_step", k, t)
            if self.progress:
                self.progress(k, nsteps)
            if per_period and k % per_period == 0:  # a whole period ends here
                if s.converge_tol > 0:
                    arr = np.array([r[1:5] for r in rows])  # s, Fx, Fz, contact length
                    with np.errstate(divide="ignore", invalid="ignore"):  # no load: mu is NaN
                        q = {"mu_force": -arr[:, 1] / arr[:, 2], "contact_fraction": arr[:, 3] / L}
                    names = WINDOW_QUANTITIES[s.window_quantity]
                    means = [period_means(arr[:, 0], q[name], L) for name in names]
                    halves = [period_means(arr[:, 0], q[name], 0.5 * L) for name in names]
                    self.window_used = converged_window(means, s.converge_tol, s.window_periods,
                                                        halves, run_in)
                    self.converged = float(self.window_used > 0)
                    if self.converged:
                        break
                    earliest = earliest_convergence(means, s.window_periods, run_in)
                    if earliest > nsteps // per_period:
                        after = "the run-in and " if run_in else ""
                        out_of_reach = (f"no stationary window within the sliding budget: "
                                        f"after period {k // per_period} the window rule "
                                        f"cannot pass before period {earliest} of "
                                        f"{nsteps // per_period} (it compares "
                                        f"{2 * s.window_periods} periods after {after}"
                                        f"after any period without a finite mean: no load on "
                                        f"the contact)")
                        break
                    self._project_wall_time(k // per_period, earliest, t)
                if history is not None and k < nsteps:
                    history.extrapolate_periodic(start)
                    start = history.snapshot()
        res = self._result(rows, distance, "ok", out_of_reach, t)
        if s.keep_state:
            res.final_state = self._final_state(offset0 - s.velocity * (t - t_s))
        return res

    def _load_from_rest(self, t_p: float, dt_p: float, F_target: float
                        ) -> tuple[float, SlidingResult | None]:
        """Load history phases 1 and 2 (module docstring): the initial contact under displacement
        control, then the compression to F_target over t_p.  Returns the time reached and None,
        or the failed result."""
        s, t = self.spec, 0.0
        # 1. initial contact under displacement control
        delta, Fz = 0.0, 0.0
        ddelta = 1e-4 * self.H
        for _ in range(60):
            target = delta + ddelta

            # loads are linear in time over the step, so a cut-back sub-step takes a part of it
            def load(tk, t0=t, lo=delta, hi=target):
                self.cmap.update_value(self.top_z_dof, -(lo + (hi - lo) * (tk - t0) / dt_p))

            ok, reason, _ = self._solve_step(t, dt_p, load)
            if not ok:
                return t, SlidingResult("failed", reason=f"initial contact: {reason}", t_reached=t)
            t, delta = t + dt_p, target
            Fz = -self._top_reaction()
            if Fz >= 0.02 * F_target:
                break
            ddelta *= 2.0
        else:
            return t, SlidingResult("failed", reason="initial contact: no load after 60 increments",
                                    t_reached=t)
        # 2. compression to p over t_p under force control
        self._switch_to_force_control()
        F0 = min(Fz, F_target)
        for k in range(1, s.compression_steps + 1):

            def load(tk, t0=t, k=k):
                Fk = F0 + (F_target - F0) * (k - 1 + (tk - t0) / dt_p) / s.compression_steps
                self.fext[:] = 0.0
                self.fext[self.top_z_dof] = -Fk

            ok, reason, _ = self._solve_step(t, dt_p, load)
            if not ok:
                return t, SlidingResult("failed", reason=f"compression: {reason}", t_reached=t)
            t += dt_p
        self.compression_contact = self.contact.state()["contact_length"] / self.L
        return t, None

    def _warm_state(self) -> InitialState | None:
        """The spec's initial state if this attempt's mesh is the one it was computed on (a
        refined fallback attempt starts from rest); stats ``warm_start`` 1 or 0."""
        state = self.spec.initial_state
        fits = (state is not None and state.mesh == mesh_digest(self.sp.node_X)
                and state.w.shape == self.sp.w.x.array.shape)
        self.warm_started = bool(fits)
        return state if fits else None

    def _restore(self, state: InitialState) -> None:
        """Take an earlier run's final state as the converged state now: displacements and
        pressures, the Prony histories at this run's temperatures, the contact's reference
        positions at the road's offset then with its stick history, force control."""
        self._switch_to_force_control()
        x = self.sp.w.x.array
        x[:] = state.w
        if self.sp.history is not None:
            self.sp.history.restore(state.history, state.sbar)
        self.problem.constraints.set_prescribed(x)
        gap = state.elastic_gap if state.elastic_gap.size else None
        self.contact.reset_history(x, (state.offset, 0.0), gap)

    def _final_state(self, offset: float) -> InitialState:
        """This attempt's converged state now, for a later run to start from (spec.keep_state)."""
        h = self.sp.history
        empty = np.zeros(0)
        return InitialState("", self.sp.w.x.array.copy(),
                            h.H.copy() if h is not None else empty,
                            h.Sbar_n.copy() if h is not None else empty,
                            float(offset % self.L) if self.spec.period > 0 else float(offset),
                            mesh_digest(self.sp.node_X), self.contact.elastic_gap(), self.refine)

    def _project_wall_time(self, done: int, earliest: int, t: float) -> None:
        """Stop a run that cannot reach a converged window before its wall-time limit: after
        ``done`` >= 2 whole periods (the run-in is not a pace), the periods still needed before
        the window rule can first pass (``earliest``, at least the next one) at the pace of the
        period that just ended take longer than the time left.  Such a run would be stopped by
        the limit anyway, later (a "timeout": recomputed on the next run of the scene).  The
        default scene's micro2 runs at 63 and 191 MPa slid 4 to 6.5 of their 12 periods at
        90-140 s each before the 600 s limit stopped them."""
        now = time.perf_counter()
        pace, self._period_wall = now - self._period_wall, now
        if self.wall_limit <= 0.0 or done < 2:
            return
        need = max(earliest, done + 1) - done
        left = self._deadline - now
        if need * pace > left:
            raise _WallLimit(t, f"projected after period {done}: {need} more period(s) before "
                                f"a converged window is possible, at {pace:.0f} s per period, "
                                f"with {max(left, 0.0):.0f} s left")

    def _solvers(self) -> list:
        """The Newton solvers of this attempt (two in the hybrid)."""
        return [self.newton] + ([self.trust] if self.trust not in (None, self.newton) else [])

    def _cpu_split(self) -> dict[str, float]:
        """CPU seconds of this attempt by part (stats ``cpu_*``): bulk forms, contact, P^T A P
        (with PETSc's assembly calls), linear solves (numeric LU + triangular solves), history
        update (eq. 3.76), and the whole attempt (set-up and Python included)."""
        asm = self.problem.cpu
        return {"cpu_bulk": asm["bulk"], "cpu_contact": asm["hooks"],
                "cpu_condense": asm["condense"],
                "cpu_linear": sum(n.cpu_linear for n in self._solvers()),
                "cpu_history": self.sp.cpu_history,
                "cpu_attempt": time.process_time() - self._cpu_start}

    def _result(self, rows, distance, status, reason, t) -> SlidingResult:
        cols = ["t", "s", "Fx", "Fz", "contact_length", "viscous_energy", "friction_energy",
                "mean_pressure", "stabilisation_energy", "stabilisation_impulse"]
        arr = np.array(rows, dtype=float).reshape(-1, len(cols))
        series = {c: arr[:, i] for i, c in enumerate(cols)}
        res = SlidingResult(status, reason=reason, t_reached=t, series=series,
                            min_det_F=self.min_det_F if math.isfinite(self.min_det_F) else math.nan,
                            road_intrusion=(self.intrusion / self.hc if self.intrusion >= 0.0
                                            else math.nan))
        lo, hi = self._window(series["s"], distance)
        res.stats = {"cutbacks": self.cutbacks, "newton_iterations": self.newton_iterations,
                     "predictor_used": self.predictor_used,
                     "extrapolation_used": self.extrapolation_used,
                     "period_used": self.period_used,
                     # extrapolated starts the guard rejected (solved again from the others)
                     "extrapolation_rejected": self.guard_rejections,
                     "extrapolation_unseen": self.extrapolation_unseen,
                     "steps": len(rows), "h_contact": self.hc,
                     "dofs": float(self.sp.w.x.array.size),
                     "stabilised_steps": self.stabilised_steps,
                     "lu_fallbacks": sum(n.lu_fallbacks for n in self._solvers()),
                     # trial steps the trust region refused (newton = "trust-region" or "hybrid")
                     "rejected_steps": float(self.trust.rejected if self.trust else 0),
                     "trust_region_solves": float(self.trust_solves),
                     "window_start": lo, "window_end": hi,
                     "compression_contact_fraction": self.compression_contact,
                     "warm_start": float(self.warm_started), **self._cpu_split()}
        if len(rows) == 0:
            return res
        Fz = series["Fz"]
        with np.errstate(divide="ignore", invalid="ignore"):
            # friction force on the block opposes +x sliding
            series["mu_force"] = -series["Fx"] / Fz
        win = series["s"] > lo + 1e-9 * max(hi, 1.0)
        if status == "ok" and np.count_nonzero(win) >= 2:
            ds = step_lengths(series["s"])[win]
            res.mu_force = float(np.sum(series["mu_force"][win] * ds) / ds.sum())
            energy = (series["viscous_energy"] + series["friction_energy"])[win].sum()
            res.mu_energy = float(energy / (np.mean(Fz[win]) * ds.sum()))
            res.mean_pressure = pooled_contact_pressure(series["mean_pressure"][win],
                                                        series["contact_length"][win])
            res.contact_fraction = float(np.mean(series["contact_length"][win]) / self.L)
            res.window_drift = window_drift(series["s"], series["mu_force"], lo, hi)
            res.contact_drift = window_drift(series["s"], series["contact_length"] / self.L, lo, hi)
            res.stabilisation_share = stabilisation_share(series, win, ds, self.spec.velocity,
                                                          self.spec.pressure * self.L)
            self._stationarity(res, series)
        return res

    def _window(self, s_done: np.ndarray, distance: float) -> tuple[float, float]:
        """(start, end) sliding distance of the averaging window (driver.sliding.window)."""
        spec = self.spec
        if spec.converge_tol > 0 and spec.period > 0:
            end = spec.period * math.floor(float(np.max(s_done, initial=0.0)) / spec.period + 1e-9)
            w = self.window_used or spec.window_periods
            return max(0.0, end - w * spec.period), end
        return spec.window_start * distance, distance

    def _stationarity(self, res: SlidingResult, series: dict[str, np.ndarray]) -> None:
        """Converged rule: whether the run got there, the period means and the error estimate;
        fixed rule: half the window drift as the error estimate."""
        spec = self.spec
        if spec.converge_tol > 0 and spec.period > 0:
            w = self.window_used or spec.window_periods
            means = period_means(series["s"], series["mu_force"], spec.period)
            contact = period_means(series["s"], series["contact_length"] / self.L, spec.period)
            res.converged = 1.0 if self.converged == 1.0 else 0.0
            res.mu_error = error_estimate(means, w)
            res.contact_error = error_estimate(contact, w)
            res.stats["period_mu"] = [float(m) for m in means]
            res.stats["period_contact"] = [float(c) for c in contact]
        else:
            res.mu_error = 0.5 * abs(res.window_drift)
            res.contact_error = 0.5 * abs(res.contact_drift)
        if spec.period > 0:
            res.stats["periods"] = round(float(series["s"][-1] / spec.period), 6)


def pooled_contact_pressure(step_pressure: np.ndarray, contact_length: np.ndarray) -> float:
    """Eq. (6.11): the contact pressures of all contact nodes of all time steps, each weighted by
    its contact area, averaged: sum_t p_t A_t / sum_t A_t with a step's area-weighted mean
    pressure p_t over its contact length A_t.  (The mean of the p_t would weigh a step with a
    small contact patch, whose pressure is high, as much as one with a large patch.)  NaN
    without contact."""
    area = float(np.sum(contact_length))
    return float(np.sum(step_pressure * contact_length) / area) if area > 0.0 else math.nan


def stabilisation_share(series: dict[str, np.ndarray], win: np.ndarray, ds: np.ndarray,
                        velocity: float, load: float = 0.0) -> float:
    """What the stabilising dashpots carry of a window (driver.fe.stabilisation): the largest of
    their work and of the work equivalent of their net x-force (impulse sum F_x,d dt times v) over
    the friction work sum |F_x| ds, and of the part of the normal ``load`` (p l, held on the top
    edge) that the contact does not carry in the stabilised steps, sum |p l - F_z| ds over
    p l sum ds (quasi-static: the dashpots carry it; a stabilised step can hold the block with the
    contact carrying nothing).  0 without stabilised sub-steps."""
    work = float(np.sum(np.abs(series["Fx"][win]) * ds))
    if not work > 0.0:
        return math.nan
    energy = float(np.sum(series["stabilisation_energy"][win]))
    impulse = abs(float(np.sum(series["stabilisation_impulse"][win]))) * velocity
    normal = 0.0
    if load > 0.0:
        stab = ((series["stabilisation_energy"][win] != 0.0)
                | (series["stabilisation_impulse"][win] != 0.0))
        missing = np.abs(load - np.abs(series["Fz"][win][stab]))
        normal = float(np.sum(missing * ds[stab])) / (load * ds.sum())
    return max(energy / work, impulse / work, normal)


def run_sliding(spec: SlidingSpec, progress=None, observers=(),
                wall_limit: float = 0.0) -> SlidingResult:
    """Run one sliding run with the default mesh and contact; never raises for a failed run.

    ``wall_limit`` > 0 stops a run that is still going after that many seconds with a structured
    failure (``stats["failure"] == "wall_limit"``), e.g. for sweeps over extreme settings.
    With ``spec.shortcut`` a run that ``driver.sliding.shortcut.check`` admits (frictionless,
    full contact, small slopes) is the linear viscoelastic closed form, not an FE run.
    """
    if spec.shortcut:
        admitted = shortcut.check(spec)
        if admitted.admitted:
            return shortcut.closed_form_result(spec, admitted)
    try:
        return SlidingRun(spec, block_mesh, sliding_contact, progress=progress,
                          observers=observers, wall_limit=wall_limit).run()
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
