"""``rubberfriction verify pressure-modes``: spurious pressure modes of the mixed elements.

A nearly incompressible block confined on all sides (u = 0 on the boundary of the unit square,
uniform n x n quadrilaterals).  Linearising the residual of ``SolidProblem`` at u = 0 gives the
saddle-point system

    [ A   B^T ] [u]       A: deviatoric stiffness (shear modulus G), B: div (from J - 1),
    [ B   -C  ] [p]       C: M / K plus the Q1P0s jump stabilisation, M: the pressure mass,

and the pressure Schur complement S = B A^-1 B^T + C.  Its generalised eigenvalues S p = lambda M p
(1/MPa) are the squared inf-sup constants of the discrete pair over G: lambda G is dimensionless.

* the uniform pressure is a mode of every element (the confined block cannot change its volume,
  B^T 1 = 0): lambda_1 = 1 / K, about 0;
* Q1P0 has a second one, the checkerboard pressure (+1/-1 alternating cells is orthogonal to
  the divergence of every bilinear field on a uniform mesh): lambda_2 = 1 / K on every mesh.
  That mode is what lets a Q1P0 pressure oscillate without bound where rubber is confined in a
  filled valley;
* a stable pair (Q1P0s) has lambda_2 G bounded below by a constant independent of n.

Checked: lambda_1 K = 1 (the uniform mode), and for the stable element lambda_2 at the finest
mesh against the next one (ratio >= 1 - tolerance) and lambda_2 >= 1000 / K; Q1P0's lowest
regular eigenvalue falls like h^2 (measured values: docs/verification.md).  The Q1P0 figures are
printed beside them as notes.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.linalg
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from dolfinx.fem import petsc as fem_petsc
from mpi4py import MPI

from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import check
from rubberfriction.forms.compound import Compound, MooneyRivlin

BETA = SolidSettings.stabilisation  # the element's default


def pressure_spectrum(element: str, n: int, G: float = 1.0, K: float = 1e8, beta: float = BETA,
                      modes: int = 4) -> np.ndarray:
    """The `modes` smallest eigenvalues of S p = lambda M p (see the module docstring), in 1/MPa."""
    m = dmesh.create_unit_square(MPI.COMM_SELF, n, n, dmesh.CellType.quadrilateral)
    tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
    mat = Compound(name="confined", hyperelastic=MooneyRivlin.neo_hooke(G, K), prony=None, wlf=None,
                   thermal=None)
    sp = SolidProblem(m, tags, mat, SolidSettings(element=element, stabilisation=beta))
    if not sp.settings.mixed:
        raise ValueError(f"element {element!r} has no independent pressure")
    Jac = fem_petsc.assemble_matrix(fem.form(sp.jacobian()))
    Jac.assemble()
    A = Jac.convert("dense").getDenseArray().copy()
    if sp.pressure_jump is not None:  # the Q1P0s term is a constant hook, not part of the form
        A += sp.pressure_jump.L.toarray()
    Q, pmap = sp.W.sub(1).collapse()
    pdofs = np.asarray(pmap)
    X = sp.node_X
    on_boundary = np.any(np.isclose(X, 0.0) | np.isclose(X, 1.0), axis=1)
    udofs = sp.displacement_dofs()[~on_boundary].ravel()
    Auu, Aup = A[np.ix_(udofs, udofs)], A[np.ix_(udofs, pdofs)]
    Apu, App = A[np.ix_(pdofs, udofs)], A[np.ix_(pdofs, pdofs)]
    S = -App + Apu @ np.linalg.solve(Auu, Aup)
    q = ufl.TestFunction(Q)
    M = fem_petsc.assemble_vector(fem.form(q * ufl.dx)).array  # DG0: the mass matrix is diagonal
    lam = scipy.linalg.eigh(0.5 * (S + S.T), np.diag(M), eigvals_only=True)
    return np.sort(lam)[:modes]


def pressure_modes(*, n: tuple = (8, 16), G: float = 1.0, K: float = 1e8, beta: float = BETA,
                   tolerance: float = 0.25) -> dict:
    """Spectra of Q1P0 and Q1P0s on the meshes n; checks on Q1P0s (module docstring)."""
    if len(set(n)) < 2:
        raise ValueError("pressure-modes: give at least two meshes (--n 8 16)")
    t0 = time.perf_counter()
    spectra = {e: {k: pressure_spectrum(e, k, G, K, beta) for k in n} for e in ("Q1P0", "Q1P0s")}
    stab, plain = spectra["Q1P0s"], spectra["Q1P0"]
    second, fine = sorted(set(n))[-2:]
    checks = [
        check(f"Q1P0s lambda_1 K (n={fine})", stab[fine][0] * K, 1.0, 1e-3),
        check(f"Q1P0s lambda_2({fine})/lambda_2({second})",
              min(1.0, stab[fine][1] / stab[second][1]), 1.0, tolerance),
        check(f"Q1P0s lambda_2 K >= 1000 (n={fine})", min(1.0, stab[fine][1] * K / 1e3), 1.0, 0.0),
    ]
    notes = [f"{e} n={k}: lambda G = " + ", ".join(f"{v * G:.4g}" for v in spectra[e][k])
             for e in spectra for k in n]
    notes.append(f"Q1P0 checkerboard: lambda_2 K = {plain[fine][1] * K:.4g} at n={fine} "
                 f"(a spurious mode); Q1P0s lambda_2 G = {stab[fine][1] * G:.4g}; "
                 f"{time.perf_counter() - t0:.1f} s")
    return {"case": "pressure-modes", "parameters": {"n": list(n), "G": G, "K": K, "beta": beta},
            "checks": checks, "notes": notes,
            "spectra": {e: {str(k): v.tolist() for k, v in s.items()} for e, s in spectra.items()}}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--n", type=int, nargs="+", default=[8, 16],
                        help="cells per side (default: 8 16)")
    parser.add_argument("--G", type=float, default=1.0, help="shear modulus, MPa (default: 1)")
    parser.add_argument("--K", type=float, default=1e8, help="bulk modulus, MPa (default: 1e8)")
    parser.add_argument("--beta", type=float, default=BETA,
                        help=f"Q1P0s stabilisation (default: {BETA})")
    parser.add_argument("--tolerance", type=float, default=0.25,
                        help="allowed decay of lambda_2 between the two finest meshes "
                             "(default: 0.25)")


def run(args: argparse.Namespace) -> dict:
    return pressure_modes(n=tuple(args.n), G=args.G, K=args.K, beta=args.beta,
                          tolerance=args.tolerance)
