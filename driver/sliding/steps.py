"""Step control of a sliding run: one load step with cut-backs, and the Newton start of a sub-step.

A step that does not converge (or inverts an element) is retried with half the sub-step
(cut-back); sub-steps grow again after easy successes; a sub-step that still fails after
``stabilise_after`` cut-backs (or at the last one) is retried with viscous stabilisation up the
ladder ``spec.STABILISATION_LADDER`` (``driver.fe.stabilisation``, thesis 6.3.3).  A sliding
sub-step starts Newton from the best of several candidate iterates (:meth:`StepControl._start`).
The state here lives for one attempt of :class:`~rubberfriction.driver.sliding.run.SlidingRun`;
the solid, contact and solvers it drives are the run's.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections import deque
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from rubberfriction.driver.fe.contact import RigidMaster
from rubberfriction.driver.sliding.spec import (
    STABILISATION_LADDER,
    STABILISE_AFTER,
    STABILISED_ITERATIONS,
    STABILISED_STAGNATION,
)

#: a sub-step converging in at most this many Newton iterations counts as easy; EASY_STREAK easy
#: sub-steps in a row double the sub-step length (one would make it oscillate: double, fail, halve)
EASY_ITERATIONS = 6
EASY_STREAK = 2
#: after a rejected extrapolated start the next 1, 2, 4, ... (at most this many) sub-steps start
#: without it, until one from it converges within the guard again
MAX_BACKOFF = 32
#: Newton starts a sliding sub-step chooses from (:meth:`StepControl._start`): the last state,
#: the translation, the extrapolated last increment (guarded, :meth:`StepControl._guarded`) and
#: the state one period earlier at the same phase (periodic cells) and a recent state moved by
#: whole element columns (:class:`ColumnShift`); ``bench sliding --part start`` compares them
START_CANDIDATES = ("last", "translation", "extrapolation", "period", "column")
#: converged sub-steps kept for the "column" start (a column is two steps at the shipped step
#: of half an element, eight sub-steps after two cut-backs)
COLUMN_PAST = 9
#: Newton iterations an extrapolated start may take before the sub-step is solved again from
#: the other starts (0: unguarded)
EXTRAPOLATION_GUARD = 6
#: extrapolated starts that won the residual comparison in a row, after which as many are
#: taken without computing the starts' residuals (0: always compared)
UNSEEN_AFTER = 16


class WallLimit(Exception):
    """The run's wall-time limit passed (raised between sub-steps, caught in SlidingRun.run)."""

    def __init__(self, t: float, projected: str = ""):
        super().__init__(t)
        self.t = t
        self.projected = projected  # why the limit will pass before the run can converge


class StepControl:
    """Sub-stepping, cut-backs and Newton starts of one attempt, with their counters.

    ``run`` provides the current ``spec``, the wall-clock ``_deadline`` and the attempt's
    ``model`` (``driver.sliding.model``: the solid, contact, solvers, stabiliser and element
    check), read when used (the deadline moves when an observer's time is excluded).
    """

    def __init__(self, run: Any, start_candidates: tuple[str, ...] = START_CANDIDATES,
                 extrapolation_guard: int = EXTRAPOLATION_GUARD,
                 unseen_after: int = UNSEEN_AFTER, stabilise_after: int = STABILISE_AFTER):
        self.run = run
        self.start_candidates = start_candidates
        self.extrapolation_guard = extrapolation_guard
        self.unseen_after = unseen_after
        self.stabilise_after = stabilise_after  # cut-backs before a sub-step is stabilised
        self.cutbacks = self.newton_iterations = 0
        self.predictor_used = 0  # sub-steps started from the translation
        self.extrapolation_used = 0  # sub-steps started from the extrapolated increment
        self.period_used = 0  # steps started from the state one period earlier
        self.column_used = 0  # sub-steps started from a recent state moved by whole columns
        # sliding: the "column" start's shifter (None: not a structured periodic block) and the
        # last converged sub-steps as (road offset, state)
        self.column_shift: ColumnShift | None = None
        self.past: deque[tuple[float, np.ndarray]] = deque(maxlen=COLUMN_PAST)
        self.guard_rejections = 0  # extrapolated starts the guard rejected
        self.extrapolation_unseen = 0  # of extrapolation_used: taken without comparing residuals
        self.stabilised_steps = 0
        self.trust_solves = 0  # hybrid: sub-steps handed to the trust region
        self.min_det_F = math.inf
        # energies of the step being solved (reset by begin_step)
        self.step_energy = self.step_friction_energy = 0.0
        self.step_stabilisation_energy = self.step_stabilisation_impulse = 0.0
        # the step's frictional dissipation as the contact law books it (the heat source of the
        # thermal coupling, consistent with the law's heat fluxes) and by the trapezoidal rule
        # (the energy balance), what the contact takes up (:meth:`_book_contact_work`), and the
        # force on the slave nodes and the road's offset at the last converged sub-step
        self.step_friction_dissipation = self.step_interface_energy = 0.0
        self._slave_force: np.ndarray | None = None
        self._road_offset: tuple[float, float] | None = None
        self._traction: np.ndarray | None = None  # per slave node, at the last converged sub-step
        self._frame: np.ndarray | None = None  # ... its contact normal
        self._weight: np.ndarray | None = None  # ... its mortar weight
        self.easy = 0  # easy sub-steps in a row
        self.h_next = math.inf  # sliding: the sub-step length carried to the next step
        # sub-steps without the extrapolation after rejections, and the unseen-start counters
        self._backoff = self._skip = self._streak = self._unseen = 0
        self.last_increment: tuple[np.ndarray, float] | None = None  # (x_n - x_prev, h_prev)

    def begin_step(self) -> None:
        """A new load step: its energies start from zero."""
        self.step_energy = self.step_friction_energy = 0.0
        self.step_stabilisation_energy = self.step_stabilisation_impulse = 0.0
        self.step_friction_dissipation = self.step_interface_energy = 0.0

    # --- one step with cut-backs ---------------------------------------------------------------
    def solve(self, t: float, dt: float, apply_load, predict=None, adaptive: bool = False,
              period_guess: np.ndarray | None = None) -> tuple[bool, str, int]:
        """Advance from t to t + dt (sub-stepping on failure). Returns (ok, reason, cutbacks).

        predict(h), if given, moves the start iterate of a sub-step of length h (not the result);
        it is kept only where it lowers the start residual (see :meth:`_start`), as is
        ``period_guess`` for the whole step.  The sub-step length halves on failure and doubles
        (up to dt) after EASY_STREAK sub-steps in a row that converged in at most EASY_ITERATIONS
        iterations; the step fails when it would fall below dt / 2**max_cutbacks. ``adaptive``:
        the sub-step length is also remembered from step to step (sliding phase), so a step after
        a hard one does not first repeat its failed attempts.
        """
        run, m = self.run, self.run.model
        sp, spec = m.sp, run.spec
        cutbacks, t_cur = 0, t
        # h_goal: the sub-step length the control asks for; h: that length clipped to what is
        # left of the step.  Only h_goal is carried on (doubling a sub-step near a step's end
        # would otherwise be lost to the clip, and a run stay at half steps after one cut-back)
        h_goal = min(dt, self.h_next) if adaptive else dt
        while t_cur < t + dt - 1e-12 * dt:
            if time.perf_counter() > run._deadline:
                raise WallLimit(t_cur)
            h = min(h_goal, t + dt - t_cur)
            x_saved = sp.w.x.array.copy()
            apply_load(t_cur + h)
            sp.prepare_step(h)
            m.contact.set_time_step(h)
            full = abs(h - dt) <= 1e-12 * dt and t_cur == t  # the whole step: its phase is known
            start = (self._start(predict, h, x_saved,
                                 period_guess=period_guess if full else None)
                     if adaptive else "last")
            hybrid = m.trust is not None and m.trust is not m.newton
            x_start = sp.w.x.array.copy() if hybrid else None
            if start == "extrapolation" and self.extrapolation_guard > 0:
                res, redo_start = self._guarded(predict, h, x_saved)
                if hybrid and redo_start is not None:
                    x_start = redo_start
            else:
                res = m.newton.solve()
            self.newton_iterations += res.iterations
            if not res.converged and hybrid:
                # the sub-step again from the same start, with the trust region
                sp.w.x.array[:] = x_start
                res = m.trust.solve()
                self.newton_iterations += res.iterations
                self.trust_solves += 1
            ok, reason = res.converged, res.reason
            if ok and m.inverted():
                ok, reason = False, m.bad_element_reason()
            floor = dt * 0.5**spec.max_cutbacks * (1.0 - 1e-9)
            if not ok and spec.stabilisation > 0.0 and (cutbacks >= self.stabilise_after
                                                        or 0.5 * h < floor):
                ok, res = self._stabilised(h, x_saved, predict, adaptive)
            if ok:
                if "extrapolation" in self.start_candidates:  # only then is it read
                    self.last_increment = (sp.w.x.array - x_saved, h)
                if self.column_shift is not None and adaptive:
                    self.past.append((m.contact.offset[0], sp.w.x.array.copy()))
                self.min_det_F = min(self.min_det_F, m.iterate_det_F)
                self.step_energy += sp.commit_step()
                self._book_contact_work(x_saved)
                m.contact.commit()
                t_cur += h
                self.easy = self.easy + 1 if res.iterations <= EASY_ITERATIONS else 0
                if self.easy >= EASY_STREAK:
                    h_goal, self.easy = min(dt, 2.0 * h_goal), 0
                if adaptive:
                    self.h_next = h_goal
                continue
            sp.w.x.array[:] = x_saved
            self.easy = 0
            cutbacks += 1
            self.cutbacks += 1
            h_goal = 0.5 * h
            if h_goal < floor:
                if adaptive:
                    self.h_next = dt
                return False, reason, cutbacks
            if adaptive:
                self.h_next = h_goal
        return True, "", cutbacks

    def _book_contact_work(self, x_saved: np.ndarray) -> None:
        """The contact's energies of a converged sub-step from x_saved to the state now, added to
        the step's: the frictional dissipation as the contact law books it
        (``step_friction_energy``) and by the trapezoidal rule (``step_friction_dissipation``),
        and what the contact takes up itself (``step_interface_energy``), the last two booked
        like the rubber's dissipation (``forms.viscoelastic``; docs/notes-energy.md, "Where the
        balance goes").

        Friction: sum_A w_A (|t_A,n+1| + sign(t_A,n+1) t_A,n) / 2 dgamma_A over the slipping
        nodes (w_A the mortar weight, t_A the tangential traction, dgamma_A the slip of the
        return mapping), and on a rigid road w_A,n |t_A,n| / 2 |tau_A,n . (du_A - d(offset))|
        over the nodes that left contact within the step (open at its end, so without a slip
        of the law: the trapezoid with t_A,n+1 = 0 over their relative tangential motion).
        The contact law's own figure, w_A |t_A,n+1| dgamma_A, books the end-of-step traction
        over the whole slip and nothing for a node that left: a node entering contact within a
        step dissipates as if it had slid at full traction from its start, one leaving it not at
        all.  That was the friction runs' energy gap up to 0.29.0 (the macro friction run of the
        four-scale point: -3.2 % at the shipped step, first order in it, while mu_force moves by
        0.4 % over four halvings; -0.6 % with the entering nodes booked alone, +0.8 % with both).
        The first sub-step of an attempt, without an earlier traction, books the law's figure.
        The law's figure stays the thermal coupling's heat source (``step_friction_energy``),
        which its per-node heat fluxes carry.

        Interface (rigid road only): the road's work F_total . d(offset) minus the frictional
        dissipation and minus the work on the rubber (F_n + F_n+1) . du / 2 (F the road's force on
        the slave nodes): 0 over a period of a steady state for a conservative contact up to
        O(dt^2); what is left is the mortar contact's non-conservation (its normal is the
        slave's, not the road's) and the implicit step's booking of the normal forces."""
        c = self.run.model.contact
        st = c.state()
        friction = float(st.get("dissipation", 0.0))
        self.step_friction_energy += friction
        if "tangential_traction" not in st:
            self.step_friction_dissipation += friction
            return
        active = st["status"] > 0
        traction = np.where(active, st["tangential_traction"], 0.0)
        rigid = hasattr(c, "slave_forces") and isinstance(getattr(c, "master", None), RigidMaster)
        x = self.run.model.sp.w.x.array
        offset = (float(c.offset[0]), float(c.offset[1]))
        dofs = np.asarray(c.slave.dofs, dtype=np.int64)
        du = x[dofs] - x_saved[dofs]
        if self._traction is not None and self._traction.shape == traction.shape:
            slip = np.where(active, st["slip_increment"], 0.0)
            mean = 0.5 * (np.abs(traction) + np.sign(traction) * self._traction)
            friction = float(np.sum(st["weight"] * mean * slip))
            if rigid and self._road_offset is not None and self._frame is not None:
                # nodes that left contact within the step: half the step at their last traction
                left = (self._traction != 0.0) & ~active
                rel = du - (np.asarray(offset) - np.asarray(self._road_offset))[None, :]
                tau = np.stack([-self._frame[:, 1], self._frame[:, 0]], axis=1)
                g = np.abs(np.sum(tau * rel, axis=1))
                friction += float(np.sum((0.5 * self._weight * np.abs(self._traction) * g)[left]))
        self._traction = traction
        self._frame, self._weight = np.asarray(st["normal"]).copy(), np.asarray(st["weight"]).copy()
        self.step_friction_dissipation += friction
        if not rigid:
            return
        force = c.slave_forces(x)
        if self._slave_force is not None and self._road_offset is not None:
            total = force.sum(axis=0)
            road = (total[0] * (offset[0] - self._road_offset[0])
                    + total[1] * (offset[1] - self._road_offset[1]))
            rubber = 0.5 * float(np.sum((force + self._slave_force) * du))
            self.step_interface_energy += road - friction - rubber
        self._slave_force, self._road_offset = force, offset

    # --- stabilisation ---------------------------------------------------------------------------
    def _stabilised(self, h: float, x_saved: np.ndarray, predict,
                    sliding: bool = False) -> tuple[bool, object]:
        """The failed sub-step again with viscous stabilisation (driver.fe.stabilisation), beta
        up the ladder spec.stabilisation x STABILISATION_LADDER until Newton converges; the
        dashpots' work and net x-force are added to the step's (series ``stabilisation_energy``,
        ``stabilisation_impulse``).  The load of the sub-step is already applied."""
        newton = self.run.model.newton
        plain = newton.settings
        newton.settings = dataclasses.replace(plain, max_iterations=STABILISED_ITERATIONS,
                                              stagnation=STABILISED_STAGNATION)
        try:
            return self._ladder(h, x_saved, predict, sliding)
        finally:
            newton.settings = plain
            self.run.model.stabiliser.deactivate()

    def _ladder(self, h: float, x_saved: np.ndarray, predict,
                sliding: bool = False) -> tuple[bool, object]:
        run, m = self.run, self.run.model
        pb, damper, x_now = m.problem, m.stabiliser, m.sp.w.x.array
        x_now[:] = x_saved
        damper.deactivate()
        pb.constraints.set_prescribed(x_now)
        pb.assemble(need_vector=False)
        diagonal = pb.A.getDiagonal().array.copy()  # of the tangent at u_n, for every rung
        res = None
        for factor in STABILISATION_LADDER:
            x_now[:] = x_saved
            damper.activate(run.spec.stabilisation * factor, diagonal, x_saved)
            if sliding:  # not the extrapolation: unguarded, it may choose another branch
                self._start(predict, h, x_saved, exclude=("extrapolation",))
            res = m.newton.solve()
            self.newton_iterations += res.iterations
            if res.converged and not m.inverted():
                x = m.sp.w.x.array
                fx = float(np.sum(damper.forces(x)[m.stabilised_x]))
                self.step_stabilisation_energy += damper.energy(x)
                self.step_stabilisation_impulse += fx * h
                self.stabilised_steps += 1
                return True, res
        x_now[:] = x_saved
        return False, res

    # --- Newton starts ---------------------------------------------------------------------------
    def _guarded(self, predict, h: float, x_saved: np.ndarray) -> tuple[Any, np.ndarray | None]:
        """Newton from the extrapolated start, allowed ``extrapolation_guard`` iterations.  A
        start near the continuation of the path converges within them; one that needs more has
        left it and may be heading for another equilibrium, so the sub-step is solved again from
        the other starts (the iterations of both count) and the next 1, 2, 4, ... MAX_BACKOFF
        sub-steps do without the extrapolation (where it does not pay, its rejections would
        otherwise double their cost).  Returns Newton's result and, after a rejection, the start
        of the solve again (None when the extrapolated start converged)."""
        m = self.run.model
        plain = m.newton.settings
        m.newton.settings = dataclasses.replace(plain, max_iterations=self.extrapolation_guard)
        try:
            res = m.newton.solve()
        finally:
            m.newton.settings = plain
        if res.converged:
            self._backoff = 0
            return res, None
        self.guard_rejections += 1
        self._streak = self._unseen = 0  # compare the starts again
        self._backoff = min(2 * self._backoff or 1, MAX_BACKOFF)
        self._skip = self._backoff
        self.newton_iterations += res.iterations
        m.sp.w.x.array[:] = x_saved
        self._start(predict, h, x_saved, exclude=("extrapolation",))
        redo_start = m.sp.w.x.array.copy()
        return m.newton.solve(), redo_start

    def _start(self, predict, h: float, x_saved: np.ndarray, exclude: tuple[str, ...] = (),
               period_guess: np.ndarray | None = None) -> str:
        """Newton start of a sliding sub-step of length h, returned by name: of the last converged
        state, the translation prediction (``predict``, periodic cells), the extrapolation of the
        last converged sub-step's increment (unless backing off after a rejected one, see
        :meth:`_guarded`) and the period start, the one with the lowest residual (each costs one
        residual assembly); ``exclude`` leaves candidates out.  Once the extrapolation has won
        ``unseen_after`` comparisons in a row, as many next sub-steps take it unseen, then one
        comparison decides again (a rejection by the guard starts the count anew; unguarded, it
        is always compared): where it always wins, comparing is pure cost.

        Extrapolation: x_n + (h / h_prev) (x_n - x_prev), the forward-Euler predictor of the
        displacement path: on steep micro cells the other starts are far from the solution (the
        translation interpolates contact nodes into the road's flanks).  A start can choose the
        branch where the discrete equilibrium is not unique, so it is used through the guard only
        and never in the stabilisation ladder (docs/history.md, "Start iterate").

        Period (``period_guess``, whole steps of a periodic cell from its second period on): the
        converged state one period earlier at the same phase plus the drift between the periods
        at the step before, x(t - T) + (x_n - x(t_n - T)).  In a periodic steady state it is the
        solution itself; while a run still settles it carries the active set of the last period.
        Always compared (never taken unseen).

        Column (:meth:`_column_guess`): the same travelling-wave idea one element column back
        instead of one period: a state a few sub-steps old, fresher than the period's.  Always
        compared.  Where it exists the translation is left out: the same move, interpolated
        (on the four-scale point's micro2 run it won 14 of 2354 comparisons against it)."""
        wanted = tuple(c for c in self.start_candidates if c not in exclude)
        candidates: list[tuple[str, Any]] = [("last", None)]
        column = (self._column_guess(x_saved)
                  if "column" in wanted and self.column_shift is not None else None)
        if predict is not None and "translation" in wanted and column is None:
            candidates.append(("translation", predict))  # the column's interpolated sibling
        inc = self.last_increment
        if "extrapolation" in wanted and self._skip > 0:
            self._skip -= 1  # backing off after a rejected extrapolation (_guarded)
        elif ("extrapolation" in wanted and inc is not None and inc[0].shape == x_saved.shape
                and inc[1] > 0.0):
            candidates.append(("extrapolation", x_saved + (h / inc[1]) * inc[0]))
        if "period" in wanted and period_guess is not None and period_guess.shape == x_saved.shape:
            candidates.insert(1, ("period", period_guess))
        if column is not None:
            candidates.insert(1, ("column", column))
        if len(candidates) < 2:
            return "last"  # the last state (already the iterate): nothing to compare
        pb = self.run.model.problem
        x = self.run.model.sp.w.x.array
        best, best_r = "last", math.inf
        best_x = x_saved
        if (candidates[-1][0] == "extrapolation" and self._unseen > 0
                and candidates[1][0] not in ("period", "column")):
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
        self.column_used += best == "column"
        if candidates and candidates[-1][0] == "extrapolation":
            self._streak = self._streak + 1 if best == "extrapolation" else 0
            if 0 < self.unseen_after <= self._streak and self.extrapolation_guard > 0:
                self._unseen = self.unseen_after
        return best

    def _column_guess(self, x_saved: np.ndarray) -> np.ndarray | None:
        """The "column" start of the sub-step to the road offset now set: the latest kept state
        whose road stood k >= 1 whole columns ahead, moved by k columns, plus the drift the
        same move missed at the last converged sub-step,

            S_k x(o + k h) + (x_n - S_k x(o_n + k h)),

        (o the target offset, o_n the last one, h the column width, S_k the move).  The
        deformation of steady sliding travels with the road (u(X, t) = U(X + v t) in the block
        frame), and a move by whole columns of the structured block is a permutation of its
        nodes, with nothing interpolated (the "translation" start interpolates contact nodes
        into the road's flanks).  Without the drift term where its state is not kept."""
        shift, past = self.column_shift, self.past
        if shift is None or not past or past[-1][1].shape != x_saved.shape:
            return None
        target = self.run.model.contact.offset[0]

        def kept(offset: float) -> tuple[int, np.ndarray] | None:
            for o, x in reversed(past):
                k = (o - offset) / shift.h
                if round(k) >= 1 and abs(k - round(k)) < 1e-6:
                    return int(round(k)), x
            return None

        found = kept(target)
        if found is None:
            return None
        k, x_old = found
        guess = shift(x_old, k)
        o_n, x_n = past[-1]
        for o, x in past:
            if abs((o - o_n) / shift.h - k) < 1e-6:
                return guess + (x_n - shift(x, k))
        return guess


class ColumnShift:
    """A state of the structured periodic block moved by whole element columns against x:
    ``shift(x, k)`` is x with every node's displacements (and every cell's pressure) taken from
    the node (cell) k columns further in +x, periodic in L: u_new(X) = u(X + k h).  Build it
    with :func:`column_shift`."""

    def __init__(self, h: float, node_dofs: np.ndarray, node_next: np.ndarray,
                 cell_dofs: np.ndarray | None, cell_next: np.ndarray | None):
        self.h = h  # column width (mm)
        self.node_dofs, self.node_next = node_dofs, node_next  # (n, 2) dofs; node one column on
        self.cell_dofs, self.cell_next = cell_dofs, cell_next  # pressure dof per cell, or None
        self._maps: dict[int, tuple[np.ndarray, np.ndarray | None]] = {}

    def maps(self, k: int) -> tuple[np.ndarray, np.ndarray | None]:
        """(node, cell) each node (cell) takes its values from in a move by k columns."""
        if k not in self._maps:
            nodes = np.arange(self.node_next.size)
            cells = None if self.cell_next is None else np.arange(self.cell_next.size)
            for _ in range(k):
                nodes = self.node_next[nodes]
                cells = None if cells is None else self.cell_next[cells]
            self._maps[k] = (nodes, cells)
        return self._maps[k]

    def __call__(self, x: np.ndarray, k: int) -> np.ndarray:
        nodes, cells = self.maps(k)
        out = x.copy()
        out[self.node_dofs] = x[self.node_dofs[nodes]]
        if cells is not None:
            out[self.cell_dofs] = x[self.cell_dofs[cells]]
        return out


def column_shift(sp, L: float) -> ColumnShift | None:
    """The :class:`ColumnShift` of a periodic block of length L whose nodes lie on equal
    columns of width h (``meshes.block``: the same x-columns at every height, L / h of them),
    or None when the mesh is not such a block."""
    X = sp.node_X
    x0 = X[:, 0].min()
    face = np.unique(np.round((X[:, 0] - x0) / L, 9)) * L
    n = face.size - 1
    if n < 2 or not np.allclose(np.diff(face), L / n, rtol=1e-6, atol=0.0):
        return None
    h = L / n
    tol = 1e-6 * h

    def next_of(points: np.ndarray) -> np.ndarray | None:
        moved = points.copy()
        moved[:, 0] = (points[:, 0] - x0 + h) % L + x0
        wrap = moved[:, 0] > x0 + L - 0.5 * h  # the periodic image at x0 + L -> x0
        moved[wrap, 0] -= L
        tree = cKDTree(np.where(np.isclose(points[:, 0], x0 + L, atol=tol)[:, None],
                                points - [L, 0.0], points))
        dist, idx = tree.query(moved)
        return idx if dist.max() <= tol else None

    node_next = next_of(X)
    if node_next is None:
        return None
    node_dofs = np.asarray(sp.displacement_dofs(), dtype=np.int64)
    cell_dofs = cell_next = None
    if sp.settings.mixed:
        Q, pmap = sp.W.sub(1).collapse()
        n_cells = sp.cell_centroids().shape[0]
        cell_dofs = np.asarray(pmap, dtype=np.int64)[
            np.asarray(Q.dofmap.list.array, dtype=np.int64).reshape(-1)[:n_cells]]
        cell_next = next_of(sp.cell_centroids())
        if cell_next is None:
            return None
    return ColumnShift(h, node_dofs, node_next, cell_dofs, cell_next)


def translation_predictor(sp, L: float, H: float, velocity: float):
    """Start iterate for a sliding step of a periodic cell: steady sliding carries the
    deformation along with the surface, u_{n+1}(X) ~ u_n(X + v h) (periodic in x).  Nodes of
    the structured block lie on rows of equal z; each row is interpolated in numpy.  Only the
    Newton start changes; without it a step starts far from equilibrium on steep surfaces.
    Returns predict(h), or None when the block is not structured."""
    X, v = sp.node_X, velocity
    d = sp.displacement_dofs()
    x0 = X[:, 0].min()
    rows = []
    for z in np.unique(np.round(X[:, 1], 12)):
        nodes = np.nonzero(np.abs(X[:, 1] - z) < 1e-9 * max(L, H))[0]
        nodes = nodes[np.argsort(X[nodes, 0])]
        data = nodes[:-1] if np.isclose(X[nodes[-1], 0] - X[nodes[0], 0], L) else nodes
        rows.append((nodes, data))  # the right-edge node is the left one's periodic image
    if sum(r[0].size for r in rows) < X.shape[0]:
        return None  # not a structured block: no predictor

    def predict(h: float) -> None:
        shift = v * h
        x = sp.w.x.array
        for nodes, data in rows:
            xd = X[data, 0] - x0
            xe = (X[nodes, 0] - x0 + shift) % L
            for c in (0, 1):
                x[d[nodes, c]] = np.interp(xe, xd, x[d[data, c]], period=L)

    return predict
