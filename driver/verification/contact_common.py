"""What the contact verification cases share (``rubberfriction verify patch|hertz|...``, one
module per case: ``patch``, ``hertz``, ``westergaard``, ``sliding_block``, ``thermal_bars``,
``periodic_sliding``).

Each case is a plain function with keyword parameters returning a dict

    {"case", "parameters", "checks": [check(quantity, computed, analytical, tol)], "notes", ...}

(:func:`verdict`) that the tests call with fixed parameters and the CLI with the user's.
Bulk: the project's finite-strain Mooney-Rivlin solid (``driver.fe.solid.SolidProblem``, Q1P0) in
the small-strain regime of the closed forms; contact: ``driver.fe.contact`` (C++ mortar or
node-to-segment); Newton: ``driver.fe.newton`` with the contact as a hook.  Here: the elastic
compound, meshes of several bodies, the Newton set-up, the search for the approach that carries
a given force, the blocks the cases press and slide.
"""

from __future__ import annotations

import numpy as np
import ufl
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintSpec
from rubberfriction.driver.fe.contact import Contact
from rubberfriction.driver.fe.newton import (
    NewtonSettings,
    NewtonSolver,
)
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import SolverFailure
from rubberfriction.forms.compound import Compound, MooneyRivlin
from rubberfriction.forms.kinematics import deformation_gradient
from rubberfriction.forms.viscoelastic import evaluate_at_points
from rubberfriction.meshes.block import rubber_block
from rubberfriction.meshes.common import build_body_mesh
from rubberfriction.meshes.patch import patch_test_pair


def elastic_compound(E: float, nu: float):
    """Neo-Hooke compound with small-strain Young's modulus E [MPa] and Poisson ratio nu."""

    G = E / (2.0 * (1.0 + nu))
    K = E / (3.0 * (1.0 - 2.0 * nu))
    return Compound(name=f"elastic E={E:g} nu={nu:g}", hyperelastic=MooneyRivlin.neo_hooke(G, K),
                    prony=None, wlf=None, thermal=None)


def plane_strain_modulus(E: float, nu: float) -> float:
    return E / (1.0 - nu * nu)


def _mesh_arrays(body) -> tuple[np.ndarray, np.ndarray]:
    m = body.mesh
    return m.geometry.x[:, :2].copy(), m.geometry.dofmap.array.reshape(-1, 4).astype(np.int64)


def merged_mesh(bodies, rules, levels=(), info=None):
    """One DOLFINx mesh holding several disconnected bodies (meshes.common.BodyMesh), with new
    facet rules (tag, predicate) -- the project's Newton works on one function space."""

    pts, cells, off = [], [], 0
    for b in bodies:
        p, c = _mesh_arrays(b)
        pts.append(p)
        cells.append(c + off)
        off += p.shape[0]
    return build_body_mesh(MPI.COMM_SELF, np.vstack(pts), np.vstack(cells), rules, levels,
                           info or {})


def n_full(sp) -> int:
    return sp.W.dofmap.index_map.size_local * sp.W.dofmap.index_map_bs


def newton_settings(**kw) -> NewtonSettings:
    """Newton settings of the verification cases: monotone backtracking (a step that increases the
    residual is halved).  Friction makes that necessary at stick/slip transitions: from a trial
    slip state a full Newton step can jump over the narrow stick cone (width 2 mu p / c_T) into
    reverse slip and back, a 2-cycle that a monotone line search breaks."""
    s = NewtonSettings(**kw)
    s.backtrack_growth = 1.0
    return s


def make_newton(sp, cmap, contact: Contact, *, fext=None, force_scale=1.0, rtol=1e-10,
                max_iterations=30):
    pb = sp.nonlinear_problem(cmap, hooks=[contact.hook], extra_couplings=contact.couplings(),
                              external_force=fext)
    solver = NewtonSolver(pb, newton_settings(rtol=rtol, atol=1e-14 * force_scale,
                                              max_iterations=max_iterations),
                          force_scale=force_scale)
    return pb, solver


def solve_or_raise(solver, what: str):
    res = solver.solve()
    if not res.converged:
        raise SolverFailure(f"{what}: Newton failed: {res.reason}")
    return res


def cauchy_zz(sp) -> np.ndarray:
    """sigma_zz at every quadrature point."""

    u, _ = sp.split()
    F = deformation_gradient(u)
    sigma = F * sp.second_piola() * F.T / ufl.det(F)
    cells = np.arange(sp.mesh.topology.index_map(2).size_local, dtype=np.int32)
    return evaluate_at_points(sigma[1, 1], sp.mesh, sp.rule, cells).ravel(), cells


def approach_to_force(solve_at, target: float, delta0: float, rel_tol: float = 2e-3,
                      max_solves: int = 40):
    """Find the prescribed approach delta with contact force solve_at(delta) = target.

    Grows delta (x2 at most per step, secant when possible) until the force is bracketed, then a
    safeguarded secant (bisection whenever the secant falls outside the middle 80 % of the bracket).
    Each call of solve_at starts from the previous solution.  Returns (delta, force, solves)."""
    lo, hi = (0.0, 0.0), None
    prev = None
    delta = delta0
    for k in range(1, max_solves + 1):
        F = solve_at(delta)
        if abs(F - target) <= rel_tol * target:
            return delta, F, k
        if F < target:
            lo = max(lo, (delta, F))
        else:
            hi = (delta, F) if hi is None or delta < hi[0] else hi
        if hi is None:
            new = 2.0 * delta
            if prev is not None and F > prev[1] and delta > prev[0]:
                new = min(delta + (target - F) * (delta - prev[0]) / (F - prev[1]), 2.0 * delta)
        else:
            (d0, f0), (d1, f1) = lo, hi
            new = d0 + (target - f0) * (d1 - d0) / (f1 - f0)
            if not (d0 + 0.1 * (d1 - d0) <= new <= d1 - 0.1 * (d1 - d0)):
                new = 0.5 * (d0 + d1)
        prev = (delta, F)
        delta = new
    raise SolverFailure(f"approach: force {F:.6g} after {max_solves} solves, target {target:.6g}")


def verdict(case: str, parameters: dict, checks: list, notes=(), **extra) -> dict:
    """The result dict of a case: case, parameters, checks, notes and any extra entries."""
    out = {"case": case, "parameters": parameters, "checks": checks, "notes": list(notes)}
    out.update(extra)
    return out


def two_blocks(length, h_upper, h_lower, n_upper, n_lower, *, ny_upper=None, ny_lower=None, gap):
    """The patch-test pair (``meshes.patch``) as ONE mesh: upper [0, l] x [gap, gap + h_upper],
    lower [0, l] x [-h_lower, 0].  Facet tags: upper 1 contact (bottom), 2 top, 3 left, 4 right;
    lower 5 contact (top), 6 bottom, 7 left, 8 right.  Cell tags: 1 lower, 2 upper."""

    up, lo = patch_test_pair(length, h_upper, h_lower, n_upper=n_upper, n_lower=n_lower,
                             ny_upper=ny_upper, ny_lower=ny_lower, gap=gap)
    tol = 1e-9 * max(length, h_upper, h_lower)
    rules = [
        (1, lambda p: np.abs(p[:, 1] - gap) <= tol),
        (2, lambda p: np.abs(p[:, 1] - (gap + h_upper)) <= tol),
        (3, lambda p: (np.abs(p[:, 0]) <= tol) & (p[:, 1] >= gap - tol)),
        (4, lambda p: (np.abs(p[:, 0] - length) <= tol) & (p[:, 1] >= gap - tol)),
        (5, lambda p: np.abs(p[:, 1]) <= tol),
        (6, lambda p: np.abs(p[:, 1] + h_lower) <= tol),
        (7, lambda p: (np.abs(p[:, 0]) <= tol) & (p[:, 1] <= tol)),
        (8, lambda p: (np.abs(p[:, 0] - length) <= tol) & (p[:, 1] <= tol)),
    ]
    return merged_mesh([up, lo], rules, levels=(0.5 * gap,))


def elastic_body(*, E, nu, length, height, n_contact, periodic, element, edge_radius=0.0):
    """The elastic block the sliding cases press and slide: body, solid problem, constraint spec,
    and the top face's dofs (x, z)."""
    if edge_radius > 0.0:
        body = rubber_block(length, height, h_contact=length / n_contact, grading=1.2,
                            leading_edge_radius=edge_radius, leading_edge="right")
    else:
        body = rubber_block(length, height, nx_contact=n_contact, grading=1.2)
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu),
                      SolidSettings(element=element))
    X, d = sp.node_X, sp.displacement_dofs()
    tol = 1e-9 * length
    top = np.abs(X[:, 1] - height) <= tol
    spec = ConstraintSpec(n_full(sp))
    if periodic:
        left = np.nonzero(np.abs(X[:, 0]) <= tol)[0]
        right = np.nonzero(np.abs(X[:, 0] - length) <= tol)[0]
        left, right = left[np.argsort(X[left, 1])], right[np.argsort(X[right, 1])]
        spec.equal(d[left, 0], d[right, 0])
        spec.equal(d[left, 1], d[right, 1])
    spec.fix(d[top, 0], 0.0)
    spec.tie(d[top, 1])
    top_x, top_z = d[top, 0], int(d[top, 1][0])
    spec.fix(top_z, 0.0)
    return body, sp, spec, top_x, top_z
