"""Westergaard (``rubberfriction verify westergaard``): elastic layer (one period, periodic
sides, thickness >= 2 lambda) on the periodic rigid sinusoid z = h cos(2 pi x/lambda):
p* = pi E* h/lambda, p_mean = p* sin^2(pi a/lambda).  Shared set-up: ``contact_common``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.contact import (
    Contact,
    PenaltySettings,
    RigidMaster,
    SlaveSurface,
)
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import (
    add_keyword_arguments,
    call_with_arguments,
    check,
)
from rubberfriction.driver.verification.contact_common import (
    approach_to_force,
    elastic_compound,
    make_newton,
    n_full,
    plane_strain_modulus,
    solve_or_raise,
    verdict,
)
from rubberfriction.meshes.block import rubber_block


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
    return verdict("westergaard", {"E": E, "nu": nu, "E_star": Es, "wavelength": lam,
                                   "amplitude": h,
                                   "p_ratio": p_ratio, "n_contact": n_contact,
                                   "master_points": master_points, "depth": depth, "method": method,
                                   "element": element}, checks, notes,
                   wall_time=wall)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of :func:`westergaard` (defaults shown in --help)."""
    add_keyword_arguments(parser, westergaard)


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(westergaard, args)
