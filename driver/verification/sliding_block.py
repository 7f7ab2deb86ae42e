"""Coulomb sliding block (``rubberfriction verify sliding-block``): F_x/F_z = mu for constant mu
(finite block) and a mu(p, v) spline at the known (p, v) of a periodic layer in steady sliding;
the Newton residual history of a sliding step shows quadratic convergence.  Shared set-up:
``contact_common``.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.fe.constraints import ConstraintMap
from rubberfriction.driver.fe.contact import (
    DEFAULT_ALPHA,
    Contact,
    PenaltySettings,
    RigidMaster,
    SlaveSurface,
)
from rubberfriction.driver.verification import (
    SolverFailure,
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
    A fixed 12 steps left a larger block's corner node sticking and the periodic layer not
    slipping (docs/verification.md)."""
    G = E / (2.0 * (1.0 + nu))
    distance = mu * pressure * (height / G + 1.0 / c_T)
    return max(minimum, math.ceil(2.0 * distance / step))


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
       (cpp_contact/README.md, "Frame of a chain end"; the one-sided normal of the end segment
       tilts under the corner's pressure peak).  What error remains is the averaged normal of the
       nodes next to the corner or on the arc, tilted where the slave is not flat (errors per
       mesh: docs/verification.md).  A note reports the leading end node: its pressure over the
       mean and the tilt and length of its end segment.
       Limit: a sharp leading edge carries a concentrated normal and friction force at its
       corner node; at high p/E and fine meshes the front face, which is not a contact surface,
       rolls under the road and the corner element folds, and the error grows under refinement
       (the 20 x 8 mm block at 0.3 MPa: docs/verification.md).  Round the edge there, as the
       thesis' run-in samples (6.5.1), or make the front face a contact surface.
       frame = "master" (``Contact(frame=)``): every node's frame is the road's normal, so in full
       slip -F_x/F_z = mu exactly (to round-off) wherever the run converges (which runs do:
       docs/verification.md).  That says nothing about the folded corner, only that every
       traction lies on the road's friction cone.
       steps (default: automatic) -- enough to slide each block twice as far as it must go
       before it slides as a whole (``gross_sliding_steps``), at least 12.
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
        body, sp, spec, top_x, top_z = elastic_body(
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
                        "verification.sliding_block): round it with edge_radius > 0"
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
    return verdict("sliding-block", {"E": E, "nu": nu, "pressure": pressure, "velocity": velocity,
                                     "mu": mu, "length": length, "height": height,
                                     "n_contact": n_contact, "edge_radius": edge_radius,
                                     "steps": steps or n_steps, "method": method,
                                     "element": element, "frame": frame}, checks, notes,
                   newton={k: {"residuals": v["residuals"], "orders": v["orders"],
                               "order": v["order"]}
                           for k, v in runs.items()})


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of :func:`sliding_block` (defaults shown in --help)."""
    add_keyword_arguments(parser, sliding_block)


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(sliding_block, args)
