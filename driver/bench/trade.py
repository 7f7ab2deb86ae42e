"""Benchmark: the speed-accuracy trade of the whole method at one mu point of the default road.

    rubberfriction bench trade [--pressure 0.3] [--velocity 100] [--out DIR]
                               [--settings quick,el6,el12,el24,alpha10,alpha100,k2,k10,step2,
                                           converged]
    mpirun -n 2 rubberfriction bench trade ...      # the campaigns farm their runs over the ranks

One (p, v) point of the default scene (four scales of the CAPTIF road) is computed with each
setting: the quick defaults of the shipped scene, then one setting changed at a time (contact
elements per shortest wavelength 6 / 12 / 24, normal penalty factor alpha 10 / 100, samples per
scale k = j = 2 / 10, the sliding step halved), and the most converged setting (24 elements per
wavelength, alpha 100, ten samples, half the convergence tolerance, half the step).  Printed per
setting: mu with its 95 % confidence interval over the samples, the runs it needs (failed,
unconverged), and their cost: the sum of the runs' wall times (each run's own time, also when
this bench found it in the store, so every row is the cost of computing that setting from
scratch).  Last, how far the quick defaults are from the most converged setting.  All campaigns
share one store (``<out>/store``): a run two settings have in common is computed once.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path
from typing import Any

from rubberfriction.driver.multiscale.campaign import run_scene
from rubberfriction.driver.multiscale.scene import Scene, load_scene, override

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
    """One campaign; its row of the table (None on MPI worker ranks)."""
    t0 = time.perf_counter()
    result = run_scene(scene, output=out, quiet=quiet, report=False)
    if result is None:
        return None
    point = result.points[0]
    outcomes = [o for runs in point.runs.values() for _, o in runs]
    mu = point.mu
    return {"mu": mu.mean if mu else math.nan, "ci95": mu.ci95 if mu else math.nan,
            "samples": mu.n_used if mu else 0, "status": point.status, "runs": len(outcomes),
            "failed": sum(not o.ok for o in outcomes),
            "unconverged": sum(o.ok and o.value("converged") == 0.0 for o in outcomes),
            "cost_s": sum(o.wall_time for o in outcomes),
            "elapsed_s": time.perf_counter() - t0}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench trade", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pressure", type=float, default=0.3, help="nominal pressure, MPa")
    ap.add_argument("--velocity", type=float, default=100.0, help="sliding velocity, mm/s")
    ap.add_argument("--out", default="rf-bench/trade", help="work folder (one shared store)")
    ap.add_argument("--settings", default=",".join(SETTINGS),
                    help=f"comma-separated subset of {', '.join(SETTINGS)}")
    ap.add_argument("--quiet", action="store_true", help="no campaign progress lines")
    args = ap.parse_args(argv)
    names = [s.strip() for s in args.settings.split(",") if s.strip()]
    unknown = [s for s in names if s not in SETTINGS]
    if unknown or not names:
        ap.error(f"--settings: unknown {unknown}; expected some of {', '.join(SETTINGS)}")
    if not (args.pressure > 0 and args.velocity > 0):
        ap.error("--pressure and --velocity: expected values > 0")
    base = load_scene("default")
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
    print(f"\nspeed-accuracy trade, default road, p = {args.pressure:g} MPa, "
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
    out.mkdir(parents=True, exist_ok=True)
    with (out / "trade.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, ["setting", "label", *next(iter(rows.values())).keys()])
        w.writeheader()
        for name, r in rows.items():
            w.writerow({"setting": name, "label": SETTINGS[name][0], **r})
    print(f"table: {out / 'trade.csv'}")
    return 0
