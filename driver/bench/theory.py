"""Benchmark: wall time of a full 50-speed mu(v) curve from the analytical theories vs the FE.

The cheap end of the speed-accuracy trade (issue 7): every model on the default road (PSD of
the four band profiles, 20 mm to 3 um) with the default compound, 50 log-spaced speeds from
1e-3 to 1e4 mm/s, isothermal and with the flash temperature.  Each theory figure is the best of
``--repeat`` runs; the surface and material set-up (read, FFT, Abel transform) is timed
separately, once.

The FE side (``--fe``, on by default, a few seconds): one FE single-scale sliding run, timed --
the viscoelastic block sliding frictionless over one sinusoid in full contact
(``driver/verification/viscoelastic_sinusoid.py``: 1 mm wavelength, 2 um amplitude, 0.1 MPa,
10 mm/s, ``--fe-mesh`` contact-face elements per wavelength, ``--fe-periods`` wavelengths of
sliding), with its mu against the closed form as a sanity check.  A multiscale point is
``(n - 1) k + n j`` such runs for n scales, k pressure and j friction samples (``--scene``
gives n, k, j; the default scene: 3 x 1 + 4 x 2 = 11), each on a larger cell than this one,
so runs x (one run) is a lower bound, not a measurement.  The measured time of a whole point
comes from ``--fe-seconds`` (e.g. from ``rubberfriction bench multiscale``) or by timing
``--fe-command`` (any shell command computing one FE multiscale point).

    rubberfriction bench theory [--n 50] [--repeat 3] [--no-fe] [--fe-mesh 16] [--fe-repeat 2]
                                [--scene default] [--fe-seconds S | --fe-command "..."]
                                [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import time
from typing import Any, Callable

import numpy as np

from rubberfriction.driver.multiscale.baseline import load_rubber, surface_psd
from rubberfriction.driver.multiscale.campaign import runs_per_point
from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.theory.curves import iso_psd_from_profile_psd
from rubberfriction.driver.theory.kluppel import descriptors_from_psd, kluppel_heinrich_friction
from rubberfriction.driver.theory.persson import persson_friction
from rubberfriction.driver.theory.spectrum import spectrum_from_psd
from rubberfriction.driver.verification.viscoelastic_sinusoid import simulate
from rubberfriction.forms.material_files import load_compound

#: the theory row the FE is compared with
REFERENCE_CASE = "Persson line roughness (1D), isothermal"


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def fe_single_run(temperature: float | None, mesh: int, periods: float,
                  repeat: int) -> dict[str, Any]:
    """Time one FE single-scale sliding run: the viscoelastic sinusoid in full contact.

    Returns the first and the best wall time of ``repeat`` runs (the first may include form
    compilation), the run's size (dofs, sliding steps, Newton iterations) and mu from the FE
    (force, eq. 6.2) against the closed form of ``viscoelastic_sinusoid``.
    """

    comp = load_compound("tread_default")
    times, out = [], None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = simulate(comp, temperature=temperature, elements_per_wavelength=mesh,
                       periods=periods)
        times.append(time.perf_counter() - t0)
    assert out is not None
    res = out["result"]
    return {"status": res.status, "reason": res.reason, "time_first_s": times[0],
            "time_best_s": min(times), "repeat": len(times),
            "elements_per_wavelength": mesh, "periods": periods,
            "dofs": int(res.stats.get("dofs", 0)), "steps": int(res.stats.get("steps", 0)),
            "newton_iterations": int(res.stats.get("newton_iterations", 0)),
            "mu_fe": float(out["mu_force"]), "mu_exact": float(out["mu_exact"])}


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark table; ``--json FILE`` also writes the figures."""

    ap = argparse.ArgumentParser(prog="rubberfriction bench theory",
                                 description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--n", type=int, default=50, help="number of speeds (default 50)")
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats, best is reported")
    ap.add_argument("--surface", default="default", help="profile file or 'default'")
    ap.add_argument("--compound", default="tread_default")
    ap.add_argument("--pressure", type=float, default=0.3, help="MPa")
    ap.add_argument("--temperature", type=float, default=293.15, help="K")
    ap.add_argument("--fe", action=argparse.BooleanOptionalAction, default=True,
                    help="time one FE single-scale sliding run (default on, a few seconds)")
    ap.add_argument("--fe-mesh", type=int, default=16,
                    help="FE run: contact-face elements per wavelength (default 16)")
    ap.add_argument("--fe-periods", type=float, default=3.0,
                    help="FE run: sliding distance in wavelengths (default 3)")
    ap.add_argument("--fe-repeat", type=int, default=2,
                    help="FE run: repeats; first and best are reported (default 2)")
    ap.add_argument("--scene", default="default",
                    help="scene whose scales and samples give the runs per multiscale point")
    ap.add_argument("--fe-seconds", type=float,
                    help="measured wall time of one FE multiscale point (s)")
    ap.add_argument("--fe-command",
                    help="shell command computing one FE multiscale point, timed once")
    ap.add_argument("--json", help="write the figures to this file")
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
        (REFERENCE_CASE,
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
    report: dict[str, Any] = {
        "n_speeds": args.n, "v_min_mm_s": 1e-3, "v_max_mm_s": 1e4, "surface": psd.source,
        "compound": name, "pressure_MPa": p, "T0_K": T0, "repeat": args.repeat,
        "spectrum_nodes_1d": int(spec1.q.size), "spectrum_nodes_2d": int(spec2.q.size),
        "time_setup_s": t_surface, "time_spectra_s": t_spectra, "theory": {},
    }
    print(f"theory benchmark: {args.n} speeds 1e-3..1e4 mm/s, surface {psd.source}, "
          f"compound {name}, "
          f"p = {p:g} MPa, T0 = {T0:g} K; {spec1.q.size} / {spec2.q.size} spectrum nodes (1D / 2D)")
    row = "  {:<60s} {:>9s} {:>13s}  {}"
    print(row.format("what", "wall (s)", "ms per speed", "note"))
    print(row.format("set-up (profile/road, PSD, compound)", f"{t_surface:.3f}", "",
                     "once per surface"))
    print(row.format("spectra (nodes, Abel 2D PSD, KH fit)", f"{t_spectra:.3f}", "",
                     "once per surface"))
    times = {}
    for label, fn in cases:
        t, res = _best(fn, max(1, args.repeat))
        times[label] = t
        iters = int(getattr(res, "iterations", 0) or 0)
        report["theory"][label] = {"time_s": t, "time_per_speed_ms": 1e3 * t / args.n,
                                   "fixed_point_iterations": iters}
        print(row.format(f"{label}: {args.n}-speed curve", f"{t:.4f}",
                         f"{1e3 * t / args.n:.3f}",
                         f"best of {max(1, args.repeat)}"
                         + (f", {iters} fixed-point iterations" if iters else "")))
    t1 = times[REFERENCE_CASE]

    if args.fe:
        fe = fe_single_run(T0, args.fe_mesh, args.fe_periods, args.fe_repeat)
        report["fe_single_run"] = fe
        what = (f"one FE single-scale run: sinusoid, {fe['elements_per_wavelength']} "
                f"el/wavelength, {fe['dofs']} dofs")
        err = abs(fe["mu_fe"] - fe["mu_exact"]) / abs(fe["mu_exact"])
        print(row.format(what, f"{fe['time_best_s']:.2f}", "",
                         f"best of {fe['repeat']} (first {fe['time_first_s']:.2f} s), "
                         f"{fe['steps']} sliding steps, "
                         f"{fe['status']}, mu {fe['mu_fe']:.4g} vs closed form "
                         f"{fe['mu_exact']:.4g} ({100 * err:.1f} %)"))
        try:

            scene = load_scene(args.scene)
            runs, how = runs_per_point(scene)
            bound = runs * fe["time_best_s"]
            report["fe_point_estimate"] = {"scene": scene.name, "runs_per_point": runs,
                                           "how": how, "lower_bound_s": bound}
            print(row.format(f"FE multiscale point, scene {scene.name!r}: >= {runs} x one run",
                             f">= {bound:.1f}", "", f"estimate, not measured: {runs} runs = "
                             f"{how}, on larger cells"))
        except Exception as err_:  # noqa: BLE001 -- the estimate is a by-line of the bench
            print(f"  (runs per multiscale point not estimated: {err_})")
        t_max = max(times.values())
        print(f"  one FE single-scale run costs {fe['time_best_s'] / t1:.3g} x the whole "
              f"{args.n}-speed 1D curve ({fe['time_best_s'] / (t1 / args.n):.3g} x one theory "
              f"speed), {fe['time_best_s'] / t_max:.3g} x the slowest theory curve")

    point = args.fe_seconds
    if args.fe_command:
        t0 = time.perf_counter()
        proc = subprocess.run(shlex.split(args.fe_command), capture_output=True, text=True)
        point = time.perf_counter() - t0
        status = "ok" if proc.returncode == 0 else f"exit code {proc.returncode}"
        report["fe_point"] = {"command": args.fe_command, "status": status, "time_s": point}
        print(row.format("FE multiscale point (timed command)", f"{point:.1f}", "",
                         f"{args.fe_command!r}, {status}"))
    elif point is not None:
        report["fe_point"] = {"command": None, "status": "given", "time_s": point}
        print(row.format("FE multiscale point (given)", f"{point:.1f}", "", "--fe-seconds"))
    if point is not None:
        print(f"  one FE multiscale point costs {point / t1:.3g} x the whole {args.n}-speed 1D "
              f"curve, {point / (t1 / args.n):.3g} x one theory speed")
    elif not args.fe:
        print("  FE: not timed (--fe times one single-scale run; --fe-seconds S or "
              "--fe-command CMD a whole multiscale point)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=2)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
