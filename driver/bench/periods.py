"""Benchmark: periods to the periodic steady state with and without the creep extrapolation.

The first micro2 sample of the four-scale road, built as the scene ``four_scale`` builds its
friction runs (``SpecBuilder``: band-limited master, element size, converged window, steady-state
jump), at ``--pressure`` (7.21 MPa: what that scene's pressure branch hands micro2 at 0.3 MPa)
and ``--velocity``, with ``--coarsen`` times longer contact elements and sliding steps.  It
slides with the extrapolation along the slow modes (``driver.sliding.slowmode``) and without it,
side by side, and (``--reference N``) N periods without either the extrapolation or the window
rule, whose last period means are the steady state both are compared with.  Prints per run:
status, periods, Newton iterations, wall time, mu_force, extrapolations, and the period means.

    rubberfriction bench periods [--pressure 7.21] [--velocity 100] [--coarsen 1]
                                 [--reference 40] [--factor-reuse K] [--json FILE]

What it measured is in ``docs/performance.md`` ("The periodic steady state").
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time

from rubberfriction.driver.bench.sliding import lowest_scale_spec
from rubberfriction.driver.fe.newton import FACTOR_REUSE
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.spec import SlidingSpec, default_h_contact
from rubberfriction.driver.sliding.window import period_means


#: contact elements per shortest wavelength the bench's micro2 cell is measured at (the scene
#: ``four_scale`` ran micro2 at 6 before 0.22.0; the measurements in docs/performance.md and
#: tests/test_slow_mode.py are on that cell)
BENCH_ELEMENTS_PER_WAVELENGTH = 6


def micro2_spec(pressure: float, velocity: float, coarsen: float = 1.0) -> SlidingSpec:
    """The first micro2 sample of the scene ``four_scale`` as its campaign builds a friction run
    (frictionless: the lowest scale), with contact elements and steps ``coarsen`` times those of
    BENCH_ELEMENTS_PER_WAVELENGTH per shortest wavelength (the scene's element size scales
    with 1 / elements_per_wavelength, ``specs.SpecBuilder``)."""
    spec = lowest_scale_spec(pressure, velocity, None, scene_name="four_scale")
    hc = spec.h_contact or default_h_contact(spec)
    step = spec.step_length or 0.5 * hc
    f = coarsen * spec.elements_per_wavelength / BENCH_ELEMENTS_PER_WAVELENGTH
    return dataclasses.replace(spec, h_contact=f * hc, step_length=f * step,
                               elements_per_wavelength=BENCH_ELEMENTS_PER_WAVELENGTH)


def compare(spec: SlidingSpec, reference_periods: int = 0,
            factor_reuse: int = FACTOR_REUSE) -> dict:
    """The spec with and without the extrapolation (and the reference run): one row each;
    ``factor_reuse`` of their Newton solves (``driver.fe.newton``)."""
    rows = {}
    runs = {"extrapolated": dataclasses.replace(spec, period_extrapolation=True),
            "not extrapolated": dataclasses.replace(spec, period_extrapolation=False)}
    if reference_periods > 0:
        runs["reference"] = dataclasses.replace(spec, period_extrapolation=False,
                                                converge_tol=0.0,
                                                slide_distance=reference_periods * spec.period)
    for name, s in runs.items():
        t0 = time.perf_counter()
        r = run_sliding(s, factor_reuse=factor_reuse)
        st = r.stats
        rows[name] = {"status": r.status, "reason": r.reason, "mu_force": r.mu_force,
                      "contact_fraction": r.contact_fraction, "periods": st.get("periods"),
                      "newton_iterations": st.get("newton_iterations"),
                      "wall_s": time.perf_counter() - t0,
                      "extrapolated_creep": st.get("extrapolated_creep", 0.0),
                      "extrapolation_factor": st.get("extrapolation_factor", 0.0),
                      "period_mu": (list(period_means(r.series["s"], r.series["mu_force"],
                                                      s.period)) if r.series else [])}
        if name == "reference" and rows[name]["period_mu"]:
            rows[name]["mu_force"] = rows[name]["period_mu"][-1]  # the steady state
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench periods", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pressure", type=float, default=7.21, help="MPa (7.21)")
    ap.add_argument("--velocity", type=float, default=100.0, help="mm/s (100)")
    ap.add_argument("--coarsen", type=float, default=1.0,
                    help="contact elements and steps this many times longer (1)")
    ap.add_argument("--reference", type=int, default=0, metavar="N",
                    help="also N periods without extrapolation or window rule (0: none)")
    ap.add_argument("--factor-reuse", type=int, default=FACTOR_REUSE, metavar="K",
                    help=f"GMRES iterations on a reused factorisation ({FACTOR_REUSE}; 0: a "
                         f"factorisation at every Newton iteration, as the measurements in "
                         f"docs/performance.md before 0.23.0)")
    ap.add_argument("--json", metavar="FILE", help="write the rows as JSON")
    a = ap.parse_args(argv)
    if not (a.pressure > 0 and a.velocity > 0 and a.coarsen > 0 and a.reference >= 0
            and a.factor_reuse >= 0):
        ap.error("--pressure, --velocity and --coarsen must be > 0, --reference and "
                 "--factor-reuse >= 0")
    spec = micro2_spec(a.pressure, a.velocity, a.coarsen)
    print(f"micro2 cell of the four-scale road: period {spec.period:g} mm, p {a.pressure:g} MPa, "
          f"v {a.velocity:g} mm/s, contact elements {spec.h_contact:.3g} mm, window tolerance "
          f"{spec.converge_tol:g}", flush=True)
    rows = compare(spec, a.reference, a.factor_reuse)
    ref = rows.get("reference", {}).get("mu_force")
    print(f"{'run':>17} {'status':>7} {'periods':>7} {'newton':>7} {'wall [s]':>9} "
          f"{'mu':>8} {'vs ref':>7} {'extrap.':>7}")
    for name, r in rows.items():
        dev = f"{r['mu_force'] / ref - 1:+.1%}" if ref else ""
        n_ex = int(r["extrapolated_creep"] or 0)
        print(f"{name:>17} {r['status']:>7} {r['periods'] or 0:>7.0f} "
              f"{r['newton_iterations'] or 0:>7.0f} {r['wall_s']:>9.1f} {r['mu_force']:>8.4f} "
              f"{dev:>7} {n_ex:>7}")
        print("   period means: " + " ".join(f"{m:.4f}" for m in r["period_mu"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
