"""Benchmark: wall time of a full 50-speed mu(v) curve from the analytical theories.

The cheap end of the speed-accuracy trade (issue 7): every model on the default road (PSD of
the four band profiles, 20 mm to 3 um) with the default compound, 50 log-spaced speeds from
1e-3 to 1e4 mm/s, isothermal and with the flash temperature.  The time of one FE multiscale
point is taken, for the comparison, from ``--fe-seconds`` (a measured figure, e.g. from
``rubberfriction bench multiscale``) or by timing ``--fe-command`` (any shell command that
computes one FE multiscale point).  Each theory figure is the best of ``--repeat`` runs; the
surface and material set-up (read, FFT, Abel transform) is timed separately, once.

    rubberfriction bench theory [--n 50] [--repeat 3] [--fe-seconds S | --fe-command "..."]
"""

from __future__ import annotations

import argparse
import shlex
import subprocess
import time

import numpy as np

from rubberfriction.driver.theory.curves import iso_psd_from_profile_psd
from rubberfriction.driver.theory.kluppel import descriptors_from_psd, kluppel_heinrich_friction
from rubberfriction.driver.theory.persson import persson_friction
from rubberfriction.driver.theory.spectrum import spectrum_from_psd


def _best(fn, repeat: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv: list[str] | None = None) -> int:
    from rubberfriction.driver.cli_theory import load_rubber, surface_psd

    ap = argparse.ArgumentParser(prog="rubberfriction bench theory",
                                 description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--n", type=int, default=50, help="number of speeds (default 50)")
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats, best is reported")
    ap.add_argument("--surface", default="default", help="profile file or 'default'")
    ap.add_argument("--compound", default="tread_default")
    ap.add_argument("--pressure", type=float, default=0.3, help="MPa")
    ap.add_argument("--temperature", type=float, default=293.15, help="K")
    ap.add_argument("--fe-seconds", type=float,
                    help="measured wall time of one FE multiscale point (s)")
    ap.add_argument("--fe-command",
                    help="shell command computing one FE multiscale point, timed once")
    args = ap.parse_args(argv)

    t0 = time.perf_counter()
    psd = surface_psd(args.surface)
    rubber, name = load_rubber(args.compound)
    t_surface = time.perf_counter() - t0
    t0 = time.perf_counter()
    spec1 = spectrum_from_psd(psd.q, psd.C1D, 1, psd.qmin, psd.qmax)
    q2, C2, _ = iso_psd_from_profile_psd(psd.q, psd.C1D)
    spec2 = spectrum_from_psd(q2, C2, 2, max(psd.qmin, q2[0]), min(psd.qmax, q2[-1]))
    desc = descriptors_from_psd(psd.q, psd.C1D, psd.qmin, psd.qmax)
    t_spectra = time.perf_counter() - t0
    v = np.geomspace(1e-3, 1e4, args.n)
    p, T0 = args.pressure, args.temperature
    cases = [
        ("Persson line roughness (1D), isothermal",
         lambda: persson_friction(spec1, rubber, p, v, T0=T0)),
        ("Persson isotropic (2D), isothermal",
         lambda: persson_friction(spec2, rubber, p, v, T0=T0)),
        ("Kluppel-Heinrich, isothermal",
         lambda: kluppel_heinrich_friction(desc, 2 * np.pi / psd.qmax, rubber, p, v, T0=T0)),
        ("Persson 1D + flash temperature",
         lambda: persson_friction(spec1, rubber, p, v, T0=T0, flash=True)),
        ("Persson 2D + flash temperature",
         lambda: persson_friction(spec2, rubber, p, v, T0=T0, flash=True)),
    ]
    print(f"theory benchmark: {args.n} speeds 1e-3..1e4 mm/s, surface {psd.source}, "
          f"compound {name}, "
          f"p = {p:g} MPa, T0 = {T0:g} K; {spec1.q.size} / {spec2.q.size} spectrum nodes (1D / 2D)")
    print(f"  set-up (profile/road, PSD, compound): {t_surface:8.3f} s (once per surface)")
    print(f"  spectra (nodes, Abel 2D PSD, KH fit): {t_spectra:8.3f} s (once per surface)")
    times = {}
    for label, fn in cases:
        t, res = _best(fn, max(1, args.repeat))
        times[label] = t
        extra = ""
        if getattr(res, "iterations", 0):
            extra = f"  ({res.iterations} fixed-point iterations)"
        print(f"  {label:<42s} {t:8.4f} s  = {1e3 * t / args.n:7.3f} ms per speed{extra}")
    fe = args.fe_seconds
    if args.fe_command:
        t0 = time.perf_counter()
        proc = subprocess.run(shlex.split(args.fe_command), capture_output=True, text=True)
        fe = time.perf_counter() - t0
        status = "ok" if proc.returncode == 0 else f"exit code {proc.returncode}"
        print(f"  FE multiscale point ({args.fe_command!r}, {status}): {fe:.1f} s")
    elif fe is not None:
        print(f"  FE multiscale point (given): {fe:.1f} s")
    if fe is not None:
        t1 = times["Persson line roughness (1D), isothermal"]
        print(f"  one FE point costs {fe / t1:.3g} x the whole 50-speed 1D curve, "
              f"{fe / (t1 / args.n):.3g} x one theory speed")
    else:
        print("  FE multiscale point: not timed (pass --fe-seconds S or --fe-command CMD)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
