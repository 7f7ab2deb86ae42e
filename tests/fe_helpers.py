"""Small helpers shared by the finite-element tests (homogeneous states on tiny meshes)."""

from __future__ import annotations

import numpy as np
import ufl
from dolfinx import mesh as dmesh
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver
from rubberfriction.forms.kinematics import deformation_gradient, vector_from_tensor3
from rubberfriction.forms.viscoelastic import evaluate_at_points


def unit_square(n: int = 2, length: float = 1.0):
    m = dmesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [length, length]], [n, n],
                               dmesh.CellType.quadrilateral)
    tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
    return m, tags


def n_full(sp) -> int:
    return sp.W.dofmap.index_map.size_local * sp.W.dofmap.index_map_bs


def solve(sp, spec: ConstraintSpec, rtol: float = 1e-13, hooks=None):
    cmap = ConstraintMap(spec)
    pb = sp.nonlinear_problem(cmap, hooks=hooks or ())
    res = NewtonSolver(pb, NewtonSettings(rtol=rtol, atol=1e-14)).solve()
    assert res.converged, res.reason
    return pb, res


def cauchy_at_points(sp) -> np.ndarray:
    """Cauchy stress (n_points, 3, 3) at every quadrature point."""
    u, _ = sp.split()
    F = deformation_gradient(u)
    sigma = F * sp.second_piola() * F.T / ufl.det(F)
    cells = np.arange(sp.mesh.topology.index_map(2).size_local, dtype=np.int32)
    return evaluate_at_points(vector_from_tensor3(sigma), sp.mesh, sp.rule, cells).reshape(-1, 3, 3)


def mooney_rivlin_cauchy(F: np.ndarray, C10: float, C01: float, D1: float,
                         volumetric: str = "quadratic") -> np.ndarray:
    """Closed-form Cauchy stress of the split Mooney-Rivlin energy (3.58), independent of UFL.

    sigma = (2/J) dev[(C10 + C01 I1bar) bbar - C01 bbar^2] + 2 (J - 1)/D1 * 1, or with the
    logarithmic volumetric energy (ln J)^2 / D1 the last term 2 ln(J) / (J D1) * 1.
    """
    J = np.linalg.det(F)
    bbar = J ** (-2.0 / 3.0) * F @ F.T
    I1 = np.trace(bbar)
    s = (C10 + C01 * I1) * bbar - C01 * bbar @ bbar
    s = s - np.trace(s) / 3.0 * np.eye(3)
    vol = {"quadratic": J - 1.0, "logarithmic": np.log(J) / J}[volumetric]
    return 2.0 / J * s + 2.0 * vol / D1 * np.eye(3)


def plane_strain_compression(E: float, nu: float, q: float) -> tuple[float, float]:
    """Homogeneous plane-strain state of the neo-Hooke solid (C10 = G/2, D1 = 2/K) under a dead
    load q per reference length on its top, sides free: stretches (lambda_x, lambda_z) with
    sigma_xx = 0 and -sigma_zz lambda_x = q, from the closed-form stress above (no UFL).  The
    contact pressure of the patch test is then -sigma_zz = q / lambda_x."""
    from scipy.optimize import root

    G, K = E / (2.0 * (1.0 + nu)), E / (3.0 * (1.0 - 2.0 * nu))

    def residual(lam):
        s = mooney_rivlin_cauchy(np.diag([lam[0], lam[1], 1.0]), G / 2.0, 0.0, 2.0 / K)
        return [s[0, 0] / q, (-s[1, 1] * lam[0] - q) / q]

    sol = root(residual, [1.0, 1.0], tol=1e-15)  # (reports "no further improvement" at round-off)
    assert max(abs(r) for r in residual(sol.x)) < 1e-13, sol
    return float(sol.x[0]), float(sol.x[1])


def checks_of(result: dict, expected: set[str]) -> dict:
    """The checks of a verification result by quantity; every expected one must be there (an
    empty or renamed check list fails)."""
    by = {c["quantity"]: c for c in result["checks"]}
    assert expected <= set(by), f"missing checks: {sorted(expected - set(by))}; got {sorted(by)}"
    return by


def rel(computed: float, exact: float) -> float:
    return abs(computed - exact) / abs(exact)
