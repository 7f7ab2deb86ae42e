"""Thermal contact (``rubberfriction verify thermal-bars``): two bars through a conductance,
q = dT/(L1/k1 + 1/h_c + L2/k2), and frictional heat mu p v A split kappa / 1 - kappa between the
bodies.  Shared set-up: ``contact_common``.
"""

from __future__ import annotations

import argparse

import numpy as np
import ufl
from dolfinx import fem
from scipy.spatial import cKDTree

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.contact import (
    Contact,
    DeformableMaster,
    PenaltySettings,
    SlaveSurface,
    ThermalSettings,
)
from rubberfriction.driver.fe.newton import (
    ConstrainedNonlinearProblem,
    NewtonSolver,
)
from rubberfriction.driver.verification import (
    add_keyword_arguments,
    call_with_arguments,
    check,
)
from rubberfriction.driver.verification.contact_common import (
    newton_settings,
    solve_or_raise,
    two_blocks,
    verdict,
)


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
    return verdict("thermal-bars", {"L1": L1, "L2": L2, "k1": k1, "k2": k2, "width": width,
                                    "h0": h0, "h1": h1, "beta": beta, "T_top": T_top,
                                    "T_bottom": T_bottom, "n_upper": n_upper, "n_lower": n_lower,
                                    "c_N": c_N, "mu": mu, "kappa": kappa, "slide": slide,
                                    "dt": dt, "method": method}, checks, notes)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One --option per keyword parameter of :func:`thermal_bars` (defaults shown in --help)."""
    add_keyword_arguments(parser, thermal_bars)


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(thermal_bars, args)
