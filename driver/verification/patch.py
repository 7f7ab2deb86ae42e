"""Contact patch test (``rubberfriction verify patch``): two stacked blocks with non-matching
contact meshes, uniform pressure on top: the contact pressure must be uniform (exact for
segment-to-segment; node-to-segment reported).  Shared set-up: ``contact_common``.
"""

from __future__ import annotations

import argparse

import numpy as np
import ufl
from dolfinx import fem

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.contact import (
    Contact,
    DeformableMaster,
    PenaltySettings,
    SlaveSurface,
)
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.verification import (
    add_keyword_arguments,
    call_with_arguments,
    check,
)
from rubberfriction.driver.verification.contact_common import (
    cauchy_zz,
    elastic_compound,
    make_newton,
    n_full,
    plane_strain_modulus,
    solve_or_raise,
    two_blocks,
    verdict,
)


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
    return verdict("patch", {"E": E, "nu": nu, "pressure": pressure, "length": length,
                             "n_upper": n_upper, "n_lower": n_lower, "method": method, "c_N": cN},
                   checks, notes,
                   pressure_spread=float((p.max() - p.min()) / p_exact),
                   stress_spread_lower=float((s_lo.max() - s_lo.min()) / p_exact),
                   stress_spread_upper=float((s_up.max() - s_up.min()) / p_exact))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of :func:`patch` (defaults shown in --help)."""
    add_keyword_arguments(parser, patch)


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(patch, args)
