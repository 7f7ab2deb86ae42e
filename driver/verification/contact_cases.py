"""Contact verification cases against closed forms (``rubberfriction verify patch|hertz|...``).

Each case is a plain function with keyword parameters returning a dict

    {"case", "parameters", "checks": [check(quantity, computed, analytical, tol)], "notes", ...}

that the tests call with fixed parameters and the CLI with the user's.  Bulk: the project's
finite-strain Mooney-Rivlin solid (``driver.solid.SolidProblem``, Q1P0) in the small-strain regime
of the closed forms; contact: ``driver.contact`` (C++ mortar or node-to-segment); Newton:
``driver.newton`` with the contact as a hook.

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

from rubberfriction.driver.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.contact import (
    Contact, DeformableMaster, PenaltySettings, RigidMaster, SlaveSurface, ThermalSettings)
from rubberfriction.driver.newton import ConstrainedNonlinearProblem, NewtonSettings, NewtonSolver
from rubberfriction.driver.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import check

# --------------------------------------------------------------------------------- helpers


def elastic_compound(E: float, nu: float):
    """Neo-Hooke compound with small-strain Young's modulus E [MPa] and Poisson ratio nu."""
    from rubberfriction.forms.materials import Compound, MooneyRivlin

    G = E / (2.0 * (1.0 + nu))
    K = E / (3.0 * (1.0 - 2.0 * nu))
    return Compound(name=f"elastic E={E:g} nu={nu:g}", hyperelastic=MooneyRivlin.neo_hooke(G, K), prony=None,
                    wlf=None, thermal=None)


def plane_strain_modulus(E: float, nu: float) -> float:
    return E / (1.0 - nu * nu)


def _mesh_arrays(body) -> tuple[np.ndarray, np.ndarray]:
    m = body.mesh
    return m.geometry.x[:, :2].copy(), m.geometry.dofmap.array.reshape(-1, 4).astype(np.int64)


def merged_mesh(bodies, rules, levels=(), info=None):
    """One DOLFINx mesh holding several disconnected bodies (meshes.common.BodyMesh), with new
    facet rules (tag, predicate) -- the project's Newton works on one function space."""
    from rubberfriction.meshes.common import build_body_mesh

    pts, cells, off = [], [], 0
    for b in bodies:
        p, c = _mesh_arrays(b)
        pts.append(p)
        cells.append(c + off)
        off += p.shape[0]
    return build_body_mesh(MPI.COMM_SELF, np.vstack(pts), np.vstack(cells), rules, levels, info or {})


def n_full(sp) -> int:
    return sp.W.dofmap.index_map.size_local * sp.W.dofmap.index_map_bs


def make_newton(sp, cmap, contact: Contact, *, fext=None, force_scale=1.0, rtol=1e-10, max_iterations=30):
    pb = ConstrainedNonlinearProblem(sp.residual, sp.jacobian(), sp.w, cmap, hooks=[contact.hook],
                                     extra_couplings=contact.couplings(), external_force=fext)
    solver = NewtonSolver(pb, NewtonSettings(rtol=rtol, atol=1e-14 * force_scale, max_iterations=max_iterations),
                          force_scale=force_scale)
    return pb, solver


def solve_or_raise(solver, what: str):
    res = solver.solve()
    if not res.converged:
        raise RuntimeError(f"{what}: Newton failed: {res.reason}")
    return res


def cauchy_zz(sp) -> np.ndarray:
    """sigma_zz at every quadrature point."""
    from rubberfriction.forms.kinematics import deformation_gradient
    from rubberfriction.forms.viscoelastic import evaluate_at_points

    u, _ = sp.split()
    F = deformation_gradient(u)
    sigma = F * sp.second_piola() * F.T / ufl.det(F)
    cells = np.arange(sp.mesh.topology.index_map(2).size_local, dtype=np.int32)
    return evaluate_at_points(sigma[1, 1], sp.mesh, sp.rule, cells).ravel(), cells


def _result(case: str, parameters: dict, checks: list, notes=(), **extra) -> dict:
    out = {"case": case, "parameters": parameters, "checks": checks, "notes": list(notes)}
    out.update(extra)
    return out


# ----------------------------------------------------------------------------- patch test


def patch(*, E: float = 10.0, nu: float = 0.3, pressure: float = 0.1, length: float = 1.0,
          n_upper: int = 7, n_lower: int = 5, method: str = "mortar", c_N: float | None = None,
          tolerance: float = 1e-8) -> dict:
    """Contact patch test on non-matching meshes.

    Upper block [0, l] x [gap, gap + l/2] (slave, n_upper facets on its contact face) on the lower
    block [0, l] x [-l/2, 0] (deformable master, n_lower facets), same material, frictionless.
    Uniform dead-load pressure on top, the lower block's bottom on rollers, both left faces on
    symmetry rollers (u_x = 0).  The exact discrete solution is homogeneous: the contact pressure
    at every slave node equals the applied force over the current contact length, and sigma_zz
    is uniform in both bodies.
    """
    from rubberfriction.meshes.patch import patch_test_pair

    gap = 0.01 * length
    up, lo = patch_test_pair(length, 0.5 * length, 0.5 * length, n_upper=n_upper, n_lower=n_lower, gap=gap)
    tol = 1e-9 * length
    hu = 0.5 * length
    rules = [
        (1, lambda p: np.abs(p[:, 1] - gap) <= tol),  # upper contact face
        (2, lambda p: np.abs(p[:, 1] - (gap + hu)) <= tol),  # upper top
        (3, lambda p: (np.abs(p[:, 0]) <= tol) & (p[:, 1] >= gap - tol)),
        (4, lambda p: (np.abs(p[:, 0] - length) <= tol) & (p[:, 1] >= gap - tol)),
        (5, lambda p: np.abs(p[:, 1]) <= tol),  # lower contact face
        (6, lambda p: np.abs(p[:, 1] + 0.5 * length) <= tol),  # lower bottom
        (7, lambda p: (np.abs(p[:, 0]) <= tol) & (p[:, 1] <= tol)),
        (8, lambda p: (np.abs(p[:, 0] - length) <= tol) & (p[:, 1] <= tol)),
    ]
    body = merged_mesh([up, lo], rules, levels=(0.5 * gap,))
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu), SolidSettings(element="Q1P0"))
    q = fem.Constant(body.mesh, 0.0)
    sp.add_traction(2, ufl.as_vector([0.0, -q]))
    X, d = sp.node_X, sp.displacement_dofs()
    spec = ConstraintSpec(n_full(sp))
    spec.fix(d[np.abs(X[:, 1] + 0.5 * length) <= tol, 1], 0.0)
    spec.fix(d[np.abs(X[:, 0]) <= tol, 0], 0.0)
    cmap = ConstraintMap(spec)
    Es = plane_strain_modulus(E, nu)
    pen = PenaltySettings(c_N=c_N) if c_N else PenaltySettings()
    contact = Contact(SlaveSurface.from_boundary(sp.boundary(1)), DeformableMaster.from_boundary(sp.boundary(5)),
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
    mid_z = np.repeat(sp.mesh.geometry.x[sp.mesh.geometry.dofmap.array.reshape(-1, 4)][:, :, 1].mean(axis=1),
                      szz.size // cells.size)
    s_up, s_lo = szz[mid_z > 0.5 * gap], szz[mid_z < 0.5 * gap]
    checks = [
        check("slave nodes in contact", float(act.sum()), float(act.size), 0.0),
        check("contact pressure min", float(p.min()), p_exact, tolerance),
        check("contact pressure max", float(p.max()), p_exact, tolerance),
        check("total contact force F_z", st["Fz"], pressure * length, tolerance),
        check("sigma_zz upper (max dev.)", float(s_up[np.argmax(np.abs(s_up + p_exact))]), -p_exact, tolerance),
        check("sigma_zz lower (max dev.)", float(s_lo[np.argmax(np.abs(s_lo + p_exact))]), -p_exact, tolerance),
    ]
    notes = [f"{method}: pressure spread (max-min)/p = {(p.max() - p.min()) / p_exact:.3e}, "
             f"sigma_zz spread in the lower block {(s_lo.max() - s_lo.min()) / p_exact:.3e}",
             contact.report_text()]
    return _result("patch", {"E": E, "nu": nu, "pressure": pressure, "length": length, "n_upper": n_upper,
                             "n_lower": n_lower, "method": method, "c_N": cN}, checks, notes,
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


def _hertz_one(R, E, nu, P, h, method, element, c_N, alpha, grading):
    from rubberfriction.meshes.cylinder import hertz_cylinder

    Es = plane_strain_modulus(E, nu)
    a_t, _ = hertz_solution(P, R, Es)
    t0 = time.perf_counter()
    body = hertz_cylinder(R, h_contact=h, contact_width=min(1.6 * a_t, 0.5 * R), grading=grading)
    sp = SolidProblem(body.mesh, body.facet_tags, elastic_compound(E, nu), SolidSettings(element=element))
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
                      RigidMaster(np.array([[-2.0 * R, 0.0], [2.0 * R, 0.0]])), method=method, E_eff=Es,
                      penalty=pen, comm=body.mesh.comm)
    pb, solver = make_newton(sp, cmap, contact, force_scale=P, rtol=1e-10)
    # displacement control of the rigid top; secant on the approach until F_z = P within 0.5 %
    delta, Fz, history = 2.0 * a_t * a_t / R, 0.0, []
    iterations = 0
    for _ in range(12):
        cmap.update_value(top_z, -delta)
        res = solve_or_raise(solver, f"Hertz h={h:g}")
        iterations += res.iterations
        Fz = contact.state()["Fz"]
        history.append((delta, Fz))
        if abs(Fz - P) <= 5e-3 * P:
            break
        if len(history) >= 2 and history[-1][1] != history[-2][1]:
            (d0, f0), (d1, f1) = history[-2:]
            delta = d1 + (P - f1) * (d1 - d0) / (f1 - f0)
        else:
            delta *= (P / Fz) if Fz > 0 else 2.0
    wall = time.perf_counter() - t0
    st = contact.state()
    act = st["active"]
    x = contact.slave.X[act, 0] + sp.w.x.array[contact.slave.dofs[act, 0]]
    p = st["pressure"][act]
    a_fit, p0_fit = fit_elliptic(x, p)
    a_ex, p0_ex = hertz_solution(Fz, R, Es)  # closed form at the load actually carried
    p0_node = float(p[np.argmin(np.abs(x))])
    return {"h_contact": h, "elements_per_a": a_ex / h, "P": Fz, "a": a_fit, "a_exact": a_ex,
            "p0": p0_node, "p0_fit": p0_fit, "p0_exact": p0_ex, "err_a": abs(a_fit - a_ex) / a_ex,
            "err_p0": abs(p0_node - p0_ex) / p0_ex, "contact_length": st["contact_length"],
            "newton_iterations": iterations, "wall_time": wall, "dofs": n_full(sp),
            "c_N": contact.report()["penalty"]["c_N"], "active_nodes": int(act.sum())}


def hertz(*, R: float = 10.0, E: float = 6.0, nu: float = 0.3, P: float | None = None, a_over_R: float = 0.04,
          elements_per_a: tuple = (4, 8, 16), method: str = "mortar", element: str = "Q1P0",
          c_N: float | None = None, alpha: float | None = None, grading: float = 1.2,
          tolerance: float = 0.02) -> dict:
    """Plane-strain cylinder of radius R on a rigid flat (frictionless), load P per unit depth
    (default: the load giving a = a_over_R R).  One run per refinement (elements of the contact
    zone per Hertz half-width a); the finest is checked against `tolerance`.  a is fitted to the
    nodal pressures (p^2 linear in x^2), p0 is the pressure of the node at x = 0.  The top flat is
    held rigidly (u_x = 0, one u_z) and moved down until the contact carries P within 0.5 %; the
    closed form is evaluated at the load actually carried."""
    from rubberfriction.driver.contact import DEFAULT_ALPHA

    Es = plane_strain_modulus(E, nu)
    if P is None:
        a = a_over_R * R
        P = a * a * math.pi * Es / (4.0 * R)
    runs = [_hertz_one(R, E, nu, P, hertz_solution(P, R, Es)[0] / n, method, element, c_N,
                       alpha or DEFAULT_ALPHA, grading) for n in elements_per_a]
    fine = runs[-1]
    checks = [check("half-width a", fine["a"], fine["a_exact"], tolerance),
              check("peak pressure p0", fine["p0"], fine["p0_exact"], tolerance)]
    notes = [f"n/a = {r['elements_per_a']:.1f}: a err {r['err_a']:.3e}, p0 err {r['err_p0']:.3e}, "
             f"{r['newton_iterations']} Newton its, {r['wall_time']:.1f} s" for r in runs]
    return _result("hertz", {"R": R, "E": E, "nu": nu, "P": P, "E_star": Es, "method": method, "element": element,
                             "elements_per_a": list(elements_per_a), "c_N": fine["c_N"]}, checks, notes, runs=runs)
