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

Periodic cells slid over whole periods (``driver.sliding.periods``): the converged-window rule at
each period end, the steady-state history jump, the period start of the Newton solves.

Outputs (``driver.sliding.result``): mu(t) = F_x/F_z (eq. 6.2) and mu from dissipated energy
(eq. 2.8: viscous (+ frictional) energy per sliding distance over F_z), their averages over the
homogenisation window, the mean contact pressure over contact nodes and steps (eq. 6.11), the
contact length (area per unit depth) and its average (7.4), dissipation by depth.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

import ufl

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import LINEAR_SOLVERS, NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.fe.stabilisation import ViscousStabilisation
from rubberfriction.driver.fe.trust_region import TrustRegionSolver
from rubberfriction.driver.sliding import shortcut, steps
from rubberfriction.driver.sliding.bodies import block_mesh, sliding_contact
from rubberfriction.driver.sliding.intrusion import road_intrusion
from rubberfriction.driver.sliding.outputs import DissipationByDepth
from rubberfriction.driver.sliding.periods import Periods, sliding_step
from rubberfriction.driver.sliding.progress import StepReporter
from rubberfriction.driver.sliding.result import (
    assemble,
    pooled_contact_pressure,
    stabilisation_share,
)
from rubberfriction.driver.sliding.steps import EASY_STREAK, StepControl, WallLimit
from rubberfriction.driver.sliding.temperature import (
    MIN_ROW_FRACTION,
    cell_temperatures,
    check_layers,
    mesh_levels,
)
from rubberfriction.driver.sliding.spec import (
    MESH_REFINEMENT,
    SOFT_TANGENT,
    STABILISE_AFTER,
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
from rubberfriction.driver.sliding.window import WINDOW_QUANTITIES
from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient

__all__ = ["Attempt", "EASY_STREAK", "NEWTON_METHODS", "SlidingRun", "block_mesh",
           "pooled_contact_pressure", "run_sliding", "sliding_contact", "sliding_runner",
           "stabilisation_share"]

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


def _of_steps(name: str) -> property:
    """A counter of the current attempt's step control, read on the run (observers, benches)."""
    return property(lambda run: getattr(run.steps, name),
                    doc=f"``steps.{name}`` of the current (or last) attempt")


class SlidingRun:
    """Set-up, load history and fallback attempts of one sliding run; `run()` returns a
    SlidingResult.  Each attempt has its step control (``steps``), its periods (``periods``)
    and its result (``driver.sliding.result``)."""

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
    guard_rejections = _of_steps("guard_rejections")
    stabilised_steps = _of_steps("stabilised_steps")
    min_det_F = _of_steps("min_det_F")
    #: energies of the sliding step just solved (on_step observers)
    step_energy = _of_steps("step_energy")
    step_friction_energy = _of_steps("step_friction_energy")

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
        self.steps: StepControl | None = None  # the current attempt's step control
        self.periods: Periods | None = None  # and its sliding periods
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
        # on steep rough samples, it also saves iterations (docs/performance.md)
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

    # --- helpers of the parts --------------------------------------------------------------------
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
            # the nodes far outside the stick cone (docs/performance.md)
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
        if s.period > 0 and hasattr(self.contact, "slave") and hasattr(self.contact, "offset"):
            self.intrusion = 0.0  # a periodic cell on the rigid road: measured (-1: not)
        F_target = s.pressure * self.L
        step_len = sliding_step(s, self.L, (s.step_length or 0.5 * self.hc) * step_factor)
        t_p = s.compression_time or self.L / (2.0 * np.pi * s.velocity)
        distance = s.slide_distance or 3.0 * (s.period if s.period > 0 else self.L)
        warm = self._warm_state()
        self.t_planned = (0.0 if warm else t_p) + distance / s.velocity  # w/o initial contact
        if warm is not None:  # slide on from an earlier run's final state (spec.InitialState)
            self._restore(warm, F_target)
            t, offset0 = 0.0, warm.offset
        else:
            t, failed = self._load_from_rest(t_p, t_p / s.compression_steps, F_target)
            if failed is not None:
                return failed
            offset0 = 0.0
        return self._slide(t, offset0, step_len, distance, warm is not None)

    def _begin_attempt(self) -> SlidingSpec:
        """Fresh per-attempt state: the step control with the run's start settings, counters."""
        self.steps = StepControl(self, self.start_candidates, self.extrapolation_guard,
                                 self.unseen_after, self.stabilise_after)
        self.periods = None
        self._cpu_start = time.process_time()
        self.compression_contact = float("nan")
        self._detF = None
        self.intrusion = -1.0  # deepest road vertex inside the rubber face over the sliding steps
        self.warm_started = False  # slid on from spec.initial_state (_warm_state)
        return self.spec

    def _slide(self, t: float, offset0: float, step_len: float, distance: float,
               warm: bool) -> SlidingResult:
        """Load history phase 3: sliding at v with p held, from time t and road offset offset0,
        until the distance is slid or the periods say stop; the attempt's result."""
        s, control = self.spec, self.steps
        dt_slide = step_len / s.velocity
        nsteps = int(np.ceil(distance / step_len))
        t_s = t
        keep = self.fext.copy()
        predict = (steps.translation_predictor(self.sp, self.L, self.H, s.velocity)
                   if s.period > 0 else None)
        self.t_start, self.slide_distance, self.dt_slide, self.n_slide_steps = (
            t_s, distance, dt_slide, nsteps)
        self._notify("on_start")
        control.h_next, control.easy = dt_slide, 0
        periods = self.periods = Periods(s, self.L, step_len, nsteps, self.sp.history, warm,
                                         self.wall_limit)
        rows: list[tuple] = []
        for k in range(1, nsteps + 1):
            control.begin_step()

            def load(tk):
                self.fext[:] = keep
                self.contact.set_master_offset(offset0 - s.velocity * (tk - t_s), 0.0)

            ok, reason, _ = control.solve(t, dt_slide, load, predict, adaptive=True,
                                          period_guess=periods.guess(k))
            if not ok:
                return assemble(self, rows, distance, "failed", f"sliding: {reason}", t)
            t += dt_slide
            periods.record(k, self.sp.w.x.array)
            rows.append(self._row(t, s.velocity * (t - t_s)))
            if self.intrusion >= 0.0:
                self.intrusion = max(self.intrusion, self._road_intrusion())
            self._notify("on_step", k, t)
            if self.progress:
                self.progress(k, nsteps)
            if periods.end_of_step(k, rows, t, self._deadline):
                break
        res = assemble(self, rows, distance, "ok", periods.out_of_reach, t)
        if s.keep_state:
            res.final_state = self._final_state(offset0 - s.velocity * (t - t_s))
        return res

    def _row(self, t: float, slid: float) -> tuple:
        """The sliding step's row of the series (result.COLUMNS)."""
        st, c = self.contact.state(), self.steps
        return (t, slid, st["Fx"], st["Fz"], st["contact_length"], c.step_energy,
                c.step_friction_energy, st["mean_pressure"], c.step_stabilisation_energy,
                c.step_stabilisation_impulse)

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
        s, t = self.spec, 0.0
        # 1. initial contact under displacement control
        delta, Fz = 0.0, 0.0
        ddelta = 1e-4 * self.H
        for _ in range(60):
            target = delta + ddelta

            # loads are linear in time over the step, so a cut-back sub-step takes a part of it
            def load(tk, t0=t, lo=delta, hi=target):
                self.cmap.update_value(self.top_z_dof, -(lo + (hi - lo) * (tk - t0) / dt_p))

            ok, reason, _ = self.steps.solve(t, dt_p, load)
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

            ok, reason, _ = self.steps.solve(t, dt_p, load)
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

    def _restore(self, state: InitialState, F_target: float) -> None:
        """Take an earlier run's final state as the converged state now: displacements and
        pressures, the Prony histories at this run's temperatures, the contact's reference
        positions at the road's offset then with its stick history, force control at
        F_target."""
        self._switch_to_force_control()
        x = self.sp.w.x.array
        x[:] = state.w
        if self.sp.history is not None:
            self.sp.history.restore(state.history, state.sbar)
        self.problem.constraints.set_prescribed(x)
        gap = state.elastic_gap if state.elastic_gap.size else None
        self.contact.reset_history(x, (state.offset, 0.0), gap)
        self.fext[:] = 0.0
        self.fext[self.top_z_dof] = -F_target

    def _final_state(self, offset: float) -> InitialState:
        """This attempt's converged state now, for a later run to start from (spec.keep_state)."""
        h = self.sp.history
        empty = np.zeros(0)
        return InitialState("", self.sp.w.x.array.copy(),
                            h.H.copy() if h is not None else empty,
                            h.Sbar_n.copy() if h is not None else empty,
                            float(offset % self.L) if self.spec.period > 0 else float(offset),
                            mesh_digest(self.sp.node_X), self.contact.elastic_gap(), self.refine)


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
