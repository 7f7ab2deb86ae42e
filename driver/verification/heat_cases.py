"""Heat verification cases of the thermal macro scale (``rubberfriction verify flash-flux|...``).

All three run the project's block-and-road conduction (``driver.thermal.conduction.TwoBodyHeat``:
Q1 elements graded from the interface, lumped interface, implicit Euler) against the closed forms
of ``driver.theory.heat_sources``:

* ``flash-flux``: block at rest on the road, uniform frictional power q, kappa = 1, h_c = 0:
  block surface temperature T0 + 2 q sqrt(t / (pi k rho c)).
* ``two-body-conduction``: the same with h_c large, both bodies conducting: interface temperature
  T0 + 2 q sqrt(t / pi) / (e1 + e2), heat split e_i / (e1 + e2); plus the heat bookkeeping of the
  adiabatic run (stored heat = time integral of the power).
* ``moving-heat-source``: kappa = 0, h_c = 0, the road moving under the block at v (block frame,
  SUPG-stabilised convection): steady road surface temperature under the block against Jaeger's
  moving band source.  The road extents are set in units of the decay length 2 chi / v
  (``moving_band_domain``), which keeps the 2D low-Peclet growth of the field inside the mesh.

Times are geometrically graded from t_end / (n_steps * 10^3): the sqrt(t) rise starts with an
infinite rate, and implicit Euler with equal steps would lag at early times.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rubberfriction.driver.theory.heat_sources import (
    effusivity,
    flash_flux_rise,
    moving_band_domain,
    moving_band_rise,
    two_body_rise,
)
from rubberfriction.driver.thermal.conduction import HeatGeometry, TwoBodyHeat, geometric_steps
from rubberfriction.driver.verification import (add_keyword_arguments, call_with_arguments,
                                                case_function, check)
from rubberfriction.forms.material_files import load_compound, load_road


def _materials(compound: str, road: str):
    rubber = load_compound(compound).thermal
    rd = load_road(road).thermal
    if rubber is None or rd is None:
        raise ValueError(f"thermal data missing: compound {compound!r} or road {road!r} has no "
                         "[thermal] table")
    return rubber, rd


def _transient(heat: TwoBodyHeat, q: float, t_end: float, n_steps: int, probe_times) -> dict:
    """Run with uniform flux q (nodal power q w_i); record interface temperatures at the first step
    ending at or after each probe time (with that step's time)."""
    power = q * heat.interface.weights
    t, out, energy_in = 0.0, [], 0.0
    probes = sorted(probe_times)
    for dt in geometric_steps(t_end, n_steps):
        heat.step(float(dt), power, True)
        t += dt
        energy_in += float(power.sum()) * dt
        while probes and t >= probes[0] * (1.0 - 1e-12):
            tb, tr = heat.interface_temperatures()
            probes.pop(0)
            out.append((t, float(tb.mean()), float(tr.mean()), float(np.ptp(tb))))
    return {"probes": out, "energy_in": energy_in, "content": heat.heat_content()}


def flash_flux(*, q: float = 1.0, t_end: float = 1.0, T0: float = 293.15,
               compound: str = "tread_default", road: str = "r1", block_length: float = 1.0,
               block_height: float = 8.0, h_x: float = 0.25, first_layer: float = 0.01,
               n_steps: int = 160, tolerance: float = 0.01) -> dict:
    """Uniform frictional power q (mW/mm^2) into a resting block (kappa = 1, h_c = 0) for t_end:
    block surface temperature against T0 + 2 q sqrt(t / (pi k rho c)) at t_end / 4, / 2 and
    t_end."""
    rubber, rd = _materials(compound, road)
    chi = rubber.diffusivity
    if block_height < 6.0 * math.sqrt(chi * t_end):
        raise ValueError(f"flash-flux: block_height = {block_height} mm is not a half-space for "
                         f"t_end = {t_end} s "
                         f"(needs >= 6 sqrt(chi t) = {6.0 * math.sqrt(chi * t_end):.3g} mm)")
    geo = HeatGeometry(block_length=block_length, block_height=block_height, road_depth=1.0,
                       road_ahead=0.0, road_behind=0.0, h_x=h_x, first_layer=first_layer)
    heat = TwoBodyHeat(geo, rubber, rd, T0=T0, kappa=1.0, h_c=0.0, top_temperature=T0)
    wall = time.perf_counter()
    res = _transient(heat, q, t_end, n_steps, [t_end / 4, t_end / 2, t_end])
    wall = time.perf_counter() - wall
    checks = [check(f"block surface rise, t = {t:.4g} s", tb - T0,
                    float(flash_flux_rise(q, t, rubber.k, rubber.rho, rubber.c)), tolerance)
              for t, tb, _, _ in res["probes"]]
    checks.append(check("road surface rise, K (h_c = 0)", res["probes"][-1][2] - T0, 0.0, 1e-9))
    notes = [heat.describe(), f"{n_steps} graded implicit Euler steps, {wall:.2f} s; "
             f"effusivity e = {effusivity(rubber.k, rubber.rho, rubber.c):.4g}, sqrt(chi t_end) = "
             f"{math.sqrt(chi * t_end):.3g} mm",
             f"temperature spread along the heated face: {res['probes'][-1][3]:.2e} K (1D: 0)"]
    return _result("flash-flux", locals(), checks, notes)


def two_body_conduction(*, q: float = 1.0, t_end: float = 1.0, T0: float = 293.15,
                        h_c: float = 1.0e6, kappa: float = 1.0, compound: str = "tread_default",
                        road: str = "r1", block_length: float = 1.0, depth: float = 8.0,
                        h_x: float = 0.25, first_layer: float = 0.01, n_steps: int = 160,
                        tolerance: float = 0.01) -> dict:
    """Uniform frictional power q at the interface of block and road (both conducting, h_c large,
    adiabatic outer faces): interface temperature against T0 + 2 q sqrt(t / pi) / (e1 + e2), the
    heat share of the block against e1 / (e1 + e2), and the stored heat against q A t (1e-6)."""
    rubber, rd = _materials(compound, road)
    chi = max(rubber.diffusivity, rd.diffusivity)
    if depth < 6.0 * math.sqrt(chi * t_end):
        raise ValueError(f"two-body-conduction: depth = {depth} mm is not a half-space for "
                         f"t_end = {t_end} s "
                         f"(needs >= 6 sqrt(chi t) = {6.0 * math.sqrt(chi * t_end):.3g} mm)")
    geo = HeatGeometry(block_length=block_length, block_height=depth, road_depth=depth,
                       road_ahead=0.0, road_behind=0.0, h_x=h_x, first_layer=first_layer)
    heat = TwoBodyHeat(geo, rubber, rd, T0=T0, kappa=kappa, h_c=h_c, top_temperature=None)
    wall = time.perf_counter()
    res = _transient(heat, q, t_end, n_steps, [t_end / 4, t_end / 2, t_end])
    wall = time.perf_counter() - wall
    e1, e2 = effusivity(rubber.k, rubber.rho, rubber.c), effusivity(rd.k, rd.rho, rd.c)
    checks = [check(f"interface rise, t = {t:.4g} s", 0.5 * (tb + tr) - T0,
                    float(two_body_rise(q, t, e1, e2)), tolerance)
              for t, tb, tr, _ in res["probes"]]
    eb, er = res["content"]
    checks += [check("block share of the heat", eb / (eb + er), e1 / (e1 + e2), tolerance),
               check("stored heat / frictional energy", (eb + er) / res["energy_in"], 1.0, 1e-6)]
    jump = res["probes"][-1][1] - res["probes"][-1][2]
    notes = [heat.describe(),
             f"{n_steps} graded implicit Euler steps, {wall:.2f} s; e1 = {e1:.4g}, e2 = {e2:.4g}",
             f"temperature jump block - road at t_end: {jump:.3e} K (h_c = {h_c:g})"]
    return _result("two-body-conduction", locals(), checks, notes)


def moving_heat_source(*, q: float = 1.0, length: float = 2.0, peclet: tuple = (2.0, 20.0),
                       T0: float = 293.15, road: str = "r1", compound: str = "tread_default",
                       elements: int = 80, first_layer: float = 0.01,
                       tolerance: float = 0.03) -> dict:
    """Block of length l sliding at v = 2 chi Pe / l over the road, all frictional heat q into the
    road (kappa = 0, h_c = 0): steady road surface temperature under the block (mean, trailing
    edge, 3/4 of the band) against Jaeger's moving band source, for each Peclet number."""
    rubber, rd = _materials(compound, road)
    chi = rd.diffusivity
    h_x = length / elements
    checks, notes, profiles = [], [], {}
    for pe in peclet:
        v = 2.0 * chi * pe / length
        dom = moving_band_domain(length, v, chi)
        whole = lambda d: h_x * math.ceil(d / h_x)  # noqa: E731 - whole elements
        geo = HeatGeometry(block_length=length, block_height=min(1.0, length),
                           road_depth=dom["depth"], road_ahead=whole(dom["ahead"]),
                           road_behind=whole(dom["behind"]), h_x=h_x, first_layer=first_layer)
        heat = TwoBodyHeat(geo, rubber, rd, T0=T0, kappa=0.0, h_c=0.0, road_velocity=-v,
                           top_temperature=T0)
        wall = time.perf_counter()
        heat.steady(q * heat.interface.weights, False)
        wall = time.perf_counter() - wall
        x, T = heat.road_surface()
        under = (x >= -1e-12) & (x <= length + 1e-12)
        xs, dT = x[under], T[under] - T0
        exact = moving_band_rise(xs, q=q, length=length, velocity=v, k=rd.k, chi=chi)
        w = np.full(len(xs), h_x)
        w[[0, -1]] *= 0.5
        i34 = int(np.argmin(np.abs(xs - 0.25 * length)))
        checks += [check(f"Pe {pe:g}: mean rise under the block", float(w @ dT / length),
                         float(w @ exact / length), tolerance),
                   check(f"Pe {pe:g}: rise at the trailing edge", float(dT[0]), float(exact[0]),
                         tolerance),
                   check(f"Pe {pe:g}: rise at x = l/4", float(dT[i34]), float(exact[i34]),
                         tolerance)]
        notes.append(f"Pe {pe:g}: v = {v:.4g} mm/s, decay length 2 chi/v = "
                     f"{dom['decay_length']:.3g} mm, road "
                     f"[{-geo.road_behind:.3g}, {length + geo.road_ahead:.3g}] x "
                     f"{geo.road_depth:.3g} mm, {len(heat.X)} dofs, element Peclet "
                     f"{heat.supg_peclet:.3g}, steady solve {wall:.2f} s; "
                     f"largest pointwise error under the block "
                     f"{np.max(np.abs(dT - exact)) / exact.max():.2%} "
                     f"of the peak")
        profiles[f"{pe:g}"] = {"x": xs.tolist(), "computed": dT.tolist(),
                               "analytical": exact.tolist()}
    params = {k: v for k, v in locals().items()
              if k in ("q", "length", "peclet", "T0", "road", "elements", "first_layer",
                       "tolerance")}
    return {"case": "moving-heat-source", "parameters": params, "checks": checks, "notes": notes,
            "profiles": profiles}


def _result(case: str, scope: dict, checks: list, notes: list) -> dict:
    names = ("q", "t_end", "T0", "h_c", "kappa", "compound", "road", "block_length", "block_height",
             "depth", "h_x", "first_layer", "n_steps", "tolerance")
    return {"case": case, "parameters": {k: scope[k] for k in names if k in scope},
            "checks": checks, "notes": notes}


CASE_FUNCTIONS = {"flash-flux": flash_flux, "two-body-conduction": two_body_conduction,
                  "moving-heat-source": moving_heat_source}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_keyword_arguments(parser, case_function(CASE_FUNCTIONS, parser, "heat_cases"))


def run(args: argparse.Namespace) -> dict:
    return call_with_arguments(CASE_FUNCTIONS[args.case], args)
