"""Periodic wrap-around (``rubberfriction verify periodic-sliding``): an elastic layer slid with
friction over several periods of a wrapped periodic rigid sinusoid; after the run-in period the
per-period means agree.  Shared set-up: ``contact_common``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rubberfriction.driver.fe.constraints import ConstraintMap
from rubberfriction.driver.fe.contact import (
    Contact,
    RigidMaster,
    SlaveSurface,
)
from rubberfriction.driver.verification import (
    add_keyword_arguments,
    call_with_arguments,
    check,
)
from rubberfriction.driver.verification.contact_common import (
    approach_to_force,
    elastic_body,
    make_newton,
    plane_strain_modulus,
    solve_or_raise,
    verdict,
)


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
    body, sp, spec, top_x, top_z = elastic_body(E=E, nu=nu, length=lam, height=lam,
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
    return verdict("periodic-sliding", {"E": E, "nu": nu, "wavelength": lam, "amplitude": h,
                                        "p_ratio": p_ratio, "mu": mu, "velocity": velocity,
                                        "n_contact": n_contact,
                                        "steps_per_period": steps_per_period,
                                        "periods": periods, "method": method},
                   checks, notes, period_means=arr.tolist())


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of :func:`periodic_sliding` (defaults shown in --help)."""
    add_keyword_arguments(parser, periodic_sliding)


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(periodic_sliding, args)
