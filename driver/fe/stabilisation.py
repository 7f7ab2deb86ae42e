"""Viscous stabilisation of a load step that Newton cannot finish (a Newton hook).

The thesis recomputed its failing ABAQUS runs "by applying the NTS contact formulation or
automatic stabilization" (section 6.3.3).  Automatic stabilisation adds viscous forces that resist
the motion within a step.  Here, for one sub-step from the converged state u_n, the residual
becomes

    R_s(u) = R(u) + beta D (u - u_n),    D = diag(dR/du) at u_n,

on the dofs the caller chooses (a sliding run leaves out its loaded top row, whose reaction is
the load): a dashpot of coefficient beta D h per dof (h the sub-step length) or, equally, a
proximal term: R_s = 0 is the stationarity of Pi(u) + beta/2 |u - u_n|_D^2 where R = dPi/du.
It is what the failing lowest-scale runs need: there, a contact-boundary node of the mortar
penalty problem has no equilibrium at the step (its own pressure opens its weighted gap faster
than the penalty closes it, README "Lowest-scale failures"), and the dashpot stiffens the
structure's response to that node's force until an equilibrium exists.  beta is dimensionless:
the damping force on a dof is beta times its diagonal stiffness times its motion within the
sub-step.

The stabilisation is not free: the dashpot dissipates

    E_s = sum_i beta D_ii (u_i - u_n,i)^2    (backward Euler work of the damping forces)

and its net force acts on the block like an external one.  Both are reported per step (the run
adds them up; ``SlidingResult.stabilisation_share``), so a run says how much of its result the
stabilisation carries.  Only sub-steps that fail without it use it.
"""

from __future__ import annotations

import numpy as np
from petsc4py import PETSc


class ViscousStabilisation:
    """A hook ``(x, A, b)`` adding beta D (x - x_n) to b and beta D to the diagonal of A.

    Inactive (adds nothing) until :meth:`activate`; ``dofs`` are the full-space dofs it acts on
    (the displacement dofs), ``size`` the full-space dimension.
    """

    def __init__(self, dofs: np.ndarray, size: int):
        self.dofs = np.ascontiguousarray(np.asarray(dofs, dtype=np.int64).ravel())
        self.size = int(size)
        self.coefficient = np.zeros(self.dofs.size)  # beta D_ii per dof
        self.anchor = np.zeros(self.dofs.size)  # u_n at the dofs
        self.active = False
        # one diagonal entry per damped row, in CSR form (rows sorted), built once
        order = np.argsort(self.dofs)
        self._order = order
        counts = np.zeros(self.size, dtype=PETSc.IntType)
        counts[self.dofs] = 1
        self._indptr = np.concatenate([[0], np.cumsum(counts)]).astype(PETSc.IntType)
        self._cols = self.dofs[order].astype(PETSc.IntType)

    def activate(self, beta: float, diagonal: np.ndarray, x_n: np.ndarray) -> None:
        """Damp motion away from ``x_n`` with beta times ``diagonal`` (full-space diagonal of
        the tangent at x_n); non-positive diagonal entries (constrained or decoupled dofs) are
        not damped."""
        if not beta > 0.0:
            raise ValueError(f"stabilisation beta = {beta!r}: expected > 0")
        d = np.asarray(diagonal, dtype=float)[self.dofs]
        self.coefficient = beta * np.where(np.isfinite(d) & (d > 0.0), d, 0.0)
        self.anchor = np.asarray(x_n, dtype=float)[self.dofs].copy()
        self.active = True

    def deactivate(self) -> None:
        self.active = False

    def forces(self, x: np.ndarray) -> np.ndarray:
        """Damping forces beta D (x - x_n) at the dofs (the hook's residual contribution)."""
        return self.coefficient * (np.asarray(x)[self.dofs] - self.anchor)

    def energy(self, x: np.ndarray) -> float:
        """Work the damping forces dissipate over the sub-step from x_n to x (>= 0)."""
        return float(np.sum(self.coefficient * (np.asarray(x)[self.dofs] - self.anchor) ** 2))

    def __call__(self, x: np.ndarray, A: PETSc.Mat | None, b: PETSc.Vec | None) -> None:
        if not self.active:
            return
        if b is not None:
            with b.localForm() as bl:
                bl.array[self.dofs] += self.forces(x)
        if A is not None:
            A.setValuesCSR(self._indptr, self._cols, self.coefficient[self._order],
                           addv=PETSc.InsertMode.ADD_VALUES)
