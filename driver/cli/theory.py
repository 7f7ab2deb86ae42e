"""``rubberfriction theory [SCENE]``: mu(v) and A/A0(v) from the analytical theories.

Persson (line roughness = plane strain, and isotropic eq. 2.10), Klüppel-Heinrich (eq. 2.9) and,
with a bell law, the adhesion term (eqs. 2.11, 7.6, 7.7), all fed with the same surface PSD and
compound as the FE (:mod:`rubberfriction.driver.multiscale.baseline`).  Examples::

    rubberfriction theory --surface default --compound tread_default --pressure 0.3 \\
        --vmin 1e-3 --vmax 1e4 --n 50 --temperature 293.15 --plot mu.png --csv mu.csv
    rubberfriction theory scene.toml --flash --json

Units: speeds mm/s, pressure MPa, temperature K, wavelengths mm.

Scene file: a scene as ``rubberfriction run`` reads it (same reader, same validation; see
``rubberfriction run --schema``).  The theories take its surface (``[surface]`` source, files,
edges: the analysis range is edges[0] .. edges[-1]; sines give a line spectrum), the first
compound and pressure of ``[conditions]``, its velocities and T0, and the ``[adhesion]`` bell law
when ``[physics] adhesion = true``.  Command-line options override the scene; ``--surface``
replaces its surface by a profile file or ``default`` (the default road).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction import validation as V
from rubberfriction.driver.multiscale.baseline import (
    DEFAULT_N,
    DEFAULT_PRESSURE,
    DEFAULT_VRANGE,
    TheoryRequest,
    TheoryResult,
    evaluate,
    request_from_scene,
)
from rubberfriction.driver.scenes import SceneError, load_scene
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.theory.curves import MODELS, plot_curves
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.forms.material_files import DEFAULT_COMPOUND


def _velocities(args: argparse.Namespace) -> tuple[float, ...] | None:
    """Speeds given on the command line (a list, or a log range), None if none were given."""
    if args.velocities:
        return tuple(args.velocities)
    if args.vmin is None and args.vmax is None and args.n is None:
        return None
    lo = args.vmin if args.vmin is not None else DEFAULT_VRANGE[0]
    hi = args.vmax if args.vmax is not None else DEFAULT_VRANGE[1]
    n = args.n if args.n is not None else DEFAULT_N
    if not (lo > 0 and hi > lo and n >= 1):
        raise TheoryInputError(f"speed range --vmin {lo} --vmax {hi} --n {n}: expected 0 < "
                               "vmin < vmax, n >= 1")
    return tuple(np.geomspace(lo, hi, int(n)))


def _adhesion(args: argparse.Namespace, law: BellLaw | None) -> BellLaw | None:
    """The scene's bell law with --adhesion TAU0 C V0 and --alpha applied."""
    if args.adhesion is not None:
        tau0, c, v0 = args.adhesion
        law = BellLaw(tau0, c, v0, law.alpha if law is not None else 1.0)
    if args.alpha is not None:
        if law is None:
            raise TheoryInputError("--alpha needs a bell law: --adhesion TAU0 C V0 or a scene "
                                   "with [physics] adhesion = true")
        law = BellLaw(law.tau0, law.c, law.v0, args.alpha)
    return law


def check_options(args: argparse.Namespace) -> None:
    """Raise a :class:`TheoryInputError` naming the first impossible option as typed
    (``--pressure -1: expected a pressure > 0 in MPa``)."""
    e = {"error": TheoryInputError}
    V.option("--pressure", args.pressure, what="a pressure", above=0.0, unit="MPa", **e)
    V.option("--velocities", args.velocities, what="sliding speeds", above=0.0, unit="mm/s", **e)
    V.option("--vmin", args.vmin, what="a speed", above=0.0, unit="mm/s", **e)
    V.option("--vmax", args.vmax, what="a speed", above=0.0, unit="mm/s", **e)
    V.option("--n", args.n, what="a number of speeds", minimum=1, **e)
    V.option("--temperature", args.temperature, what="a temperature", above=0.0, unit="K", **e)
    V.option("--lambda-max", args.lambda_max, what="a wavelength", above=0.0, unit="mm", **e)
    V.option("--lambda-min", args.lambda_min, what="a wavelength", above=0.0, unit="mm", **e)
    V.option("--gamma", args.gamma, what="a factor", minimum=0.0, maximum=1.0, **e)
    V.option("--nu", args.nu, what="a Poisson ratio", above=-1.0, maximum=0.5, **e)
    V.option("--alpha", args.alpha, what="an adhesion share", minimum=0.0, maximum=1.0, **e)
    V.option("--adhesion", args.adhesion, what="TAU0 (MPa), C, V0 (mm/s)", above=0.0, **e)
    if args.lambda_max is not None and args.lambda_min is not None \
            and not args.lambda_min < args.lambda_max:
        raise TheoryInputError(f"--lambda-max {args.lambda_max:g} --lambda-min "
                               f"{args.lambda_min:g}: expected lambda-min < lambda-max")


def request_from_args(args: argparse.Namespace) -> TheoryRequest:
    """The request of the command line: the scene (if given) with the options applied."""
    check_options(args)
    overrides: dict[str, Any] = {
        "compound": args.compound, "pressure": args.pressure, "velocities": _velocities(args),
        "T0": args.temperature, "lambda_max": args.lambda_max, "lambda_min": args.lambda_min,
        "models": tuple(args.models), "gamma": args.gamma, "nu": args.nu, "flash": args.flash}
    if args.scene:
        req = request_from_scene(load_scene(args.scene), **overrides)
    else:
        req = TheoryRequest(**{k: v for k, v in overrides.items() if v is not None})
    if args.surface:  # a profile file or the default road instead of the scene's surface
        road = args.surface in ("default", "default_road", "four_scale")
        edges = req.edges if road else None
        # the scene's analysis range belongs to its surface: a profile file gets its own
        # (or the one given with --lambda-max/--lambda-min)
        lam = {} if road else {"lambda_max": args.lambda_max, "lambda_min": args.lambda_min}
        req = replace(req, surface=args.surface, files=(), sines=(), edges=edges, **lam)
    return replace(req, adhesion=_adhesion(args, req.adhesion))


def _print_table(result: TheoryResult) -> None:
    curves = result.curves
    cond, surf, comp = (result.info[k] for k in ("conditions", "surface", "compound"))
    T = "reference" if cond["T0_K"] is None else f"{cond['T0_K']:g} K"
    print(f"analytical friction theories: p = {cond['pressure_MPa']:g} MPa, T0 = {T}, "
          f"compound {comp['name']} (nu = {comp['nu']:.4g}), flash temperature "
          f"{'on' if cond['flash_temperature'] else 'off'}")
    print(f"surface: {surf['source']}, wavelengths {surf['lambda_max_mm']:.4g} .. "
          f"{surf['lambda_min_mm']:.4g} mm")
    for note in result.info["notes"]:
        print(f"note: {note}")
    for c in curves:
        info = ", ".join(f"{k} = {v:.4g}" for k, v in c.extra.items() if isinstance(v, float))
        print(f"  {c.model}: {c.label}" + (f" ({info})" if info else ""))
        for note in c.notes:
            print(f"    note: {note}")
        for flag in c.flags:  # driver/theory/validity.py; docs/theory-baselines.md
            print(f"    outside validity: {flag.message}")
    head = ["v (mm/s)"]
    for c in curves:
        head.append(f"mu {c.model}")
        if c.area is not None:
            head.append("A/A0")
        if c.flash_dT is not None:
            head.append("dT (K)")
    print("  ".join(f"{h:>18}" for h in head))
    for i, vi in enumerate(curves[0].v):
        row = [f"{vi:18.5g}"]
        for c in curves:
            row.append(f"{c.mu[i]:18.5g}")
            if c.area is not None:
                row.append(f"{c.area[i]:18.5g}")
            if c.flash_dT is not None:
                row.append(f"{c.flash_dT[i]:18.4g}")
        print("  ".join(row))


def _write_csv(result: TheoryResult, path: Path) -> None:
    curves = result.curves
    cols = {"v_mm_s": curves[0].v}
    for c in curves:
        cols[f"{c.model}_mu"] = c.mu
        cols[f"{c.model}_mu_hysteresis"] = c.mu_hysteresis
        if c.mu_adhesion is not None:
            cols[f"{c.model}_mu_adhesion"] = c.mu_adhesion
        if c.area is not None:
            cols[f"{c.model}_area_ratio"] = c.area
        if c.flash_dT is not None:
            cols[f"{c.model}_flash_dT_K"] = c.flash_dT
    data = np.column_stack(list(cols.values()))
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="", fmt="%.10g")


def _run(args: argparse.Namespace) -> int:
    try:
        result = evaluate(request_from_args(args))
        if args.csv:
            _write_csv(result, Path(args.csv))
        if args.plot:
            cond, info = result.info["conditions"], result.info
            plot_curves(result.curves, args.plot,
                        title=f"{info['surface']['source']} | {info['compound']['name']} | "
                              f"p = {cond['pressure_MPa']:g} MPa"
                              + ("" if cond["T0_K"] is None else f" | T0 = {cond['T0_K']:g} K"))
    except (SceneError, TheoryInputError, ValueError, OSError) as err:
        print(f"rubberfriction theory: error: {err}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(result.to_dict(), indent=1))
    else:
        _print_table(result)
        for what, path in (("csv", args.csv), ("plot", args.plot)):
            if path:
                print(f"{what}: {path}")
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``theory`` to the ``rubberfriction`` command."""
    doc = __doc__ or ""
    p = subparsers.add_parser(
        "theory", help="mu(v) and contact area from the Persson / Klüppel-Heinrich theories",
        description=doc.split("\n\n")[0] + " Speeds mm/s, pressure MPa, temperature K.",
        epilog=doc[doc.find("Scene file:"):],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", nargs="?", help="scene TOML or shipped scene name (as for run)")
    p.add_argument("--surface", help="profile file, 'default' (embedded default road) or "
                                     "'four_scale' (the four-scale road)")
    p.add_argument("--compound", help=f"compound name or TOML file (default {DEFAULT_COMPOUND})")
    p.add_argument("--pressure", type=float,
                   help=f"nominal pressure, MPa (default {DEFAULT_PRESSURE:g})")
    p.add_argument("--velocities", type=float, nargs="+", metavar="V", help="sliding speeds, mm/s")
    p.add_argument("--vmin", type=float,
                   help=f"log-spaced speeds from (mm/s, default {DEFAULT_VRANGE[0]:g})")
    p.add_argument("--vmax", type=float, help=f"... to (mm/s, default {DEFAULT_VRANGE[1]:g})")
    p.add_argument("--n", type=int, help=f"... number of speeds (default {DEFAULT_N})")
    p.add_argument("--temperature", type=float,
                   help="background temperature T0, K (default: WLF reference)")
    p.add_argument("--models", nargs="+", choices=MODELS, default=list(MODELS),
                   help="models to evaluate")
    p.add_argument("--lambda-max", type=float, help="longest wavelength included, mm")
    p.add_argument("--lambda-min", type=float,
                   help="shortest wavelength included (q1 = 2 pi/lambda_min), mm")
    p.add_argument("--gamma", type=float,
                   help="S(q) = gamma + (1-gamma) P^2 (default 0.5)")
    p.add_argument("--nu", type=float,
                   help="Poisson ratio (default: the compound's long-term value)")
    p.add_argument("--flash", action="store_true", help="flash temperature (Persson 2006)")
    p.add_argument("--adhesion", type=float, nargs=3, metavar=("TAU0", "C", "V0"),
                   help="bell law eq. (7.6): tau0 MPa, c, v0 mm/s")
    p.add_argument("--alpha", type=float, help="adhesion share alpha of eq. (7.3) (default 1)")
    p.add_argument("--plot", help="write mu(v) and A/A0(v) to this PNG")
    p.add_argument("--csv", help="write the curves to this CSV")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=_run)
