"""Finite linear viscoelasticity, stress-based (Simo 1987; thesis eqs. 3.72-3.78).

Each Maxwell element k carries the algorithmic history H^k at the quadrature points, updated by

    H^k_{n+1} = a_k H^k_n + b_k (Sbar_{n+1} - Sbar_n),   a_k = exp(-dt/tau_k)

with either the midpoint rule of the thesis, eq. (3.76), b_k = exp(-dt/(2 tau_k))
(``scheme="midpoint"``), or the convolution integrated exactly for Sbar linear in time within the
step, b_k = (tau_k/dt)(1 - exp(-dt/tau_k)) (``scheme="linear"``, default).  Both are second order
for dt << tau_k, but a tread compound has Prony terms at every time scale and terms with
tau_k ~ dt carry much of E''(omega): there the midpoint factor is off by 2 sinh(x/2)/x - 1
(x = dt/tau_k; 4 % at x = 1, 42 % at x = 3), which biases the hysteresis friction at practical
step sizes.  The linear scheme is exact for a ramp and stays accurate for any tau_k/dt.

and the stress is (3.77)  S = S_vol + gamma_inf S_iso,0 + J^(-2/3) sum_k gamma_k DEV{H^k_0}.

Moduli convention.  The Mooney-Rivlin constants describe the *long-term* (equilibrium) response, as
the thesis fits them to quasi-static tests; the instantaneous energy is Psi_0 = Psi_MR / gamma_inf.
Writing every H^k with the fictitious stress Sbar of Psi_MR and g_k = gamma_k / gamma_inf, (3.77)
becomes S = S_vol + J^(-2/3) DEV{Sbar + sum_k g_k H^k}.  (Constants measured as instantaneous
moduli, the ABAQUS default, convert by C_ij,long-term = gamma_inf C_ij,instantaneous.)

Because a_k, b_k are fixed within a time step, the sum collapses to one tensor per quadrature point:

    sum_k g_k H^k_{n+1} = Hstar + beta Sbar_{n+1},
    Hstar = sum_k g_k (a_k H^k_n - b_k Sbar_n),  beta = sum_k g_k b_k,

so the residual form carries a single tensor quadrature field (Hstar) and a cell field (beta),
whatever the number of Prony terms; the consistent tangent follows from UFL differentiation.  The
per-term histories live in numpy and are updated, vectorised, after each converged step.

Storage.  In plane strain DEV{Sbar} (taken with C = F^T F, F_13 = F_23 = 0) is symmetric with
zero x-y and z-y shears, so every H^k and Hstar is stored by its 4 independent components
(xx, zz, out-of-plane yy, xz; ``kinematics.PLANE_SYM_COMPONENTS``) instead of 9.  a_k, b_k and
beta depend on dt and the temperature only: they are computed once per (dt, temperature) and
reused by the steps of equal length that make up most of a run.

Temperature enters through the WLF shift of every tau_k, eqs. (3.33), (3.37):
tau_k(T) = a_T(T) tau_k, with T given per cell (a field from the thermal loop or one value per
height partition).

Dissipation.  At small strain the dashpot of element k dissipates D_k = |s_k|^2 / (2 eta_k)
with branch stress s_k = gamma_k H^k_0 and viscosity eta_k = G_k tau_k (G_k = gamma_k G_0); in
the variables above D = sum_k g_k |H^k|^2 / (2 G_ref tau_k(T)), G_ref = mu of the (long-term) MR
constants (``dissipation_density``).  At finite strain this is not the dissipation of the model:
the non-equilibrium stress J^(-2/3) DEV{sum_k g_k H^k} does the power P = 1/2 T : dCbar/dt,
T = sum_k g_k H^k, Cbar = J^(-2/3) C, while H^k is driven by d DEV{Sbar}/dt, which equals
G_ref dCbar/dt only at C = 1.  With the branch free energy psi = sum_k g_k |H^k|^2 / (4 G_ref)
(its small-strain value) the exact dissipation is D = P - dpsi/dt = (small-strain D) +
1/2 T : (dCbar/dt - d DEV{Sbar}/dt / G_ref): over a periodic cycle it is the work of the stress
(the loop area, eq. 2.8's balance) whatever the strain, where the small-strain density
overestimates (x1.4 at simple-shear amplitude 0.5, x3 at 1, x4.6 for a 0.05 oscillation about a
0.6 pre-shear, mooney-rivlin tread compound).  ``commit_step`` with the converged Cbar computes
per step and point  D dt = 1/4 (T_n + T_n+1) : (Cbar_n+1 - Cbar_n) - (psi_n+1 - psi_n)
(trapezoidal stress work minus the stored energy change: exact over a discrete cycle up to the
O(dt^2) of the trapezoid, like the external work).  A period-end jump of the histories
(``extrapolate_periodic``) changes psi without work and dissipates nothing.  psi is the small-strain
branch energy, not a finite-strain potential of the branches, so a step's D at a point may be
negative; over whole periods of a steady state (and summed over the window's steps) it is the
work the stress did there.  On sub-stepped runs the sum must run over the committed sub-steps,
as here: a trapezoid over whole steps of two sub-steps missed part of the dissipation on a
steep macro run (docs/performance.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import basix
import numpy as np
import ufl
from dolfinx import fem

from rubberfriction.forms import jit
from rubberfriction.forms.hyperelastic import dev
from rubberfriction.forms.kinematics import (
    PLANE_SYM_COMPONENTS,
    PLANE_SYM_WEIGHTS,
    plane_sym_from_vector,
    vector_from_plane_sym,
    vector_from_tensor3,
)


@dataclass(frozen=True)
class QuadratureRule:
    """Quadrature used for every bulk integral and every history field."""

    degree: int
    points: np.ndarray
    weights: np.ndarray


def quadrature_rule(cell_type: basix.CellType, degree: int) -> QuadratureRule:
    points, weights = basix.make_quadrature(cell_type, degree)
    return QuadratureRule(degree, points, weights)


def viscous_stress(F, Sbar, Hstar, beta) -> ufl.core.expr.Expr:
    """Non-equilibrium S = J^(-2/3) DEV{beta Sbar + Hstar} (collapsed eq. 3.77); Hstar holds the
    4 plane-strain components (``plane_sym_from_vector``)."""
    C = F.T * F
    return ufl.det(F) ** (-2.0 / 3.0) * dev(beta * Sbar + plane_sym_from_vector(Hstar), C)


#: number of stored components of each history tensor (symmetric plane strain)
NCOMP = len(PLANE_SYM_COMPONENTS)
#: the coefficients of this many (dt, temperature) pairs are kept (cut-back sub-steps reuse them)
COEFFICIENT_CACHE = 8


@dataclass(frozen=True)
class HistorySnapshot:
    """A copy of the Prony histories and the converged fictitious stress at model time ``time``."""

    H: np.ndarray
    Sbar: np.ndarray
    time: float


class ViscoelasticHistory:
    """History variables H^k of all Prony terms at all quadrature points of one mesh.

    Parameters
    ----------
    mesh: the dolfinx mesh (one cell type).
    rule: the quadrature rule of the bulk forms.
    gamma, tau: Prony series (eq. 3.36), tau in s at the WLF reference temperature.
    scale: g_k = gamma_k * scale (1 / gamma_inf: the MR constants are long-term moduli).
    G_ref: shear modulus of the stored energy (for the dissipation density).
    shift: callable T [K] -> a_T (WLF, eq. 3.33); None means no temperature dependence.

    Arrays are cell-major: quadrature point q of cell c is row c * n_points_per_cell + q; tensors
    carry the 4 components of ``kinematics.PLANE_SYM_COMPONENTS``.
    """

    def __init__(self, mesh, rule: QuadratureRule, gamma, tau, scale: float, G_ref: float,
                 shift=None, scheme: str = "linear"):
        if scheme not in ("linear", "midpoint"):
            raise ValueError(f"viscoelastic scheme: got {scheme!r}, expected 'linear' or "
                             "'midpoint'")
        self.scheme = scheme
        self.mesh = mesh
        self.rule = rule
        self.g = np.asarray(gamma, dtype=float) * float(scale)
        self.tau_ref = np.asarray(tau, dtype=float)
        self.G_ref = float(G_ref)
        self.shift = shift
        cell = mesh.ufl_cell()
        qe = ufl.VectorElement("Quadrature", cell, degree=rule.degree, dim=NCOMP,
                               quad_scheme="default")
        self.Q = fem.FunctionSpace(mesh, qe)
        self.DG0 = fem.FunctionSpace(mesh, ("DG", 0))
        self.Hstar = fem.Function(self.Q, name="Hstar")
        self.beta = fem.Function(self.DG0, name="beta")
        tdim = mesh.topology.dim
        self.num_cells = mesh.topology.index_map(tdim).size_local
        self.cells = np.arange(self.num_cells, dtype=np.int32)
        self.npts = rule.points.shape[0]
        # dofs of (cell, point) in Hstar and of each cell in beta; None where they are the array
        # positions themselves (dolfinx numbers them so in serial): then no index is needed
        self._qdofs = _unless_identity(
            self.Q.dofmap.list.array.reshape(-1, self.npts)[: self.num_cells])
        self._cdofs = _unless_identity(self.DG0.dofmap.list.array[: self.num_cells])
        nq = self.num_cells * self.npts
        self.H = np.zeros((self.g.size, nq, NCOMP))  # per-term history
        self._work = np.empty((self.num_cells, self.npts * NCOMP))  # one term's update
        self.Sbar_n = np.zeros((nq, NCOMP))  # DEV{Sbar} of the last converged step
        self.T_cell = None  # kelvin per cell; None: reference temperature
        self._tau_cell = np.repeat(self.tau_ref[:, None], self.num_cells, axis=1)  # (terms, cells)
        self._coefficients: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._a = self._b = None
        self._dt = None
        self._D_n = np.zeros(nq)  # dissipation density at the last converged step
        # Cbar = J^(-2/3) C of the last converged step (PLANE_SYM_COMPONENTS): the stress power of
        # the branches (module docstring, exact dissipation); None: unknown (restore), not used
        self.Cbar_n: np.ndarray | None = np.tile(np.array([1.0, 1.0, 1.0, 0.0]), (nq, 1))
        self.rate = np.zeros(nq)  # mean dissipation rate of the last step per point (MPa/s)
        self.dissipated = 0.0  # total dissipated energy (per unit depth), mJ/mm
        self.time = 0.0  # model time of the converged state (sum of committed steps), s
        # the same per quadrature point (sums to `dissipated`): where the energy went (eq. 2.7),
        # for dissipation fields and depth profiles (driver.sliding.outputs)
        self.dissipated_points = np.zeros(nq)

    # --- temperature -------------------------------------------------------------------------
    def set_temperature(self, T_cell) -> None:
        """Temperature per cell in K (scalar broadcast); shifts every tau_k by WLF (3.37)."""
        if self.shift is None:
            raise ValueError("temperature given but the compound has no WLF data")
        T = np.broadcast_to(np.asarray(T_cell, dtype=float), (self.num_cells,)).copy()
        self.T_cell = T
        self._tau_cell = self.tau_ref[:, None] * np.asarray(self.shift(T), dtype=float)[None, :]
        self._coefficients.clear()
        self._dt = None  # coefficients must be recomputed

    def tau_at_points(self) -> np.ndarray:
        """tau_k at every quadrature point, shape (n_terms, n_points)."""
        return np.repeat(self._tau_cell, self.npts, axis=1)

    # --- stepping ----------------------------------------------------------------------------
    def coefficients(self, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(a, b, beta) of a step dt at the current temperature: a_k, b_k per term and cell
        (eq. 3.76 or the linear scheme, module docstring) and beta = sum_k g_k b_k per cell."""
        c = self._coefficients.get(dt)
        if c is None:
            x = dt / self._tau_cell
            a = np.exp(-x)
            if self.scheme == "midpoint":
                b = np.exp(-0.5 * x)  # eq. (3.76)
            else:
                b = np.where(x > 1e-6, -np.expm1(-x) / np.maximum(x, 1e-300), 1.0 - 0.5 * x)
            c = (a, b, self.g @ b)
            if len(self._coefficients) >= COEFFICIENT_CACHE:
                self._coefficients.clear()
            self._coefficients[dt] = c
        return c

    def prepare_step(self, dt: float) -> None:
        """Fill Hstar and beta for a step of size dt (called before the Newton solve)."""
        if not dt > 0.0:
            raise ValueError(f"time step dt must be > 0, got {dt}")
        self._a, self._b, beta = self.coefficients(dt)
        self._dt = dt
        # Hstar = sum_k g_k a_k H^k_n - beta Sbar_n, per cell: (cells, points x components)
        hstar = np.einsum("kc,kcj->cj", self.g[:, None] * self._a, self._by_cell(self.H))
        hstar -= beta[:, None] * self._by_cell(self.Sbar_n)
        _write(self.Hstar, self._qdofs, hstar)
        _write(self.beta, self._cdofs, beta)

    def commit_step(self, Sbar_new: np.ndarray, Cbar_new: np.ndarray | None = None) -> float:
        """Update every H^k with the converged fictitious stress; returns the step's dissipation.

        Sbar_new: (n_points, 4) DEV{Sbar} at the quadrature points (``PLANE_SYM_COMPONENTS``), the
        deviator taken with the converged C (eq. 3.76); storing the deviator matters: the
        isotropic part of Sbar is O(mu) and would leak into the stress through DEV with a later C.
        Cbar_new: (n_points, 4) the converged J^(-2/3) C: the dissipation is then the exact one of
        the finite-strain model (branch stress work minus stored energy change, module
        docstring); without it (or without the previous step's Cbar) it is the small-strain
        density integrated by the trapezoidal rule.
        """
        if self._dt is None:
            raise RuntimeError("commit_step called before prepare_step")
        exact = Cbar_new is not None and self.Cbar_n is not None
        if exact:
            T_n, psi_n = self._branch_stress_and_energy()
        # H^k <- a_k H^k + b_k (Sbar_new - Sbar_n), in place, one term at a time (the term's
        # block stays in cache between the two passes)
        dS, work = self._by_cell(Sbar_new - self.Sbar_n), self._work
        for Hk, ak, bk in zip(self._by_cell(self.H), self._a, self._b):
            Hk *= ak[:, None]
            np.multiply(bk[:, None], dS, out=work)
            Hk += work
        np.copyto(self.Sbar_n, Sbar_new)
        D = self.dissipation_density()
        w = self._point_weights()
        if exact:
            T_1, psi_1 = self._branch_stress_and_energy()
            dC = np.asarray(Cbar_new, dtype=float) - self.Cbar_n
            d = 0.25 * ((T_n + T_1) * dC) @ np.asarray(PLANE_SYM_WEIGHTS) - (psi_1 - psi_n)
        else:
            d = (0.5 * self._dt) * (D + self._D_n)  # trapezoidal rule in time
        if Cbar_new is not None:
            self.Cbar_n = np.array(Cbar_new, dtype=float)
        self.rate = d / self._dt
        dE = float(np.dot(w, d))
        self.dissipated_points += w * d
        self._D_n = D
        self.dissipated += dE
        self.time += self._dt
        return dE

    def _branch_stress_and_energy(self) -> tuple[np.ndarray, np.ndarray]:
        """T = sum_k g_k H^k (n_points, 4) and the branches' stored energy per unit reference
        volume psi = sum_k g_k |H^k|^2 / (4 G_ref) (n_points,), module docstring."""
        T = np.einsum("k,kqi->qi", self.g, self.H)
        H2 = np.einsum("kqi,kqi,i->kq", self.H, self.H, np.asarray(PLANE_SYM_WEIGHTS))
        return T, (self.g @ H2) / (4.0 * self.G_ref)

    def restore(self, H: np.ndarray, Sbar: np.ndarray) -> None:
        """Take H^k and DEV{Sbar} of an earlier converged state (a run that slides on from another
        run's final state, ``driver.sliding.spec.InitialState``) as the last converged step, at
        this history's temperatures: the dissipation rate restarts from them."""
        if H.shape != self.H.shape or Sbar.shape != self.Sbar_n.shape:
            raise ValueError(f"history of shape {H.shape}, {Sbar.shape}: this mesh has "
                             f"{self.H.shape}, {self.Sbar_n.shape}")
        np.copyto(self.H, H)
        np.copyto(self.Sbar_n, Sbar)
        self._D_n = self.dissipation_density()
        self.Cbar_n = None  # the owner sets the restored state's Cbar (SolidProblem.prepare_step)

    def snapshot(self) -> HistorySnapshot:
        """The converged history now: where a period of a periodic steady state starts."""
        return HistorySnapshot(self.H.copy(), self.Sbar_n.copy(), self.time)

    def extrapolate_periodic(self, start: HistorySnapshot) -> None:
        """Jump every Prony branch to its periodic steady state, as if Sbar(t) of the period since
        ``start`` repeated forever.

        A branch obeys H' = -H/tau + Sbar' (eq. 3.73); over one period T from H(0) it reaches
        H(T) = q H(0) + int_0^T exp(-(T - s)/tau) Sbar'(s) ds with q = exp(-T/tau).  For an input
        of period T (Sbar(0) = Sbar(T)) the periodic solution at the period's end is

            H_ss(T) = (H(T) - q H(0) - q (Sbar(T) - Sbar(0))) / (1 - q),

        the same integral with the period closed (Sbar(0) replaced by Sbar(T)): the static part of
        the load is fully relaxed in branches with tau >> T, branches with tau << T are unchanged
        (q -> 0), the ones in between get their steady phase.  Used once per period of a periodic
        sliding cell, it replaces the slow creep of the long branches (up to tau_max / T periods)
        by a fixed-point iteration that converges in a few periods.  Exact for linear
        viscoelasticity under a periodic load; the caller solves equilibrium again afterwards.
        """
        T = self.time - start.time
        if not T > 0.0:
            raise ValueError(f"periodic extrapolation over T = {T!r} s: expected T > 0")
        x = T / self.tau_at_points()
        q, one_q = np.exp(-x)[:, :, None], -np.expm1(-x)[:, :, None]
        self.H = (self.H - q * start.H - q * (self.Sbar_n - start.Sbar)[None]) / one_q
        self._D_n = self.dissipation_density()

    def dissipation_density(self) -> np.ndarray:
        """Small-strain dissipation rate per unit reference volume at each quadrature point
        (MPa/s), sum_k g_k |H^k|^2 / (2 G_ref tau_k): exact at small strain only (module
        docstring; ``rate`` is the exact mean rate of the last step)."""
        H2 = np.einsum("kqi,kqi,i->kq", self.H, self.H, np.asarray(PLANE_SYM_WEIGHTS))  # |H^k|^2
        rate = self.g[:, None] / (2.0 * self.G_ref * self._tau_cell)  # (terms, cells)
        return np.einsum("kc,kcp->cp", rate,
                         H2.reshape(self.g.size, self.num_cells, self.npts)).ravel()

    # --- helpers -----------------------------------------------------------------------------
    def _by_cell(self, a: np.ndarray) -> np.ndarray:
        """View of a point array (..., n_points, 4) as (..., n_cells, points x components)."""
        return a.reshape(a.shape[:-2] + (self.num_cells, self.npts * NCOMP))

    def _point_weights(self) -> np.ndarray:
        """Reference-configuration integration weight of each quadrature point (|det J| w)."""
        if not hasattr(self, "_wq"):
            x = ufl.SpatialCoordinate(self.mesh)
            detJ = ufl.JacobianDeterminant(self.mesh)
            expr = jit.expression(abs(detJ) + 0.0 * x[0], self.rule.points)
            dj = expr.eval(self.cells).reshape(self.num_cells, -1)
            self._wq = (dj * self.rule.weights[None, :]).ravel()
        return self._wq


def _unless_identity(dofs: np.ndarray) -> np.ndarray | None:
    """The dofs of a row-major (cell, point) block, or None if they are 0, 1, 2, ..."""
    flat = np.asarray(dofs).ravel()
    return None if np.array_equal(flat, np.arange(flat.size)) else flat


def _write(f: fem.Function, dofs: np.ndarray | None, values: np.ndarray) -> None:
    """Write values (one block of f's value size per dof, row-major) into the Function f."""
    bs = f.function_space.dofmap.index_map_bs
    arr = f.x.array.reshape(-1, bs)
    if dofs is None:
        arr[: values.size // bs] = values.reshape(-1, bs)
    else:
        arr[dofs] = values.reshape(-1, bs)
    f.x.scatter_forward()


def evaluate_at_points(expr_ufl, mesh, rule: QuadratureRule, cells: np.ndarray) -> np.ndarray:
    """Evaluate a UFL tensor expression at the quadrature points: shape (n_points, n_comp)."""
    e = jit.expression(expr_ufl, rule.points)
    vals = e.eval(cells)
    npts = rule.points.shape[0]
    return vals.reshape(cells.size * npts, -1)


__all__ = [
    "HistorySnapshot",
    "QuadratureRule",
    "ViscoelasticHistory",
    "evaluate_at_points",
    "quadrature_rule",
    "vector_from_plane_sym",
    "vector_from_tensor3",
    "viscous_stress",
]
