"""Benchmark: the speed-accuracy trade of the whole method at one mu point of a scene's road.

    rubberfriction bench trade [--scene four_scale] [--samples K J] [--pressure 0.3]
                               [--velocity 100] [--out DIR]
                               [--settings quick,el6,el12,el24,alpha10,alpha100,k2,k10,step2,
                                           converged]
    mpirun -n 2 rubberfriction bench trade ...      # the campaigns farm their runs over the ranks

One (p, v) point of a scene (default: the default scene) is computed with each
setting: the quick defaults of the shipped scene, then one setting changed at a time (contact
elements per shortest wavelength 6 / 12 / 24, normal penalty factor alpha 10 / 100, samples per
scale k = j = 2 / 10, the sliding step halved), and the most converged setting (24 elements per
wavelength, alpha 100, ten samples, half the convergence tolerance, half the step).  Printed per
setting: mu with its 95 % confidence interval over the samples, the runs it needs (failed,
unconverged), and their cost: the sum of the runs' wall times (each run's own time, also when
this bench found it in the store, so every row is the cost of computing that setting from
scratch).  Last, how far the quick defaults are from the most converged setting.  All campaigns
share one store (``<out>/store``): a run two settings have in common is computed once.  Per
scale, the table gives mu_i, the contact fraction, the pressure the scale got and its runs' cost
under every setting, and mu_i's deviation from the finest setting computed (``trade_scales.csv``):
the per-scale convergence the shipped defaults are chosen by.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path
from typing import Any

from rubberfriction.driver.multiscale.campaign import run_scene
from rubberfriction.driver.multiscale.report.tables import time_by_scale
from rubberfriction.driver.scenes import Scene, SceneError, load_scene, override

#: name -> (label, overrides of the default scene's sections)
SETTINGS: dict[str, tuple[str, dict[str, dict[str, Any]]]] = {
    "quick": ("quick defaults (shipped scene)", {}),
    "el6": ("6 elements / wavelength", {"numerics": {"elements_per_wavelength": 6}}),
    "el12": ("12 elements / wavelength", {"numerics": {"elements_per_wavelength": 12}}),
    "el24": ("24 elements / wavelength", {"numerics": {"elements_per_wavelength": 24}}),
    "alpha10": ("penalty alpha 10", {"numerics": {"penalty_alpha": 10.0}}),
    "alpha100": ("penalty alpha 100", {"numerics": {"penalty_alpha": 100.0}}),
    "k2": ("2 samples per scale", {"samples": {"pressure": 2, "friction": 2}}),
    "k10": ("10 samples per scale", {"samples": {"pressure": 10, "friction": 10}}),
    "step2": ("sliding step / 2 (step_per_element 0.25)", {"numerics": {"step_per_element": 0.25}}),
    "converged": ("most converged (24 el., alpha 100, 10 samples, tol / 2, step / 2)",
                  {"numerics": {"elements_per_wavelength": 24, "penalty_alpha": 100.0,
                                "step_per_element": 0.25},
                   "samples": {"pressure": 10, "friction": 10}}),
}


def setting_scene(base: Scene, name: str, pressure: float, velocity: float) -> Scene:
    """The default scene at one point with the overrides of setting ``name``."""
    changes = {section: dict(values) for section, values in SETTINGS[name][1].items()}
    if name == "converged":
        changes["numerics"]["convergence_tol"] = 0.5 * base.numerics.convergence_tol
    changes.setdefault("conditions", {}).update(pressures=(pressure,), velocities=(velocity,))
    return override(base, name=f"trade-{name}", **changes)


def run_setting(scene: Scene, out: Path, quiet: bool) -> dict[str, Any] | None:
    """One campaign; its row of the table (None on MPI worker ranks), with ``scales``: per scale
    its mu (eq. 6.13), contact fraction, the pressure it got and the wall time of its runs."""
    t0 = time.perf_counter()
    result = run_scene(scene, output=out, quiet=quiet, report=False)
    if result is None:
        return None
    point = result.points[0]
    outcomes = [o for runs in point.runs.values() for _, o in runs]
    mu = point.mu
    cost = time_by_scale([point])
    scales = {s.name: {"mu": s.mu.mean if s.mu else math.nan,
                       "contact": s.contact.mean if s.contact else math.nan,
                       "pressure": s.pressure, "cost_s": cost.get(s.name, 0.0)}
              for s in point.scales}
    return {"mu": mu.mean if mu else math.nan, "ci95": mu.ci95 if mu else math.nan,
            "samples": mu.n_used if mu else 0, "status": point.status, "runs": len(outcomes),
            "failed": sum(not o.ok for o in outcomes),
            "unconverged": sum(o.ok and o.value("converged") == 0.0 for o in outcomes),
            "cost_s": sum(o.wall_time for o in outcomes),
            "elapsed_s": time.perf_counter() - t0, "scales": scales}


def finest(names: list[str]) -> str | None:
    """The most refined setting among ``names`` that per-scale deviations are measured from."""
    for name in ("converged", "el24", "el12", "step2"):
        if name in names:
            return name
    return None


def scale_table(rows: dict[str, dict[str, Any]]) -> list[str]:
    """Per scale and setting: mu, contact fraction, pressure, cost, and mu's deviation from the
    finest setting present (the per-scale convergence the shipped defaults are chosen by)."""
    ref = finest(list(rows))
    lines = [f"{'scale':<8} {'setting':<10} {'mu_i':>8} {'A/A0':>7} {'p_i MPa':>9} "
             f"{'cost s':>8} {'mu vs ' + (ref or '-'):>14}"]
    names = list(next(iter(rows.values()))["scales"])
    for sc in names:
        r0 = rows[ref]["scales"].get(sc) if ref else None
        for name, r in rows.items():
            v = r["scales"].get(sc)
            if v is None:
                continue
            dev = (f"{100 * (v['mu'] / r0['mu'] - 1):+.1f} %" if r0 and name != ref
                   and r0["mu"] > 0 else "")
            lines.append(f"{sc:<8} {name:<10} {v['mu']:8.4g} {v['contact']:7.3g} "
                         f"{v['pressure']:9.4g} {v['cost_s']:8.0f} {dev:>14}")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench trade", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pressure", type=float, default=0.3, help="nominal pressure, MPa")
    ap.add_argument("--velocity", type=float, default=100.0, help="sliding velocity, mm/s")
    ap.add_argument("--out", default="rf-bench/trade", help="work folder (one shared store)")
    ap.add_argument("--settings", default=",".join(SETTINGS),
                    help=f"comma-separated subset of {', '.join(SETTINGS)}")
    ap.add_argument("--quiet", action="store_true", help="no campaign progress lines")
    ap.add_argument("--scene", default="default",
                    help="shipped scene or file whose surface and numerics are traded "
                         "(default: default; four_scale for the four resolved scales)")
    ap.add_argument("--samples", nargs=2, type=int, metavar=("K", "J"),
                    help="pressure and friction samples per scale of every setting but k2, k10 "
                         "and converged (default: the scene's)")
    args = ap.parse_args(argv)
    names = [s.strip() for s in args.settings.split(",") if s.strip()]
    unknown = [s for s in names if s not in SETTINGS]
    if unknown or not names:
        ap.error(f"--settings: unknown {unknown}; expected some of {', '.join(SETTINGS)}")
    if not (args.pressure > 0 and args.velocity > 0):
        ap.error("--pressure and --velocity: expected values > 0")
    try:
        base = load_scene(args.scene)
    except SceneError as err:
        ap.error(f"--scene: {err}")
    if args.samples:
        if min(args.samples) < 1:
            ap.error(f"--samples {args.samples[0]} {args.samples[1]}: expected counts >= 1")
        base = base.with_samples(*args.samples)
    out = Path(args.out)
    rows = {}
    for name in names:
        row = run_setting(setting_scene(base, name, args.pressure, args.velocity), out,
                          args.quiet)
        if row is None:  # an MPI worker rank: rank 0 prints
            continue
        rows[name] = row
        print(f"[trade] {SETTINGS[name][0]}: mu = {row['mu']:.4g} +- {row['ci95']:.2g}, "
              f"{row['runs']} runs, cost {row['cost_s']:.0f} s", flush=True)
    if not rows:
        return 0
    print(f"\nspeed-accuracy trade, scene {base.name}, p = {args.pressure:g} MPa, "
          f"v = {args.velocity:g} mm/s (cost: sum of the runs' wall times)")
    head = f"{'setting':<58} {'mu':>8} {'95% CI':>8} {'n':>3} {'runs':>5} {'fail':>4} " \
           f"{'unconv':>6} {'cost s':>8}"
    print(head)
    for name, r in rows.items():
        print(f"{SETTINGS[name][0]:<58} {r['mu']:8.4g} {r['ci95']:8.2g} {r['samples']:3d} "
              f"{r['runs']:5d} {r['failed']:4d} {r['unconverged']:6d} {r['cost_s']:8.0f}")
    if "quick" in rows and "converged" in rows:
        q, c = rows["quick"], rows["converged"]
        both = math.hypot(q["ci95"] if math.isfinite(q["ci95"]) else 0.0,
                          c["ci95"] if math.isfinite(c["ci95"]) else 0.0)
        print(f"quick defaults vs most converged: mu {q['mu']:.4g} vs {c['mu']:.4g} "
              f"({100 * (q['mu'] - c['mu']) / c['mu']:+.1f} %; combined 95 % CI +- {both:.2g}; "
              f"{'within' if abs(q['mu'] - c['mu']) <= both else 'outside'} it), cost "
              f"{q['cost_s']:.0f} s vs {c['cost_s']:.0f} s")
    print("\nper scale (thesis eq. 6.13 mu_i with the scales below; cost: its runs' wall time)")
    print("\n".join(scale_table(rows)))
    out.mkdir(parents=True, exist_ok=True)
    with (out / "trade.csv").open("w", newline="") as fh:
        keys = [k for k in next(iter(rows.values())) if k != "scales"]
        w = csv.DictWriter(fh, ["setting", "label", *keys])
        w.writeheader()
        for name, r in rows.items():
            w.writerow({"setting": name, "label": SETTINGS[name][0],
                        **{k: r[k] for k in keys}})
    with (out / "trade_scales.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, ["setting", "scale", "mu", "contact", "pressure", "cost_s"])
        w.writeheader()
        for name, r in rows.items():
            for sc, v in r["scales"].items():
                w.writerow({"setting": name, "scale": sc, **v})
    print(f"tables: {out / 'trade.csv'}, {out / 'trade_scales.csv'}")
    return 0
