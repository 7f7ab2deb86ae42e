"""Benchmark: the thermal macro scale (thesis 8.4.1, 8.5.1).

    rubberfriction bench thermal [--part mesh|velocities|road|bulk|all] [--out DIR]

``mesh``: the macro mesh study of thesis 8.4.1 on the shipped scene ``thermal_macro`` (20 x 8 mm
block, p = 0.3 MPa, v = 1 m/s, 10 mm of sliding, mu(T_s) of the scene, kappa = 1, h_c = 1e6) with
three z-resolutions at the interface (first element 0.04, 0.02, 0.01 mm): the temperature gradient
dT/dz in the road at the interface (pressure-weighted over the contact), the contact temperature,
mu after 10 mm, wall time, peak memory of the process and the time split into mechanics, heat and
contact.

``velocities``: the set-up of thesis 8.5.1 (hyperelastic m3, l = 20, h = 7 mm, p = 0.3 MPa,
T0 = 20 degC, kappa = 1, h_c = 1e6, road r1) for v = 0.01, 0.1, 1 m/s with a constant mu per
velocity of the magnitude of thesis fig. 8.11 a (``MU_OF_V``, stated values, not the measurement):
the road temperature behind the block T_R and the contact temperature T_C over v.

``road``: rigid against elastic road (thesis 8.4.1 takes the road as rigid), side by side on the
mesh study's case (first element 0.01 mm): the road r1 (E = 40 GPa) and, to show the trend, a road
100 times softer (stated, not a material); mu, T_C, T_R, T_max, the road's sink under the
contact and their differences from the rigid road (in %; T_R, which may be close to T0 behind
a block whose trailing edge lifts, in K).  Run it with ``--edge-radius 1`` (thesis 8.5.1): with
the square edge the corner's hot spot is not steady, and a sub-micrometre deflection moves T_C
(docs/performance.md) -- that is the corner, not the road.

``bulk``: the rubber bulk temperature study of thesis 8.5.2 (hyperelastic m2, 20 x 7 mm block with
a 1 mm rounded leading edge, p = 0.3 MPa, v = 0.5 m/s, T0 = 20 degC, kappa = 1, h_c = 1e6, road r1,
flat; mu = 0.9 stated, the magnitude of thesis fig. 8.14 a; with mu = 1.0 this block fails when full
slip sets in after 3.5 mm): ``--slides`` slides of ``--slide`` mm
(thesis: 350 mm per experiment, which it computed as seven 50 mm runs) with a 35 s pause (block
lifted) after each but the last, thermocouples at the back of the block (x = 2 mm) 1, 2 and 4 mm
above the face: their temperatures at the end of each slide and pause, and the wall time per
sliding step (the Eulerian road costs the same per step whatever the slide length).
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import time

import numpy as np

from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.multiscale.thermal_scene import friction_of
from rubberfriction.driver.thermal.macro import (THESIS_INTERFACE, MacroSettings, flat_road_spec,
                                                 run_thermal_macro, run_thermal_slides)
from rubberfriction.forms.material_files import load_compound, load_road

#: mu per velocity (mm/s) for the 8.5.1 set-up: the magnitude of thesis fig. 8.11 a (stated values)
MU_OF_V = {10.0: 0.9, 100.0: 0.95, 1000.0: 1.0}
FIRST_LAYERS = (0.04, 0.02, 0.01)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--part", choices=("mesh", "velocities", "road", "bulk", "all"), default="all")
    p.add_argument("--slides", type=int, default=2,
                   help="bulk: slides of --slide mm with 35 s pauses")
    p.add_argument("--velocity", type=float, default=1000.0, help="mm/s, mesh study")
    p.add_argument("--slide", type=float, default=10.0, help="sliding distance, mm")
    p.add_argument("--edge-radius", type=float, default=0.0,
                   help="rounded leading edge of the block, mm (a multiple of the 0.25 mm contact "
                        "elements, >= 0.75 mm; 0: square)")


def _macro(compound, road, *, length, height, pressure, velocity, friction, slide, first_layer, T0,
           h_contact=0.25, edge_radius=0.0, road_elastic=None):
    spec = flat_road_spec(compound, pressure=pressure, velocity=velocity, friction=friction,
                          block_length=length, block_height=height, slide_distance=slide,
                          h_contact=h_contact, T0=T0, edge_radius=edge_radius)
    settings = MacroSettings(road=road, T0=T0, interface=THESIS_INTERFACE, road_depth=10.0,
                             road_ahead=2.0, road_behind=20.0, first_layer=first_layer,
                             road_elastic=road_elastic)
    wall = time.perf_counter()
    res = run_thermal_macro(spec, compound.thermal, settings)
    wall = time.perf_counter() - wall
    return res, wall


def _row(res, wall: float, T0: float) -> dict:
    s, st = res.series, res.sliding.stats
    out = {"status": res.sliding.status if res.ok else "failed", "wall": wall,
           "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}
    if not len(s.get("t", [])):
        return out
    _, g_road = res.heat.interface_gradients()
    p = res.profiles["pressure"]
    cpu_heat, cpu_contact = res.stats["cpu_heat"], st.get("cpu_contact", 0.0)
    out.update({"mu": float(np.mean(s["mu"][-max(1, len(s["mu"]) // 5):])),
                "T_C": s["T_contact"][-1] - T0, "T_max": s["T_max"][-1] - T0,
                "T_R": s["T_road_behind"][-1] - T0,
                "grad_road": float(p @ g_road / p.sum()) if p.sum() > 0 else float("nan"),
                "heat_dofs": res.stats["heat_dofs"], "cpu_heat": cpu_heat,
                "cpu_contact": cpu_contact,
                "cpu_mech": st.get("cpu_attempt", float("nan")) - cpu_heat - cpu_contact,
                "steps": st.get("steps"), "per_step_ms": 1e3 * wall / max(1, st.get("steps", 1))})
    return out


def run(args: argparse.Namespace) -> int:
    parts = ("mesh", "velocities", "road", "bulk") if args.part == "all" else (args.part,)
    ok = True
    if "mesh" in parts:
        scene, comp, r, T0, law = _thermal_macro_case()
        road = r.thermal
        print(f"thermal macro mesh study (thesis 8.4.1): block {scene.thermal.block_length} x "
              f"{scene.thermal.block_height} mm, edge radius {args.edge_radius:g} mm, p 0.3 MPa, "
              f"v {args.velocity:g} mm/s, slide {args.slide} mm, "
              f"mu(T_s) of the scene thermal_macro")
        print(f"{'first layer':>11} {'heat dofs':>9} {'dT/dz road':>11} {'T_C-T0':>7} "
              f"{'T_max-T0':>8} {'mu':>6} {'wall s':>7} {'ms/step':>7} "
              f"{'mech/heat/contact CPU s':>24} {'RSS MB':>7}")
        for first in FIRST_LAYERS:
            res, wall = _macro(comp, road, length=scene.thermal.block_length,
                               height=scene.thermal.block_height, pressure=0.3,
                               velocity=args.velocity, friction=law, slide=args.slide,
                               first_layer=first, T0=T0, edge_radius=args.edge_radius)
            r = _row(res, wall, T0)
            ok &= r["status"] == "ok"
            if "mu" not in r:
                print(f"{first:>11g}  failed: {res.sliding.reason} "
                      f"{res.stats.get('thermal_error', '')}")
                continue
            print(f"{first:>11g} {r['heat_dofs']:>9.0f} {r['grad_road']:>11.4g} {r['T_C']:>7.3f} "
                  f"{r['T_max']:>8.3f} {r['mu']:>6.4f} {r['wall']:>7.1f} {r['per_step_ms']:>7.0f} "
                  f"{r['cpu_mech']:>8.1f}/{r['cpu_heat']:>5.1f}/{r['cpu_contact']:>5.1f}      "
                  f"{r['rss_mb']:>7.0f}",
                  flush=True)
    if "velocities" in parts:
        comp = dataclasses.replace(load_compound("m3"), prony=None)  # hyperelastic, as thesis 8.5.1
        road = load_road("r1").thermal
        T0 = 293.15
        print("thesis 8.5.1 set-up: m3 (Mooney-Rivlin of table C.2 only: hyperelastic), 20 x 7 mm, "
              f"edge radius {args.edge_radius:g} mm, p 0.3 MPa, T0 20 degC, kappa 1, h_c 1e6, "
              f"slide {args.slide} mm; mu(v) stated: {MU_OF_V}")
        print(f"{'v m/s':>6} {'mu':>5} {'T_C-T0':>7} {'T_R-T0':>7} {'T_max-T0':>8} {'wall s':>7}")
        for v, mu in MU_OF_V.items():
            res, wall = _macro(comp, road, length=20.0, height=7.0, pressure=0.3, velocity=v,
                               friction=mu, slide=args.slide, first_layer=0.01, T0=T0,
                               edge_radius=args.edge_radius)
            r = _row(res, wall, T0)
            ok &= r["status"] == "ok"
            if "mu" not in r:
                print(f"{v / 1e3:>6g}  failed: {res.sliding.reason} "
                      f"{res.stats.get('thermal_error', '')}")
                continue
            print(f"{v / 1e3:>6g} {mu:>5.2f} {r['T_C']:>7.3f} {r['T_R']:>7.3f} {r['T_max']:>8.3f} "
                  f"{r['wall']:>7.1f}",
                  flush=True)
    if "road" in parts:
        ok &= _road_study(args)
    if "bulk" in parts:
        ok &= _bulk_study(args)
    return 0 if ok else 1


def _thermal_macro_case():
    """The shipped scene thermal_macro's inputs: scene, compound, road material, T0 (K), mu(T_s)
    law."""
    scene = load_scene("thermal_macro")
    return (scene, load_compound(scene.conditions.compound_paths[0]), load_road(scene.thermal.road),
            scene.conditions.T0, friction_of(scene))


def _road_study(args: argparse.Namespace) -> bool:
    """Rigid against elastic road, side by side (see the module doc)."""
    scene, comp, r1, T0, law = _thermal_macro_case()
    print(f"road mechanics: block {scene.thermal.block_length} x {scene.thermal.block_height} mm, "
          f"edge radius {args.edge_radius:g} mm, p 0.3 MPa, v {args.velocity:g} mm/s, "
          f"slide {args.slide} mm, mu(T_s) of thermal_macro, road {r1.name} "
          f"(E {r1.E:g} MPa, nu {r1.nu:g}); differences from the rigid road")
    print(f"{'road':>16} {'mu':>8} {'T_C-T0':>8} {'T_R-T0':>8} {'T_max-T0':>8} {'sink um':>8} "
          f"{'d mu %':>7} {'d T_C %':>7} {'d T_max %':>9} {'d T_R K':>8} {'wall s':>7}")
    ok, base = True, None
    for label, elastic in (("rigid", None), (f"{r1.name} elastic", r1),
                           ("E/100 elastic", dataclasses.replace(r1, E=r1.E / 100.0))):
        res, wall = _macro(comp, r1.thermal, length=scene.thermal.block_length,
                           height=scene.thermal.block_height, pressure=0.3, velocity=args.velocity,
                           friction=law, slide=args.slide, first_layer=0.01, T0=T0,
                           edge_radius=args.edge_radius, road_elastic=elastic)
        r = _row(res, wall, T0)
        ok &= r["status"] == "ok"
        if "mu" not in r:
            print(f"{label:>16}  failed: {res.sliding.reason} {res.stats.get('thermal_error', '')}")
            continue
        r["sink"] = 1e3 * float(res.series["road_sink"][-1])
        base = base or r
        d = {k: 100.0 * (r[k] / base[k] - 1.0) for k in ("mu", "T_C", "T_max")}
        print(f"{label:>16} {r['mu']:>8.5f} {r['T_C']:>8.4f} {r['T_R']:>8.4f} {r['T_max']:>8.4f} "
              f"{r['sink']:>8.4f} {d['mu']:>7.3f} {d['T_C']:>7.3f} {d['T_max']:>9.3f} "
              f"{r['T_R'] - base['T_R']:>8.4f} {r['wall']:>7.1f}",
              flush=True)
    return ok


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench thermal", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(ap)
    return run(ap.parse_args(argv))


def _bulk_study(args: argparse.Namespace) -> bool:
    """Thesis 8.5.2: repeated slides with pauses, bulk thermocouples (see the module doc)."""
    # thermo-hyperelastic, as the thesis
    comp = dataclasses.replace(load_compound("m2"), prony=None)
    road = load_road("r1").thermal
    T0, v, mu = 293.15, 500.0, 0.9
    probes = ((2.0, 1.0), (2.0, 2.0), (2.0, 4.0))
    spec = flat_road_spec(comp, pressure=0.3, velocity=v, friction=mu, block_length=20.0,
                          block_height=7.0, slide_distance=args.slide, h_contact=0.25, T0=T0,
                          edge_radius=1.0)
    settings = MacroSettings(road=road, T0=T0, interface=THESIS_INTERFACE, road_depth=10.0,
                             road_ahead=2.0, road_behind=20.0, first_layer=0.01, probes=probes)
    print(f"thesis 8.5.2 set-up: m2 (hyperelastic), 20 x 7 mm, edge radius 1 mm, p 0.3 MPa, "
          f"v {v / 1e3:g} m/s, mu {mu} (stated), {args.slides} slides of {args.slide:g} mm, "
          f"35 s pauses; thermocouples at x = 2 mm, "
          f"z = {', '.join(f'{z:g}' for _, z in probes)} mm", flush=True)
    wall = time.perf_counter()

    def progress(slide: int, k: int, n: int) -> None:
        if k == n or k % max(1, n // 10) == 0:
            print(f"  slide {slide}: step {k}/{n}, {time.perf_counter() - wall:.0f} s", flush=True)

    res = run_thermal_slides(spec, comp.thermal, settings, pauses=(35.0,) * (args.slides - 1),
                             progress=progress)
    wall = time.perf_counter() - wall
    h = res.history
    steps = sum(len(r.series.get("t", [])) for r in res.slides)
    print(f"{'event':>14} {'t s':>8} "
          + " ".join(f"{'T(z=' + format(z, 'g') + ')-T0':>11}" for _, z in probes)
          + f" {'surface-T0':>10}")
    ends = [i for i in range(len(h["t"]))
            if i + 1 == len(h["t"]) or h["slide"][i + 1] != h["slide"][i]]
    for i in ends:
        what = f"end of slide {int(h['slide'][i])}" if h["slide"][i] > 0 else "end of pause"
        print(f"{what:>14} {h['t'][i]:>8.2f} " + " ".join(f"{h[f'probe_{j}'][i] - T0:>11.3f}"
                                                          for j in range(len(probes)))
              + f" {h['T_surface'][i] - T0:>10.3f}")
    print(f"{'ok' if res.ok else 'failed'}: {steps} sliding steps in {wall:.0f} s "
          f"({1e3 * wall / max(steps, 1):.0f} ms per step incl. compression and pauses)",
          flush=True)
    return res.ok
