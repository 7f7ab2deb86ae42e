"""Contact verification cases against closed forms (``rubberfriction verify patch|hertz|...``).

Each case is a plain function with keyword parameters returning a dict

    {"case", "parameters", "checks": [check(quantity, computed, analytical, tol)], "notes", ...}

that the tests call with fixed parameters and the CLI with the user's.  Bulk: the project's
finite-strain Mooney-Rivlin solid (``driver.fe.solid.SolidProblem``, Q1P0) in the small-strain
regime of the closed forms; contact: ``driver.fe.contact`` (C++ mortar or node-to-segment); Newton:
``driver.fe.newton`` with the contact as a hook.

* ``patch``: two stacked blocks with non-matching contact meshes, uniform pressure on top: the
  contact pressure must be uniform (exact for segment-to-segment; node-to-segment reported).
* ``hertz``: plane-strain cylinder on a rigid flat, a = sqrt(4 P R/(pi E*)), p0 = 2 P/(pi a),
  E* = E/(1 - nu^2), for a sequence of contact-zone refinements.
* ``westergaard``: elastic layer (one period, periodic sides, thickness >= 2 lambda) on the
  periodic rigid sinusoid z = h cos(2 pi x/lambda): p* = pi E* h/lambda,
  p_mean = p* sin^2(pi a/lambda).
* ``sliding-block``: Coulomb sliding, F_x/F_z = mu for constant mu (finite block) and a mu(p, v)
  spline at the known (p, v) of a periodic layer in steady sliding; the Newton residual history
  of a sliding step shows quadratic convergence.
* ``thermal-bars`` (tests only): two bars through a conductance, q = dT/(L1/k1 + 1/h_c + L2/k2),
  and frictional heat mu p v A split kappa / 1 - kappa between the bodies.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from scipy.spatial import cKDTree

from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.contact import (
    DEFAULT_ALPHA,
    Contact,
    DeformableMaster,
    PenaltySettings,
    RigidMaster,
    SlaveSurface,
    ThermalSettings,
)
from rubberfriction.driver.fe.newton import (
    ConstrainedNonlinearProblem,
    NewtonSettings,
    NewtonSolver,
)
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import (
    SolverFailure,
    add_keyword_arguments,
    call_with_arguments,
    case_function,
    check,
)
from rubberfriction.forms.compound import Compound, MooneyRivlin
from rubberfriction.forms.kinematics import deformation_gradient
from rubberfriction.forms.viscoelastic import evaluate_at_points
from rubberfriction.meshes.block import rubber_block
from rubberfriction.meshes.common import build_body_mesh
from rubberfriction.meshes.cylinder import hertz_cylinder
from rubberfriction.meshes.patch import patch_test_pair

# --------------------------------------------------------------------------------- helpers


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


def _result(case: str, parameters: dict, checks: list, notes=(), **extra) -> dict:
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


# ----------------------------------------------------------------------------- patch test


def patch(*, E: float = 10.0, nu: float = 0.3, pressure: float = 0.1, length: float = 1.0,
          n_upper: int = 7, n_lower: int = 5, method: str = "mortar", element: str = "Q1P0",
          c_N: float | None = None, tolerance: float = 1e-8) -> dict:
    """Contact patch test on non-matching meshes.

    Upper block [0, l] x [gap, gap + l/2] (slave, n_upper facets on its contact face) on the lower
    block [0, l] x [-l/2, 0] (deformable master, n_lower facets), same material, frictionless.
    Uniform dead-load pressure on top, the lower block's bottom on rollers, both left faces on
    symmetry rollers (u_x = 0).  The exact discrete solution is homogeneous: the contact pressure
    at every slave node equals the applied force over the current contact length, and sigma_zz
    is uniform in both bodies.
    """
    gap = 0.01 * length
    body = two_blocks(length, 0.5 * length, 0.5 * length, n_upper, n_lower, gap=gap)
    tol = 1e-9 * length
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu),
                      SolidSettings(element=element))
    q = fem.Constant(body.mesh, 0.0)
    sp.add_traction(2, ufl.as_vector([0.0, -q]))
    X, d = sp.node_X, sp.displacement_dofs()
    spec = ConstraintSpec(n_full(sp))
    spec.fix(d[np.abs(X[:, 1] + 0.5 * length) <= tol, 1], 0.0)
    spec.fix(d[np.abs(X[:, 0]) <= tol, 0], 0.0)
    cmap = ConstraintMap(spec)
    Es = plane_strain_modulus(E, nu)
    pen = PenaltySettings(c_N=c_N) if c_N else PenaltySettings()
    contact = Contact(SlaveSurface.from_boundary(sp.boundary(1)),
                      DeformableMaster.from_boundary(sp.boundary(5)),
                      method=method, E_eff=Es, penalty=pen, comm=body.mesh.comm)
    cN = contact.report()["penalty"]["c_N"]
    upper_nodes = X[:, 1] > 0.5 * gap
    sp.w.x.array[d[upper_nodes, 1]] = -(gap + pressure / cN)  # initial guess: in contact
    q.value = pressure
    pb, solver = make_newton(sp, cmap, contact, force_scale=pressure * length, rtol=1e-13)
    solve_or_raise(solver, "patch test")
    st = contact.state()
    act = st["active"]
    p = st["pressure"][act]
    x_slave = contact.slave.X[:, 0] + sp.w.x.array[contact.slave.dofs[:, 0]]
    current_length = x_slave.max() - x_slave.min()
    p_exact = pressure * length / current_length  # dead load over the current contact length
    szz, cells = cauchy_zz(sp)
    mid_z = np.repeat(
        sp.mesh.geometry.x[sp.mesh.geometry.dofmap.array.reshape(-1, 4)][:, :, 1].mean(axis=1),
        szz.size // cells.size)
    s_up, s_lo = szz[mid_z > 0.5 * gap], szz[mid_z < 0.5 * gap]
    checks = [
        check("slave nodes in contact", float(act.sum()), float(act.size), 0.0),
        check("contact pressure min", float(p.min()), p_exact, tolerance),
        check("contact pressure max", float(p.max()), p_exact, tolerance),
        check("total contact force F_z", st["Fz"], pressure * length, tolerance),
        check("sigma_zz upper (max dev.)", float(s_up[np.argmax(np.abs(s_up + p_exact))]),
              -p_exact, tolerance),
        check("sigma_zz lower (max dev.)", float(s_lo[np.argmax(np.abs(s_lo + p_exact))]),
              -p_exact, tolerance),
    ]
    notes = [f"{method}: pressure spread (max-min)/p = {(p.max() - p.min()) / p_exact:.3e}, "
             f"sigma_zz spread in the lower block {(s_lo.max() - s_lo.min()) / p_exact:.3e}",
             contact.report_text()]
    return _result("patch", {"E": E, "nu": nu, "pressure": pressure, "length": length,
                             "n_upper": n_upper, "n_lower": n_lower, "method": method, "c_N": cN},
                   checks, notes,
                   pressure_spread=float((p.max() - p.min()) / p_exact),
                   stress_spread_lower=float((s_lo.max() - s_lo.min()) / p_exact),
                   stress_spread_upper=float((s_up.max() - s_up.min()) / p_exact))


# ---------------------------------------------------------------------------------- Hertz


def hertz_solution(P: float, R: float, E_star: float) -> tuple[float, float]:
    """Plane-strain Hertz: half-width a = sqrt(4 P R/(pi E*)), peak p0 = 2 P/(pi a)."""
    a = math.sqrt(4.0 * P * R / (math.pi * E_star))
    return a, 2.0 * P / (math.pi * a)


def fit_elliptic(x: np.ndarray, p: np.ndarray, floor: float = 0.25) -> tuple[float, float]:
    """(a, p0) of p = p0 sqrt(1 - x^2/a^2) by least squares of p^2 = p0^2 - (p0/a)^2 x^2 over the
    nodes with p > floor * max(p) (the penalty rounds the pressure at the very edge)."""
    sel = p > floor * p.max()
    A = np.column_stack([np.ones(sel.sum()), x[sel] ** 2])
    c0, c1 = np.linalg.lstsq(A, p[sel] ** 2, rcond=None)[0]
    return math.sqrt(-c0 / c1), math.sqrt(c0)


def mortar_average(x: np.ndarray, f, n: int = 400) -> np.ndarray:
    """Int N_A f dx / Int N_A dx for the hat functions of the sorted nodes x (1D)."""
    out = np.zeros(x.size)
    s = (np.arange(n) + 0.5) / n  # midpoint rule on each element
    num, den = np.zeros(x.size), np.zeros(x.size)
    for k in range(x.size - 1):
        t = x[k] + s * (x[k + 1] - x[k])
        h = (x[k + 1] - x[k]) / n
        fv = f(t)
        num[k] += np.sum((1.0 - s) * fv) * h
        num[k + 1] += np.sum(s * fv) * h
        den[k] += 0.5 * (x[k + 1] - x[k])
        den[k + 1] += 0.5 * (x[k + 1] - x[k])
    out[den > 0] = num[den > 0] / den[den > 0]
    return out


def _hertz_one(R, E, nu, P, h, method, element, c_N, alpha, grading):

    Es = plane_strain_modulus(E, nu)
    a_t, _ = hertz_solution(P, R, Es)
    t0 = time.perf_counter()
    body = hertz_cylinder(R, h_contact=h, contact_width=min(1.6 * a_t, 0.5 * R), grading=grading)
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu),
                      SolidSettings(element=element))
    X, d = sp.node_X, sp.displacement_dofs()
    top = np.abs(X[:, 1] - R) <= 1e-9 * R
    spec = ConstraintSpec(n_full(sp))
    spec.fix(d[top, 0], 0.0)
    spec.tie(d[top, 1])
    top_z = int(d[top, 1][0])
    spec.fix(top_z, 0.0)
    cmap = ConstraintMap(spec)
    pen = PenaltySettings(c_N=c_N) if c_N else PenaltySettings(alpha=alpha)
    contact = Contact(SlaveSurface.from_boundary(sp.boundary(1)),
                      RigidMaster(np.array([[-2.0 * R, 0.0], [2.0 * R, 0.0]])), method=method,
                      E_eff=Es, penalty=pen, comm=body.mesh.comm)
    pb, solver = make_newton(sp, cmap, contact, force_scale=P, rtol=1e-10)
    # displacement control of the rigid top until the contact carries P within 0.5 %
    iterations = 0

    def solve_at(delta):
        nonlocal iterations
        cmap.update_value(top_z, -delta)
        iterations += solve_or_raise(solver, f"Hertz h={h:g}").iterations
        return contact.state()["Fz"]

    _, Fz, _ = approach_to_force(solve_at, P, 2.0 * a_t * a_t / R, rel_tol=5e-3)
    wall = time.perf_counter() - t0
    st = contact.state()
    act = st["active"]
    x = contact.slave.X[act, 0] + sp.w.x.array[contact.slave.dofs[act, 0]]
    p, wts = st["pressure"][act], st["weight"][act]
    # half-width from the second moment of the pressure: Int p x^2 / Int p = a^2/4 for the
    # elliptic Hertz distribution (every nodal pressure counts; the edge is integrated, not fitted)
    a_fit = 2.0 * math.sqrt(np.sum(wts * p * x * x) / np.sum(wts * p))
    _, p0_fit = fit_elliptic(x, p)
    a_ex, p0_ex = hertz_solution(Fz, R, Es)  # closed form at the load actually carried
    p0_node = float(p[np.argmin(np.abs(x))])
    # L2 error of the nodal pressures over the contact zone against the exact pressure averaged
    # like a mortar nodal value, Int N_A p_exact / Int N_A (pointwise values at the nodes would
    # penalise the square-root edge, where no nodal value can match)
    xs = contact.slave.X[:, 0] + sp.w.x.array[contact.slave.dofs[:, 0]]
    near = np.nonzero(np.abs(xs) < 1.5 * a_ex)[0]
    order = near[np.argsort(xs[near])]
    xo, po, wo = xs[order], st["pressure"][order], st["weight"][order]
    pbar = mortar_average(xo, lambda t: p0_ex * np.sqrt(np.clip(1.0 - (t / a_ex) ** 2, 0.0, None)))
    err_l2 = float(np.sqrt(np.sum(wo * (po - pbar) ** 2) / np.sum(wo * pbar ** 2)))
    return {"h_contact": h, "elements_per_a": a_ex / h, "P": Fz, "a": a_fit, "a_exact": a_ex,
            "p0": p0_node, "p0_fit": p0_fit, "p0_exact": p0_ex, "err_a": abs(a_fit - a_ex) / a_ex,
            "err_p0": abs(p0_node - p0_ex) / p0_ex, "err_l2": err_l2,
            "contact_length": st["contact_length"], "newton_iterations": iterations,
            "wall_time": wall, "dofs": n_full(sp),
            "c_N": contact.report()["penalty"]["c_N"], "active_nodes": int(act.sum())}


def hertz(*, R: float = 10.0, E: float = 6.0, nu: float = 0.3, P: float | None = None,
          a_over_R: float = 0.02, elements_per_a: tuple = (4, 8, 16, 32), method: str = "mortar",
          element: str = "Q1P0",
          c_N: float | None = None, alpha: float | None = None, grading: float = 1.2,
          tolerance: float = 0.02) -> dict:
    """Plane-strain cylinder of radius R on a rigid flat (frictionless), load P per unit depth
    (default: the load giving a = a_over_R R).  One run per refinement (elements of the contact
    zone per Hertz half-width a); the finest is checked against `tolerance`.  The top flat is
    held rigidly (u_x = 0, one u_z) and moved down until the contact carries P within 0.5 %; the
    closed form is evaluated at the load actually carried.  The half-width is measured by the second
    moment of the nodal pressures, Int p x^2 / Int p = a^2/4, and p0 is the pressure of the node at
    x = 0."""

    Es = plane_strain_modulus(E, nu)
    if P is None:
        a = a_over_R * R
        P = a * a * math.pi * Es / (4.0 * R)
    runs = [_hertz_one(R, E, nu, P, hertz_solution(P, R, Es)[0] / n, method, element, c_N,
                       alpha or DEFAULT_ALPHA, grading) for n in elements_per_a]
    fine, coarse = runs[-1], runs[0]
    checks = [check("half-width a", fine["a"], fine["a_exact"], tolerance),
              check("peak pressure p0", fine["p0"], fine["p0_exact"], tolerance),
              check("L2 pressure error", fine["err_l2"], 0.0, None)]
    notes = [f"n/a = {r['elements_per_a']:.1f}: a err {r['err_a']:.3e}, p0 err {r['err_p0']:.3e}, "
             f"L2 pressure err {r['err_l2']:.3e}, {r['newton_iterations']} Newton its, "
             f"{r['wall_time']:.1f} s, {r['dofs']} dofs" for r in runs]
    notes.append("the error is not monotone level to level: the pressure edge falls anywhere "
                 "between two nodes and the unstructured bulk mesh adds ~0.5 % nodal noise; "
                 "compare coarsest and finest")
    if len(runs) > 1:
        checks.append(check("L2 error finest/coarsest", fine["err_l2"] / coarse["err_l2"], 0.0,
                            None))
    return _result("hertz", {"R": R, "E": E, "nu": nu, "P": P, "E_star": Es, "method": method,
                             "element": element, "elements_per_a": list(elements_per_a),
                             "c_N": fine["c_N"]}, checks, notes, runs=runs)


# ----------------------------------------------------------------------------- Westergaard


def westergaard_solution(p_mean: float, E_star: float, amplitude: float, wavelength: float) -> dict:
    """Rigid sinusoid h cos(2 pi x/lambda) on an elastic half-plane (Johnson 13.2)."""
    p_star = math.pi * E_star * amplitude / wavelength
    if not 0.0 < p_mean < p_star:
        raise ValueError(f"p_mean must lie in (0, p* = {p_star:g}) for partial contact, "
                         f"got {p_mean:g}")
    s = math.sqrt(p_mean / p_star)
    a = wavelength / math.pi * math.asin(s)
    return {"p_star": p_star, "a": a, "p_peak": 2.0 * p_mean / s}


def westergaard(*, E: float = 6.0, nu: float = 0.4999, wavelength: float = 1.0,
                amplitude: float = 0.005, p_ratio: float = 0.4, n_contact: int = 64,
                master_points: int = 256, depth: float = 2.0, method: str = "mortar",
                element: str = "Q1P0", c_N: float | None = None,
                tolerance: float = 0.02) -> dict:
    """Elastic layer (one wavelength wide, periodic left/right sides, thickness depth x lambda,
    top held rigidly) pressed onto the periodic rigid sinusoid z = h cos(2 pi x/lambda) - h.
    Mean pressure p_mean = p_ratio p*.  The contact half-width comes from the pressure moment
    Int p sin^2(pi x/lambda) / Int p = sin^2(pi a/lambda)/4 (exact for the Westergaard
    distribution; every nodal pressure counts); checks: a, p* sin^2(pi a/lambda)
    against the applied p_mean, and the peak pressure 2 p_mean/sin(pi a/lambda).  depth >= 2 keeps
    the finite-layer correction below 1e-6."""

    Es = plane_strain_modulus(E, nu)
    lam, h = wavelength, amplitude
    p_star = math.pi * Es * h / lam
    p_mean = p_ratio * p_star
    ex = westergaard_solution(p_mean, Es, h, lam)
    t0 = time.perf_counter()
    body = rubber_block(lam, depth * lam, nx_contact=n_contact, grading=1.15)
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu),
                      SolidSettings(element=element))
    X, d = sp.node_X, sp.displacement_dofs()
    tol = 1e-9 * lam
    top = np.abs(X[:, 1] - depth * lam) <= tol
    left = np.nonzero(np.abs(X[:, 0]) <= tol)[0]
    right = np.nonzero(np.abs(X[:, 0] - lam) <= tol)[0]
    left, right = left[np.argsort(X[left, 1])], right[np.argsort(X[right, 1])]
    spec = ConstraintSpec(n_full(sp))
    spec.equal(d[left, 0], d[right, 0])  # periodic cell, eq. (6.5)
    spec.equal(d[left, 1], d[right, 1])
    spec.fix(d[top, 0], 0.0)
    spec.tie(d[top, 1])
    top_z = int(d[top, 1][0])
    spec.fix(top_z, 0.0)
    cmap = ConstraintMap(spec)
    xm = np.arange(master_points) * lam / master_points
    master = RigidMaster(
        np.column_stack([xm, h * np.cos(2.0 * np.pi * (xm - 0.5 * lam) / lam) - h]), period=lam)
    pen = PenaltySettings(c_N=c_N) if c_N else PenaltySettings()
    contact = Contact(SlaveSurface.from_boundary(sp.boundary(1), periodic_seam=True), master,
                      method=method, E_eff=Es, penalty=pen, search_radius=4.0 * h,
                      comm=body.mesh.comm)
    F = p_mean * lam
    pb, solver = make_newton(sp, cmap, contact, force_scale=F, rtol=1e-10, max_iterations=60)
    iterations = 0

    def solve_at(delta):
        nonlocal iterations
        cmap.update_value(top_z, -delta)
        iterations += solve_or_raise(solver, "Westergaard").iterations
        return contact.state()["Fz"]

    approach_to_force(solve_at, F, 0.05 * h)
    wall = time.perf_counter() - t0
    st = contact.state()
    pm = st["Fz"] / lam  # the mean pressure actually carried
    ex = westergaard_solution(pm, Es, h, lam)
    act = st["active"]
    x = contact.slave.X[act, 0] + sp.w.x.array[contact.slave.dofs[act, 0]] - 0.5 * lam
    p, wts = st["pressure"][act], st["weight"][act]
    # moment of the exact distribution: Int p sin^2(pi x/lam) / Int p = sin^2(pi a/lam)/4
    s2 = 4.0 * float(np.sum(wts * p * np.sin(np.pi * x / lam) ** 2) / np.sum(wts * p))
    a_fit = lam / math.pi * math.asin(math.sqrt(s2))
    p_peak = float(p[np.argmin(np.abs(x))])
    checks = [check("half-width a", a_fit, ex["a"], tolerance),
              check("p_mean = p* sin^2(pi a/lam)", p_star * s2, pm, tolerance),
              check("peak pressure", p_peak, ex["p_peak"], tolerance),
              check("contact length / 2", 0.5 * st["contact_length"], ex["a"], None)]
    notes = [f"p* = {p_star:.6g} MPa, p_mean = {pm:.6g} MPa ({pm / p_star:.3f} p*), "
             f"{iterations} Newton iterations, {wall:.1f} s, {n_full(sp)} dofs",
             contact.report_text()]
    return _result("westergaard", {"E": E, "nu": nu, "E_star": Es, "wavelength": lam,
                                   "amplitude": h,
                                   "p_ratio": p_ratio, "n_contact": n_contact,
                                   "master_points": master_points, "depth": depth, "method": method,
                                   "element": element}, checks, notes,
                   wall_time=wall)


# --------------------------------------------------------------------------- sliding block


def convergence_orders(residuals, floor: float) -> list[float]:
    """Estimated orders log(r_k+1/r_k)/log(r_k/r_k-1) over the residuals above `floor`."""
    r = [x for x in residuals if x > floor]
    return [math.log(r[k + 1] / r[k]) / math.log(r[k] / r[k - 1]) for k in range(1, len(r) - 1)
            if r[k] != r[k - 1]]


def leading_end(contact: Contact, u: np.ndarray) -> dict:
    """The slave chain end with the largest x (the front of a block sliding in +x): its pressure
    over the weighted mean of the nodes in contact, and the tilt (degrees, from the road's x axis,
    negative when the end node dips) and current-to-reference length of its end segment."""
    seg = contact.slave.segments
    ends = np.nonzero(np.bincount(seg.ravel(), minlength=len(contact.slave.X)) == 1)[0]
    x = contact.slave.X + u[contact.slave.dofs]
    A = ends[np.argmax(x[ends, 0])]
    row = np.nonzero((seg == A).any(axis=1))[0][0]
    B = seg[row, 0] if seg[row, 1] == A else seg[row, 1]
    d, D = x[A] - x[B], contact.slave.X[A] - contact.slave.X[B]
    st = contact.state()
    return {"node": int(A), "pressure_ratio": float(st["pressure"][A] / st["mean_pressure"]),
            "tilt_deg": float(np.degrees(np.arctan2(d[1], d[0]))),
            "length_ratio": float(np.linalg.norm(d) / np.linalg.norm(D))}


def gross_sliding_steps(*, mu: float, pressure: float, E: float, nu: float, height: float,
                        c_T: float, step: float, minimum: int = 12) -> int:
    """Sliding steps of length `step` that take the block twice as far as it must go before it
    slides as a whole: the top drags the block through its shear, gamma = mu p / G over the
    height H, and every node of the face through its elastic slip mu p / c_T (the tangential
    penalty, 4.17) -- 2 (mu p H / G + mu p / c_T), G = E / (2 (1 + nu)); at least `minimum`.
    Before, the case took 12 steps whatever the block: the 20 x 8 mm block at 0.3 MPa (1.17 mm to
    gross sliding) slid 1.5 mm with 80 contact elements and 1.0 mm with 120, its corner node still
    sticking, and the periodic layer did not slip at all."""
    G = E / (2.0 * (1.0 + nu))
    distance = mu * pressure * (height / G + 1.0 / c_T)
    return max(minimum, math.ceil(2.0 * distance / step))


def _block_setup(*, E, nu, length, height, n_contact, periodic, element, edge_radius=0.0):

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


def sliding_block(*, E: float = 6.0, nu: float = 0.45, pressure: float = 0.2,
                  velocity: float = 10.0, mu: float = 0.6, law=None, length: float = 1.0,
                  height: float = 0.5, n_contact: int = 16, edge_radius: float = 0.2,
                  steps: int | None = None,
                  step_length: float | None = None,
                  method: str = "mortar", element: str = "Q1P0", tolerance: float = 0.005,
                  frame: str = "slave") -> dict:
    """Coulomb sliding of an elastic block on a rigid flat, F_x/F_z = mu.

    1. Finite block (free sides, front edge rounded with `edge_radius` like the thesis' samples,
       or sharp with edge_radius = 0), constant mu: pressed by a rigid top to F_z = p L, then the
       top is dragged in +x at `velocity`; once every node slips F_x/F_z = -mu, whatever the
       (non-uniform) pressure: every nodal traction p_A n_A + t_T tau_A (5.39-5.41) has
       |t_T| = mu p_A, so the sum is on the road's friction cone wherever the nodal frames are
       the road's.  The chain ends (the block's corners) take the master's normal as their frame
       (cpp_contact/README.md, "Frame of a chain end").  Error of -F_x/F_z, 16 / 32 / 64 contact
       elements: sharp -0.16 % / -0.16 % / -0.03 % (with the one-sided normal of the end
       segment, which tilts under the corner's pressure peak, it was -1.2 % / -1.4 % / -1.8 %,
       and 0.483 instead of 0.5 for the 20 x 8 mm block below); rounded (edge_radius = 0.2)
       -0.21 % / +0.09 % / -0.02 %.  What remains is the averaged normal of the nodes next to
       the corner or on the arc, tilted where the slave is not flat.  A note reports the leading
       end node: its pressure over the mean and the tilt and length of its end segment.
       Limit: a sharp leading edge carries a concentrated normal and friction force at its
       corner node (10-20 x the mean pressure); at high p/E and fine meshes the front face, which
       is not a contact surface, rolls under the road and the corner element folds.  20 x 8 mm,
       E = 3 MPa, nu = 0.45, mu = 0.5, 0.3 MPa, default steps, slave frame: +0.47 / +0.50 /
       -0.71 / -1.65 % with 40 / 60 / 80 / 120 contact elements (with 80 the corner's neighbour,
       whose averaged normal follows the folded end segment, carries the whole deficit, and the
       front face's first node ends 0.23 mm below the road).  Before the corner projected along
       the road's normal (cpp_contact/README.md, "Frame of a chain end"): +0.42 / -1.66 / -2.71 /
       -3.55 %, a bias growing under refinement.  Round the edge there, as the thesis' run-in
       samples (6.5.1), or make the front face a contact surface.
       frame = "master" (``Contact(frame=)``): every node's frame is the road's normal, so in full
       slip -F_x/F_z = mu exactly (to round-off) wherever the run converges: the default case and
       the 20 x 8 mm block at 0.3 MPa with 40, 60 and 80 contact elements (80 stopped in Newton
       at step 16 before the corner's projection normal was the road's; 120 still stops, at step
       17 of 28).  That says nothing about the folded corner, only that every traction lies on
       the road's friction cone.
       steps (default: automatic) -- enough to slide each block twice as far as it must go
       before it slides as a whole (``gross_sliding_steps``), at least 12: 12 for the default
       case, 19 (finite) and 31 (layer) for the 20 x 8 mm block with 80 elements, whose corner
       still stuck after 12.
    2. Periodic layer (periodic sides: no edges, uniform pressure) with the friction law
       `law(p, v)` (default: a smooth spline in p and log v): the master slides at -velocity under
       the held block; in steady sliding every node has p = F_z/L and v = velocity, so
       F_x/F_z = -mu(F_z/L, v) exactly.
    The Newton residuals of the last sliding step of each run are returned with the estimated
    convergence orders (quadratic: ~2).
    """

    Es = plane_strain_modulus(E, nu)
    if law is None:
        pg = np.linspace(0.0, 1.0, 6)
        vg = np.logspace(-2, 4, 9)
        law = fl.fit_mu_pv(pg, vg,
                           0.9 - 0.25 * pg[:, None] + 0.15 * np.tanh(np.log10(vg) - 1.0)[None, :])
    ds = step_length or length / (2.0 * n_contact)
    dt = ds / velocity
    runs, n_steps = {}, {}
    for kind in ("finite", "periodic"):
        body, sp, spec, top_x, top_z = _block_setup(
            E=E, nu=nu, length=length, height=height, n_contact=n_contact,
            periodic=kind == "periodic", element=element,
            edge_radius=edge_radius if kind == "finite" else 0.0)
        cmap = ConstraintMap(spec)
        slave = SlaveSurface.from_boundary(sp.boundary(1), periodic_seam=kind == "periodic")
        friction = mu if kind == "finite" else law
        if steps is None:  # c_T of the automatic penalty rule (driver.fe.contact)
            h_min = float(np.linalg.norm(np.diff(slave.X[slave.segments], axis=1), axis=2).min())
            c_T = PenaltySettings().tangential_fraction * DEFAULT_ALPHA * Es / h_min
            mu_k = mu if kind == "finite" else float(law(pressure, velocity))
            n_steps[kind] = gross_sliding_steps(mu=mu_k, pressure=pressure, E=E, nu=nu,
                                                height=height, c_T=c_T, step=ds)
        else:
            n_steps[kind] = steps
        if kind == "finite":
            x_end = length * 3.0 + n_steps[kind] * ds
            master = RigidMaster(np.array([[-2.0 * length, 0.0], [x_end, 0.0]]))
        else:
            master = RigidMaster(np.array([[0.0, 0.0], [0.5 * length, 0.0]]), period=length)
        contact = Contact(slave, master, method=method, friction=friction, E_eff=Es, frame=frame,
                          comm=body.mesh.comm)
        F = pressure * length
        pb, solver = make_newton(sp, cmap, contact, force_scale=F, rtol=1e-11, max_iterations=40)
        contact.set_time_step(dt)

        def solve_at(delta):
            cmap.update_value(top_z, -delta)
            solve_or_raise(solver, "sliding block: compression")
            return contact.state()["Fz"]

        approach_to_force(solve_at, F, 0.1 * pressure / Es * height)
        contact.commit()
        history = []
        for k in range(1, n_steps[kind] + 1):
            if kind == "finite":
                for dof in top_x:
                    cmap.update_value(int(dof), velocity * k * dt)
            else:
                contact.set_master_offset(-velocity * k * dt)
            res = solver.solve()
            if not res.converged:
                hint = ("; a sharp leading edge tucks under at high p/E (see the docstring of "
                        "contact_cases.sliding_block): round it with edge_radius > 0"
                        if kind == "finite" and edge_radius == 0.0 else "")
                raise SolverFailure(f"sliding block ({kind}): step {k}: Newton failed: "
                                    f"{res.reason}{hint}")
            history.append([float(r) for r in res.residuals])
            contact.commit()
        st = contact.state()
        floor = 1e-13 * F  # below: round-off (observed plateau ~1e-15 F)
        # quadratic convergence: finite block in its last step, layer in its second step (the
        # first step after the stick-slip transition, where mu(p, v) and its tangent act)
        probe = history[-1] if kind == "finite" else history[min(1, len(history) - 1)]
        orders = convergence_orders(probe, floor)
        runs[kind] = {"state": st, "residuals": history, "probe": probe, "orders": orders,
                      "order": orders[-1] if orders else float("nan"),
                      "report": contact.report_text(),
                      "leading_end": (leading_end(contact, sp.w.x.array) if kind == "finite"
                                      else None)}
    fin, per = runs["finite"]["state"], runs["periodic"]["state"]
    p_per = per["Fz"] / length
    mu_pv = float(law(p_per, velocity))
    act = per["active"]
    checks = [
        check("finite block: slipping nodes", float(fin["n_slip"]), float(fin["n_active"]), 0.0),
        check("finite block: -F_x/F_z", -fin["Fx"] / fin["Fz"], mu, tolerance),
        check("layer: slipping nodes", float(per["n_slip"]), float(per["n_active"]), 0.0),
        check("layer: pressure spread", float(np.ptp(per["pressure"][act]) / p_per), 0.0, None),
        check("layer: slip velocity", float(per["slip_velocity"][act].mean()), velocity, tolerance),
        check("layer: -F_x/F_z = mu(p, v)", -per["Fx"] / per["Fz"], mu_pv, tolerance),
        check("Newton order, finite block", runs["finite"]["order"], 2.0, None),
        check("Newton order, layer mu(p,v)", runs["periodic"]["order"], 2.0, None),
    ]
    end = runs["finite"]["leading_end"]
    notes = [(f"finite block, leading end node (frame: the master's normal): "
              f"p = {end['pressure_ratio']:.3g} x the mean, end segment tilted "
              f"{end['tilt_deg']:.3g} deg, {100 * end['length_ratio']:.3g} % of its length"
              if end["pressure_ratio"] > 0 else "finite block, leading end node out of contact"),
             f"periodic layer: p = {p_per:.6g} MPa, v = {velocity:g} mm/s, mu(p, v) = {mu_pv:.6g}",
             "finite block, last sliding step: residuals "
             f"{['%.1e' % r for r in runs['finite']['probe']]}",
             "layer, second sliding step: residuals "
             f"{['%.1e' % r for r in runs['periodic']['probe']]}",
             "Newton order = log(r_k+1/r_k)/log(r_k/r_k-1) of the last iterations above round-off",
             runs["periodic"]["report"]]
    return _result("sliding-block", {"E": E, "nu": nu, "pressure": pressure, "velocity": velocity,
                                     "mu": mu, "length": length, "height": height,
                                     "n_contact": n_contact, "edge_radius": edge_radius,
                                     "steps": steps or n_steps, "method": method,
                                     "element": element, "frame": frame}, checks, notes,
                   newton={k: {"residuals": v["residuals"], "orders": v["orders"],
                               "order": v["order"]}
                           for k, v in runs.items()})


# ------------------------------------------------------------------------ thermal contact


def mixed_surface(mesh, facet_tags, tag, Xu, du, XT, dT):
    """Nodes of the facets `tag` with their displacement and temperature dofs, segments oriented
    counter-clockwise around the owning body (cell centroid on the left)."""
    from dolfinx import cpp as _cpp

    tdim = mesh.topology.dim
    facets = facet_tags.indices[facet_tags.values == tag]
    mesh.topology.create_connectivity(tdim - 1, 0)
    mesh.topology.create_connectivity(tdim - 1, tdim)
    f2v, f2c = mesh.topology.connectivity(tdim - 1, 0), mesh.topology.connectivity(tdim - 1, tdim)
    verts = np.array([f2v.links(f) for f in facets])
    g = _cpp.mesh.entities_to_geometry(mesh._mesh, 0, verts.ravel().astype(np.int32), False).ravel()
    vx = mesh.geometry.x[g, :2]
    _, nu_ = cKDTree(Xu).query(vx)
    dist, nt = cKDTree(XT).query(Xu[nu_])
    if dist.max() > 1e-10:
        raise RuntimeError("temperature and displacement nodes do not coincide")
    seg = nu_.reshape(-1, 2).copy()  # (flipped below; nu_ stays paired with nt)
    cells = np.array([f2c.links(f)[0] for f in facets])
    gd = mesh.geometry.dofmap
    cent = np.array([mesh.geometry.x[gd.links(c), :2].mean(axis=0) for c in cells])
    a, b = Xu[seg[:, 0]], Xu[seg[:, 1]]
    t = b - a
    flip = np.einsum("ij,ij->i", np.column_stack([t[:, 1], -t[:, 0]]), 0.5 * (a + b) - cent) < 0.0
    seg[flip] = seg[flip][:, ::-1]
    uniq, inv = np.unique(seg.ravel(), return_inverse=True)
    tmap = dict(zip(nu_.tolist(), nt.tolist()))
    return Xu[uniq], du[uniq], inv.reshape(-1, 2), dT[np.array([tmap[i] for i in uniq])]


def thermal_bars(*, L1: float = 0.5, L2: float = 1.0, k1: float = 0.25, k2: float = 50.0,
                 width: float = 1.0, h0: float = 2.0, h1: float = 0.5, beta: float = 1.0,
                 T_top: float = 400.0, T_bottom: float = 300.0, n_upper: int = 5, n_lower: int = 7,
                 penetration: float = 1e-4, c_N: float = 1e3, mu: float = 0.5, kappa: float = 0.3,
                 slide: float = 0.01, dt: float = 1e-3, method: str = "mortar",
                 tolerance: float = 1e-8) -> dict:
    """Two bars in contact along z (upper [0, w] x [gap, gap + L1], conductivity k1; lower
    [0, w] x [-L2, 0], k2; non-matching interface meshes), steady heat conduction, displacements
    prescribed (the upper bar penetrates by `penetration`: p = c_N x penetration).

    1. Conduction: T_top on the upper end, T_bottom on the lower end, interface conductance
       h_c(p) = h0 + h1 p^beta: q = (T_top - T_bottom)/(L1/k1 + 1/h_c + L2/k2), jump q/h_c.
    2. Frictional heating (no conduction, both ends at T_bottom): the upper bar slides by `slide`
       in one step dt with friction mu; the heat leaving through the two ends must equal
       kappa W and (1 - kappa) W with W = mu p v A, v = (slide - mu p/c_T)/dt, A = w - slide.
    Heat flows are the reactions at the fixed-temperature ends (per unit depth)."""

    gap = 0.01 * width
    body = two_blocks(width, L1, L2, n_upper, n_lower, ny_upper=6, ny_lower=8, gap=gap)
    mesh, tags = body.mesh, body.facet_tags
    cell = mesh.ufl_cell()
    W = fem.FunctionSpace(mesh, ufl.MixedElement([ufl.VectorElement("Lagrange", cell, 1),
                                                  ufl.FiniteElement("Lagrange", cell, 1)]))
    w = fem.Function(W)
    Vu, mu_map = W.sub(0).collapse()
    VT, mt_map = W.sub(1).collapse()
    Xu = Vu.tabulate_dof_coordinates()[:, :2]
    du = np.asarray(mu_map, dtype=np.int64).reshape(-1, 2)
    XT = VT.tabulate_dof_coordinates()[:, :2]
    dT = np.asarray(mt_map, dtype=np.int64)
    kfun = fem.Function(fem.FunctionSpace(mesh, ("DG", 0)))
    ncell = mesh.topology.index_map(2).size_local
    zc = fem.Function(fem.FunctionSpace(mesh, ("DG", 0)))
    zc.interpolate(lambda x: x[1])
    kfun.x.array[:] = np.where(zc.x.array[:ncell] > 0.5 * gap, k1, k2)
    _, T = ufl.split(w)
    _, tau = ufl.TestFunctions(W)
    R = kfun * ufl.inner(ufl.grad(T), ufl.grad(tau)) * ufl.dx
    J = ufl.derivative(R, w, ufl.TrialFunction(W))
    n = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
    tol = 1e-9 * width
    upper_u = Xu[:, 1] > 0.5 * gap
    top = dT[np.abs(XT[:, 1] - (gap + L1)) <= tol]
    bottom = dT[np.abs(XT[:, 1] + L2) <= tol]
    su = mixed_surface(mesh, tags, 1, Xu, du, XT, dT)
    sm = mixed_surface(mesh, tags, 5, Xu, du, XT, dT)
    p = c_N * penetration
    results = {}
    for phase in ("conduction", "friction"):
        spec = ConstraintSpec(n)
        spec.fix(du[upper_u, 0], slide if phase == "friction" else 0.0)
        spec.fix(du[upper_u, 1], -(gap + penetration))
        spec.fix(du[~upper_u].ravel(), 0.0)
        spec.fix(top, T_top if phase == "conduction" else T_bottom)
        spec.fix(bottom, T_bottom)
        cmap = ConstraintMap(spec)
        thermal = ThermalSettings(h0=h0 if phase == "conduction" else 0.0,
                                  h1=h1 if phase == "conduction" else 0.0, beta=beta, kappa=kappa)
        contact = Contact(SlaveSurface(su[0], su[1], su[2], su[3]),
                          DeformableMaster(sm[0], sm[1], sm[2], sm[3]), method=method,
                          friction=mu if phase == "friction" else None,
                          penalty=PenaltySettings(c_N=c_N), thermal=thermal, comm=mesh.comm)
        contact.set_time_step(dt)
        w.x.array[:] = 0.0
        w.x.array[dT] = T_bottom
        pb = ConstrainedNonlinearProblem(R, J, w, cmap, hooks=[contact.hook],
                                         extra_couplings=contact.couplings())
        scale = k1 * abs(T_top - T_bottom) / L1 * width + 1.0
        solve_or_raise(NewtonSolver(pb, newton_settings(rtol=1e-14, atol=1e-14 * scale),
                                    force_scale=scale),
                       f"thermal bars ({phase})")
        # R = F_int - F_ext: at a fixed-temperature dof the residual is the heat entering there
        heat_top = float(pb.reaction(top).sum())
        heat_bottom = float(pb.reaction(bottom).sum())
        st = contact.state()
        results[phase] = {"heat_top": heat_top, "heat_bottom": heat_bottom, "state": st,
                          "T_interface_upper": float(w.x.array[su[3]].mean()),
                          "T_interface_lower": float(w.x.array[sm[3]].mean()),
                          "T_spread_upper": float(np.ptp(w.x.array[su[3]]))}
    hc = h0 + h1 * p ** beta
    q = (T_top - T_bottom) / (L1 / k1 + 1.0 / hc + L2 / k2)
    con, fr = results["conduction"], results["friction"]
    cT = PenaltySettings().tangential_fraction * c_N
    v = (slide - mu * p / cT) / dt
    Wf = mu * p * v * (width - slide)
    checks = [
        check("conduction: heat in at top", con["heat_top"], q * width, tolerance),
        check("conduction: heat out at bottom", -con["heat_bottom"], q * width, tolerance),
        check("conduction: interface jump", con["T_interface_upper"] - con["T_interface_lower"],
              q / hc, tolerance),
        check("friction: total heat W", -(fr["heat_top"] + fr["heat_bottom"]), Wf, 1e-6),
        check("friction: slave share", -fr["heat_top"], kappa * Wf, 1e-6),
        check("friction: master share", -fr["heat_bottom"], (1.0 - kappa) * Wf, 1e-6),
        check("friction: W from contact state", fr["state"]["friction_power"], Wf, 1e-6),
    ]
    notes = [f"h_c(p) = {hc:.6g} at p = {p:.6g} MPa; q = {q:.6g} mW/mm^2; "
             f"W = mu p v A = {Wf:.6g} mW/mm",
             "interface temperature spread on the slave (conduction): "
             f"{con['T_spread_upper']:.3e} K"]
    return _result("thermal-bars", {"L1": L1, "L2": L2, "k1": k1, "k2": k2, "width": width,
                                    "h0": h0, "h1": h1, "beta": beta, "T_top": T_top,
                                    "T_bottom": T_bottom, "n_upper": n_upper, "n_lower": n_lower,
                                    "c_N": c_N, "mu": mu, "kappa": kappa, "slide": slide,
                                    "dt": dt, "method": method}, checks, notes)


# ------------------------------------------------------------------- periodic wrap-around


def periodic_sliding(*, E: float = 6.0, nu: float = 0.45, wavelength: float = 1.0,
                     amplitude: float = 0.01, p_ratio: float = 0.5, mu: float = 0.3,
                     velocity: float = 10.0, n_contact: int = 32, steps_per_period: int = 32,
                     periods: int = 3, method: str = "mortar",
                     element: str = "Q1P0", tolerance: float = 1e-6) -> dict:
    """An elastic layer (one wavelength wide, periodic sides, top held) pressed onto the periodic
    rigid sinusoid (mean pressure p_ratio p*, partial contact) and slid with friction over
    `periods` periods: the master wraps across the cell boundary every period.  After the first
    period (run-in) the response is periodic: the per-period means of F_x, F_z and of the
    frictional dissipation agree between the last two periods within `tolerance`."""
    Es = plane_strain_modulus(E, nu)
    lam, h = wavelength, amplitude
    p_star = math.pi * Es * h / lam
    body, sp, spec, top_x, top_z = _block_setup(E=E, nu=nu, length=lam, height=lam,
                                                n_contact=n_contact, periodic=True, element=element)
    cmap = ConstraintMap(spec)
    xm = np.arange(8 * n_contact) * lam / (8 * n_contact)
    master = RigidMaster(
        np.column_stack([xm, h * np.cos(2.0 * np.pi * (xm - 0.5 * lam) / lam) - h]), period=lam)
    contact = Contact(SlaveSurface.from_boundary(sp.boundary(1), periodic_seam=True), master,
                      method=method, friction=mu, E_eff=Es, search_radius=4.0 * h,
                      comm=body.mesh.comm)
    F = p_ratio * p_star * lam
    pb, solver = make_newton(sp, cmap, contact, force_scale=F, rtol=1e-12, max_iterations=60)
    dt = lam / steps_per_period / velocity
    contact.set_time_step(dt)

    def solve_at(delta):
        cmap.update_value(top_z, -delta)
        solve_or_raise(solver, "periodic sliding: compression")
        return contact.state()["Fz"]

    approach_to_force(solve_at, F, 0.05 * h)
    contact.commit()
    t0 = time.perf_counter()
    rows, iterations = [], 0
    for k in range(1, periods * steps_per_period + 1):
        contact.set_master_offset(-velocity * k * dt)
        iterations += solve_or_raise(solver, f"periodic sliding: step {k}").iterations
        contact.commit()
        st = contact.state()
        rows.append((st["Fx"], st["Fz"], st["dissipation"]))
    wall = time.perf_counter() - t0
    arr = np.array(rows).reshape(periods, steps_per_period, 3).mean(axis=1)
    last, prev = arr[-1], arr[-2]
    checks = [check("mean F_x, last two periods", last[0], prev[0], tolerance),
              check("mean F_z, last two periods", last[1], prev[1], tolerance),
              check("mean dissipation, last two periods", last[2], prev[2], tolerance),
              check("mean F_x, run-in vs last", arr[0][0], last[0], None)]
    notes = [f"{periods} periods x {steps_per_period} steps, {iterations} Newton iterations, "
             f"{wall:.1f} s; mean -F_x/F_z = {-last[0] / last[1]:.6g}", contact.report_text()]
    return _result("periodic-sliding", {"E": E, "nu": nu, "wavelength": lam, "amplitude": h,
                                        "p_ratio": p_ratio, "mu": mu, "velocity": velocity,
                                        "n_contact": n_contact,
                                        "steps_per_period": steps_per_period,
                                        "periods": periods, "method": method},
                   checks, notes, period_means=arr.tolist())


# ------------------------------------------------------------------------------ CLI glue

#: CLI name -> case function (the registry in ``driver/verification/__init__.py`` points all of
#: them to this module; ``run`` dispatches on ``args.case``).
CASE_FUNCTIONS = {"patch": patch, "hertz": hertz, "westergaard": westergaard,
                  "sliding-block": sliding_block, "thermal-bars": thermal_bars,
                  "periodic-sliding": periodic_sliding}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of the case function (defaults shown in --help)."""
    add_keyword_arguments(parser, case_function(CASE_FUNCTIONS, parser, "contact_cases"))


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(CASE_FUNCTIONS[args.case], args)
