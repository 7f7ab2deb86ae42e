"""Benchmark: speed-accuracy of one micro-cell sliding run, and a stability sweep.

1. Speed-accuracy (the curve users choose settings from): the viscoelastic full-contact sinusoid
   (``verify viscoelastic-sinusoid`` defaults, closed form known) against mesh refinement
   (elements per wavelength) and time step (sliding distance per step / contact element size):
   mu error and wall time per run.
2. Stability: velocities 1e-6 .. 10 m/s x pressures 0.01 .. 10 MPa on a rough periodic sample
   (a band of the default road): status, fallback level, cut-backs, Newton iterations, wall
   time, mu.  Nothing may fail silently: a failed run prints its reason.  Each run has a
   wall-time limit (``--wall-limit``); a run that hits it is reported as such, not waited for.

    rubberfriction bench sliding [--part accuracy|stability|both] [--quick] [--wall-limit S]
                                 [--penalty-alpha A] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.surfaces import default_road
from rubberfriction.driver.verification.viscoelastic_sinusoid import simulate
from rubberfriction.forms.material_files import load_compound


def accuracy(quick: bool) -> None:
    comp = load_compound("tread_default")
    print("speed-accuracy: viscoelastic full-contact sinusoid (lambda 1 mm, h0 2 um, p 0.1 MPa, v 10 mm/s)")
    print(f"{'el/lambda':>9} {'step/h':>7} {'mu_force':>11} {'err':>8} {'mu_energy':>11} {'err':>8} {'wall [s]':>9}")
    meshes = (8, 16) if quick else (8, 16, 32)
    steps = (1.0, 0.5) if quick else (1.0, 0.5, 0.25)
    for m in meshes:
        for f in steps:
            t0 = time.perf_counter()
            o = simulate(comp, elements_per_wavelength=m, step_fraction=f)
            wall = time.perf_counter() - t0
            ex = o["mu_exact"]
            print(f"{m:>9} {f:>7.2f} {o['mu_force']:>11.4e} {abs(o['mu_force'] / ex - 1):>8.2%} "
                  f"{o['mu_energy']:>11.4e} {abs(o['mu_energy'] / ex - 1):>8.2%} {wall:>9.2f}", flush=True)
    print(f"closed form mu = {ex:.4e}")


def rough_sample():
    """First sample of the micro1 scale (0.3-0.04 mm band) of the default road, period 0.3 mm."""

    return default_road().extract_samples(1, seed=1)[2][0]


def stability(quick: bool, wall_limit: float, penalty_alpha: float) -> list[dict]:
    comp = load_compound("tread_default")
    sample = rough_sample()
    x, h = np.asarray(sample.x)[:-1], np.asarray(sample.h)[:-1]
    print(f"stability sweep on a rough sample: period {sample.period:.4g} mm, rms height "
          f"{sample.rms_height:.3g} mm, rms slope {sample.rms_slope:.3g}, {x.size} segments; "
          f"penalty alpha {penalty_alpha:g}, wall limit {wall_limit:g} s per run")
    print(f"{'v [m/s]':>8} {'p [MPa]':>8} {'status':>7} {'fallback':>8} {'cutbacks':>8} {'newton':>7} "
          f"{'wall [s]':>9} {'mu':>9}  reason")
    vs = (1e-6, 1e-2, 10.0) if quick else (1e-6, 1e-4, 1e-2, 1.0, 10.0)
    ps = (0.01, 10.0) if quick else (0.01, 0.1, 1.0, 10.0)
    rows = []
    for v in vs:
        for p in ps:
            spec = SlidingSpec(surface_x=x, surface_h=h, period=sample.period, pressure=p, velocity=v * 1e3,
                               compound=comp, elements_per_wavelength=8, slide_distance=sample.period,
                               penalty_alpha=penalty_alpha)
            t0 = time.perf_counter()
            r = run_sliding(spec, wall_limit=wall_limit)
            st, wall = r.stats, time.perf_counter() - t0
            print(f"{v:>8.0e} {p:>8.2g} {r.status:>7} {st.get('fallback_level', -1):>8} "
                  f"{st.get('cutbacks', 0):>8} {st.get('newton_iterations', 0):>7} "
                  f"{wall:>9.2f} {r.mu_force:>9.4f}  {r.reason[:70]}", flush=True)
            rows.append({"velocity_m_s": v, "pressure_MPa": p, "status": r.status,
                         "reason": r.reason, "failure": st.get("failure", ""),
                         "fallback_level": st.get("fallback_level"),
                         "cutbacks": st.get("cutbacks"),
                         "newton_iterations": st.get("newton_iterations"), "wall_time_s": wall,
                         "mu_force": r.mu_force, "mu_energy": r.mu_energy,
                         "contact_fraction": r.contact_fraction})
    ok = sum(r["status"] == "ok" for r in rows)
    print(f"{ok} of {len(rows)} runs converged; "
          f"{sum(r['failure'] == 'wall_limit' for r in rows)} hit the wall-time limit; "
          f"total {sum(r['wall_time_s'] for r in rows):.0f} s")
    return rows


def _number(minimum: float, strict: bool):
    """argparse type: a finite float >= minimum (> minimum if strict), else a clear error."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not np.isfinite(value) or value < minimum or (strict and value == minimum):
            raise argparse.ArgumentTypeError(
                f"expected a finite number {'>' if strict else '>='} {minimum:g}, got {text}")
        return value

    return parse


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench sliding", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--part", choices=["accuracy", "stability", "both"], default="both")
    ap.add_argument("--quick", action="store_true", help="fewer levels (a smoke run)")
    ap.add_argument("--wall-limit", type=_number(0.0, strict=False), default=300.0,
                    help="seconds per stability run before it is stopped and reported "
                         "(300; 0: no limit)")
    ap.add_argument("--penalty-alpha", type=_number(0.0, strict=True), default=100.0,
                    help="contact penalty factor of the stability runs (SlidingSpec.penalty_alpha)")
    ap.add_argument("--json", metavar="FILE", help="write the stability rows as JSON")
    a = ap.parse_args(argv)
    if a.part in ("accuracy", "both"):
        accuracy(a.quick)
    if a.part in ("stability", "both"):
        rows = stability(a.quick, a.wall_limit, a.penalty_alpha)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"stability": rows}, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
