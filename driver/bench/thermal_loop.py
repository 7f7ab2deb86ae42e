"""Benchmark: the studies of the thermal multiscale loop (thesis 8.4.2, 8.4.3).

    rubberfriction bench thermal-loop [--part partitions|divisions|all] [--store DIR]

``partitions`` (thesis 8.4.2, fig. 8.7, 8.8): one micro cell (l = h = 0.3 mm, a sine of 0.01 mm
amplitude, p = 1.5 MPa, v = 0.5 m/s, frictionless, tread_default) under two stated temperature
gradients T(z) = T0 + A exp(-z / d) (gradient 1: A = 20 K, d = 0.02 mm; gradient 2: A = 60 K,
d = 0.03 mm) sampled on macro levels (first 0.005 mm, grading 1.1), handed down as n_p = 1, 2, 4, 8
partitions below 0.09 mm (and the finest the levels allow); mu, its change from the finest, wall.

``divisions`` (thesis 8.4.3, fig. 8.10): the shipped scene ``thermal_loop`` at 1 m/s with
n_d = 1, 2, 4, 8 equal divisions, each with warm starts (every point's runs slide on from the
point before, ``[thermal] warm_start``) and with every run from rest, side by side: final mu,
the wall time per interval (cascade), the share of each scale in the lower-scale runs' time and
the cost of the coupled point against the isothermal point (its cascade alone, timed first;
issue target: at most 3x with n_d = 4).  Every loop and the isothermal point get their own
store (``--store DIR``: ``DIR/isothermal``, ``DIR/n_d=<n>-warm``, ``DIR/n_d=<n>-rest``; default
temporary folders), so nothing is reused between them; a rerun with the same ``--store`` reuses
its runs and the times then say so.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from rubberfriction.driver.multiscale.results import Point
from rubberfriction.driver.multiscale.scales import build_scales
from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
from rubberfriction.driver.multiscale.thermal_loop import (
    CascadeRunner,
    isothermal_partitions,
    run_thermal_loop,
)
from rubberfriction.driver.multiscale.thermal_loop_scene import loop_settings
from rubberfriction.driver.runtime.farm import Executor
from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.sliding.run import run_sliding, sliding_runner
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.thermal.conduction import block_levels
from rubberfriction.driver.fe.contact import ThermalSettings
from rubberfriction.driver.thermal.macro import MacroSettings, flat_road_spec
from rubberfriction.driver.thermal.profile import TemperatureProfile, partition_profile
from rubberfriction.forms.material_files import load_compound, load_road

GRADIENTS = {"gradient 1": (20.0, 0.02), "gradient 2": (60.0, 0.03)}  # (A K, d mm)
N_PARTITIONS = (1, 2, 4, 8)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--part", choices=("partitions", "divisions", "all"), default="all")
    p.add_argument("--store", default=None,
                   help="store folder for the divisions study's lower-scale runs")


def _partitions() -> bool:
    comp = load_compound("tread_default")
    T0 = 293.15
    L, amp = 0.3, 0.01
    x = np.linspace(0.0, L, 97)[:-1]
    base = SlidingSpec(surface_x=x, surface_h=amp * np.cos(2 * np.pi * x / L), period=L,
                       pressure=1.5, velocity=500.0, compound=comp, temperature=T0,
                       h_contact=L / 16, slide_distance=2 * L, step_length=L / 32)
    z = block_levels(L, 0.005, 1.1)
    print("thermal loop partition study (thesis 8.4.2): micro cell l = h = 0.3 mm, "
          "sine amplitude 0.01 mm, p 1.5 MPa, v 0.5 m/s, frictionless, tread_default; "
          "T(z) = T0 + A exp(-z/d) on macro levels "
          f"(first 0.005 mm, grading 1.1, {np.count_nonzero(z <= 0.09) - 1} rows above 0.09 mm)")
    print(f"{'gradient':>10} {'A K':>5} {'d mm':>5} {'n_p':>4} {'T_1 K':>7} {'mu':>9} "
          f"{'vs finest':>9} {'wall s':>7}")
    ok = True
    for name, (A, d) in GRADIENTS.items():
        prof = TemperatureProfile(z, T0 + A * np.exp(-z / d), np.zeros_like(z), 1)
        finest = int(np.count_nonzero(z <= 0.09) - 1)
        rows = []
        for n_p in (*N_PARTITIONS, finest):
            parts = partition_profile(prof, n_p, 0.09)
            spec = replace(base, temperature_layers=parts.layers, temperature=parts.background)
            t = time.perf_counter()
            res = run_sliding(spec)
            rows.append((n_p, parts.layers[0][1], res.mu_force if res.ok else np.nan,
                         time.perf_counter() - t))
            ok &= res.ok
        ref = rows[-1][2]
        for n_p, T1, mu, wall in rows:
            print(f"{name:>10} {A:>5g} {d:>5g} {n_p:>4d} {T1 - T0:>+7.2f} {mu:>9.5f} "
                  f"{100 * (mu / ref - 1):>+8.2f}% {wall:>7.1f}", flush=True)
    return ok


def _divisions(store_dir: str | None) -> bool:
    scene = load_scene("thermal_loop")
    t = scene.thermal
    comps = load_compounds(scene)
    scales = build_scales(scene, max(scene.samples.pressure, scene.samples.friction))
    folder = Path(store_dir) if store_dir else Path(tempfile.mkdtemp(prefix="rf-thermal-loop-"))
    runner = sliding_runner(wall_limit=scene.numerics.run_timeout)
    comp = comps[scene.conditions.compounds[0]]
    T0 = scene.conditions.T0
    v, p = 1000.0, scene.conditions.pressures[0]
    spec = flat_road_spec(comp, pressure=p, velocity=v, friction=0.0, block_length=t.block_length,
                          block_height=t.block_height, slide_distance=t.slide_distance,
                          h_contact=t.h_contact, T0=T0)
    thermal = MacroSettings(road=load_road(t.road).thermal, T0=T0,
                            interface=ThermalSettings(h0=t.h_c, kappa=t.kappa),
                            road_depth=t.road_depth, road_ahead=t.road_ahead,
                            road_behind=t.road_behind, first_layer=t.first_layer,
                            grading=t.grading)
    print(f"thermal loop division study (thesis 8.4.3): scene thermal_loop at v = {v:g} mm/s, "
          f"p = {p:g} MPa, slide {t.slide_distance} mm, mu_const {t.mu_const}; stores in {folder}")

    def cascade_runner(name: str, warm: bool = False) -> CascadeRunner:
        executor = Executor(Store(folder / name), runner)
        return CascadeRunner(scene.name, Point(scene.conditions.compounds[0], p, v), scales.sets,
                             SpecBuilder(scene, comps), scene.samples.pressure,
                             scene.samples.friction, executor,
                             states=executor.store.load_state if warm else None,
                             warm_window=t.warm_window_periods)

    # the isothermal point: its cascade alone, on the partition bounds the loop uses at T0
    base = loop_settings(scene)
    w_iso = time.perf_counter()
    iso = cascade_runner("isothermal")(isothermal_partitions(spec, thermal, base))
    w_iso = time.perf_counter() - w_iso
    reused = sum(o.reused for runs in iso.runs.values() for _, o in runs)
    mu_iso = iso.mu.mean if iso.ok and iso.mu else float("nan")
    print(f"isothermal point: lower mu {mu_iso:.5f}, wall {w_iso:.1f} s"
          f"{f' ({reused} runs reused)' if reused else ''}")
    print("start: warm = each point's runs slide on from the point before ([thermal] warm_start),"
          " rest = every run from rest (the thesis)")
    print(f"{'n_d':>4} {'start':>5} {'mu final':>9} {'lower mu':>9} {'T_s-T0':>7} {'wall s':>7} "
          f"{'s/interval':>10} {'x iso':>6}  share per scale")
    ok = iso.ok
    for n_d, start in ((n, st) for n in (1, 2, 4, 8) for st in ("warm", "rest")):
        settings = replace(base, divisions=n_d, points=(), auto_dT=0.0)
        cascade = cascade_runner(f"n_d={n_d}-{start}", warm=start == "warm")
        w = time.perf_counter()
        res = run_thermal_loop(spec, comp.thermal, thermal, settings, cascade)
        w = time.perf_counter() - w
        ok &= res.ok
        share: dict[str, float] = {}
        for iv in res.intervals:
            for stage, runs in iv.cascade.runs.items():
                name = scales.sets[int(stage.split(":")[1])].name
                share[name] = share.get(name, 0.0) + sum(o.wall_time for _, o in runs
                                                         if not o.reused)
        total = sum(share.values()) or 1.0
        per = np.mean([iv.wall for iv in res.intervals]) if res.intervals else np.nan
        T_s = res.intervals[-1].profile.mean[0] - T0 if res.intervals else np.nan
        shares = ", ".join(f"{k} {100 * s / total:.0f} %" for k, s in share.items())
        print(f"{n_d:>4d} {start:>5} {res.mu:>9.5f} {res.mu - settings.mu_const:>9.5f} {T_s:>7.2f} "
              f"{w:>7.1f} {per:>10.2f} {w / w_iso:>6.2f}  {shares or 'all runs reused'}",
              flush=True)
    return ok


def run(args: argparse.Namespace) -> int:
    ok = True
    if args.part in ("partitions", "all"):
        ok &= _partitions()
    if args.part in ("divisions", "all"):
        ok &= _divisions(args.store)
    return 0 if ok else 1


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench thermal-loop", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(ap)
    return run(ap.parse_args(argv))
