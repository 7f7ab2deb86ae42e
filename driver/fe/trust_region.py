"""Trust-region Newton on the incremental potential: the globalisation for conservative steps.

Why.  Newton with a residual line search (``newton.py``) stagnates on the default road's lowest
scale: where a pressed node sits on a road peak sharper than its element the tangent turns
indefinite (the node wants to slide off the peak) and the residual norm has local minima that
are no equilibria (README, lowest-scale failures).  A frictionless step of a rubber cell on a
rigid road with node-to-surface contact (``Contact(method="surface")``) is conservative: it is
the stationarity of an incremental potential Pi(u),

    Pi = int [(1 + beta) W_iso(Cbar) + 1/2 Hstar : Cbar] dV + sum_e |e| K/2 <g(J)>_e^2
         + sum_A w_A c_N <-g_A>^2 / 2 - F_ext . u  (+ the stabilising dashpots' quadratic),

because the step's algorithmic stress (eq. 3.77 collapsed, ``forms/viscoelastic.py``) is
S = 2 dW/dC of the bracket: beta and Hstar are fixed within a step (J^(-2/3) DEV{Hstar} =
2 d(Hstar : Cbar / 2)/dC), the Q1P0 pressure is the cell mean of K g(J) (eq. 3.61 with a
constant test function) and the node-to-surface penalty force is the gradient of its potential.
Minimising Pi converges to an equilibrium from any start: a local minimum of Pi has zero
residual, where a local minimum of |R| need not.

How.  Levenberg-Marquardt steps on Pi: solve (K + lambda D) d = -R with D the tangent's diagonal
on the displacement dofs (lambda = 0: the Newton step), accept when Pi falls by at least
``ACCEPT`` times what the quadratic model predicts, and grow lambda (shorter, more gradient-like
steps) until it does.  Pi itself is never assembled: its change along the step is the work of the
residual, Delta Pi = int_0^1 R(u + t d) . d dt, taken with Simpson's rule (residuals at t = 1/2
and 1), which has no cancellation near convergence where Pi(u + d) - Pi(u) would.  The model
decrease is m = R.d + d.K d / 2 = (R.d - lambda d.D d) / 2.  Before every residual the Q1P0
pressures are set to their cell optimum (``relax``), so R is the gradient of Pi(u) with p
eliminated and the mixed saddle-point system needs no special treatment (d.K d of the mixed
reduced system is d_u . K_cond d_u, the Schur complement, when the pressure residual is zero).

Where the problem is not conservative (mortar or node-to-segment contact, friction) the same
iteration still runs, with the residual's work as a merit function that is no longer exact.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
from petsc4py import PETSc

from rubberfriction.driver.fe.newton import NewtonResult, NewtonSolver

#: accept a step whose actual decrease of Pi is at least this share of the model's
ACCEPT = 0.1
#: above this share the model is trusted more: lambda shrinks by SHRINK
GOOD = 0.75
SHRINK = 0.25
#: lambda grows by this factor after a rejected step (or a non-descent direction)
GROW = 8.0
#: first nonzero lambda (relative to the tangent's diagonal) and the largest before giving up
LAMBDA_START = 1e-3
LAMBDA_MAX = 1e8
#: below this lambda is set to 0 (the Newton step)
LAMBDA_MIN = 1e-9


class TrustRegionSolver(NewtonSolver):
    """Newton's method globalised by a trust region on the incremental potential (module doc).

    ``relax(x)``: sets the locally eliminated unknowns of the full-space state x (the Q1P0 cell
    pressures) to their optimum for the displacements in x; None when there are none.
    ``displacement_dofs``: full-space dofs that are displacements (the shift acts on them only).
    Counts one iteration per linear solve (trial step).
    """

    def __init__(self, problem, settings=None, force_scale: float = 1.0,
                 relax: Callable[[np.ndarray], None] | None = None,
                 displacement_dofs: np.ndarray | None = None, on_iteration=None):
        super().__init__(problem, settings, force_scale=force_scale, on_iteration=on_iteration)
        self.relax = relax
        self._udofs = None if displacement_dofs is None else np.asarray(displacement_dofs)
        self._mask_for: PETSc.Mat | None = None
        self._mask: np.ndarray | None = None
        self.lam = 0.0  # kept between solves: a hard step's successor starts where it ended
        self.rejected = 0  # trial steps refused (all solves)

    def _reduced_mask(self) -> np.ndarray:
        """1 on reduced dofs that are displacements, 0 on the rest (pressures)."""
        P = self.problem.P
        if self._mask_for is not P:
            full = P.createVecLeft()
            if self._udofs is None:
                full.set(1.0)
            else:
                full.set(0.0)
                full.array[self._udofs] = 1.0
            red = P.createVecRight()
            P.multTranspose(full, red)
            self._mask = (np.abs(red.array) > 0.0).astype(float)
            self._mask_for = P
        return self._mask

    def _residual_at(self, x: np.ndarray, x_new: np.ndarray) -> np.ndarray:
        """The reduced residual at x_new (written into the state x), pressures relaxed."""
        pb = self.problem
        x[:] = x_new
        if self.relax is not None:
            self.relax(x)
        pb.assemble(need_matrix=False)
        return pb.br.array.copy()

    def _iterate(self, res: NewtonResult) -> None:
        s, pb = self.settings, self.problem
        x = pb.w.x.array
        pb.constraints.set_prescribed(x)
        if self.relax is not None:
            self.relax(x)
        t0 = time.perf_counter()
        pb.assemble()
        res.time_assemble += time.perf_counter() - t0
        r0 = pb.br.array.copy()
        rn = float(np.linalg.norm(r0))
        res.residuals.append(rn)
        if not np.isfinite(rn):
            res.reason = "residual is not finite (element inversion or overflow)"
            return
        tol = s.atol + s.rtol * max(rn, self.force_scale)
        if rn <= tol:
            res.converged = True
            return
        mask = self._reduced_mask()
        diag0 = pb.Ar.getDiagonal()
        D = np.maximum(np.abs(diag0.array), 1e-300) * mask
        shifted = diag0.duplicate()
        lam = self.lam
        floor = 0.0  # above the largest shift that gave no descent in this solve
        for it in range(1, s.max_iterations + 1):
            t1 = time.perf_counter()
            shifted.array[:] = diag0.array + lam * D
            pb.Ar.setDiagonal(shifted)
            pb.br.array[:] = r0
            res.reason = self._solve_direction(res)
            if res.reason:
                return
            d = pb.dur.array.copy()
            res.time_solve += time.perf_counter() - t1
            res.iterations = it
            model = 0.5 * (float(r0 @ d) - lam * float(d @ (D * d)))
            if not (np.isfinite(model) and model < 0.0):  # no descent: shift more
                floor = max(floor, 2.0 * lam)
                lam = max(GROW * lam, LAMBDA_START)
                self.rejected += 1
                if lam > LAMBDA_MAX:
                    break
                continue
            t1 = time.perf_counter()
            x0 = x.copy()
            pb.P.mult(pb.dur, pb.du)
            du = pb.du.array.copy()
            r_mid = self._residual_at(x, x0 + 0.5 * du)
            r1 = self._residual_at(x, x0 + du)
            actual = float((r0 + 4.0 * r_mid + r1) @ d) / 6.0
            rho = actual / model if np.isfinite(actual) else -np.inf
            r1n = float(np.linalg.norm(r1))
            res.time_assemble += time.perf_counter() - t1
            if self.on_iteration:
                self.on_iteration(it, r1n)
            if not (rho >= ACCEPT and np.isfinite(r1n)):
                x[:] = x0  # refused: back, shorter step
                lam = max(GROW * lam, LAMBDA_START)
                self.rejected += 1
                if lam > LAMBDA_MAX:
                    break
                continue
            res.residuals.append(r1n)
            if rho > GOOD:  # a longer step next, but not back into known non-descent shifts
                lam = SHRINK * lam if SHRINK * lam > LAMBDA_MIN else 0.0
                lam = max(lam, floor)
            tol = s.atol + s.rtol * max(res.residuals[0], self.force_scale)
            small = np.linalg.norm(du) <= s.stol * max(np.linalg.norm(x), 1e-300)
            if r1n <= tol or (small and r1n <= 1e3 * tol):
                self.lam = lam
                res.converged = True
                return
            if r1n > s.divergence_factor * max(res.residuals[0], self.force_scale):
                res.reason = f"diverged: residual {r1n:.3e} after {it} trial steps"
                return
            t1 = time.perf_counter()
            pb.assemble(need_vector=False)  # tangent at the accepted state (br is r1 already)
            res.time_assemble += time.perf_counter() - t1
            r0 = r1
            pb.Ar.getDiagonal(diag0)
            D = np.maximum(np.abs(diag0.array), 1e-300) * mask
        self.lam = 0.0
        pb.Ar.setDiagonal(diag0)
        res.reason = ("trust region: no step lowers the potential (shift "
                      f"{lam:.1e} x diag; residual {res.residuals[-1]:.3e})"
                      if lam > LAMBDA_MAX else
                      f"trust region: no convergence in {s.max_iterations} trial steps (residual "
                      f"{res.residuals[-1]:.3e})")
