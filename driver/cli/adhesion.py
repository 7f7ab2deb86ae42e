"""``rubberfriction adhesion fit``: identify the bell law from friction measurements (thesis ch. 7).

::

    rubberfriction adhesion fit --dry DRY.csv (--soap SOAP.csv | --hysteresis H.csv)
        (--area AREA.csv | --campaign DIR) --pressure P [--water WATER.csv] --json FILE
        [--plot FILE.png] [--approach original|modified] [--alpha A] [--extrapolate]

Files are speed curves (``driver/adhesion/measurements.py``): a header ``v [m/s], mu`` (or
``mu_H``, ``A_r``; speed units m/s, mm/s, um/s, km/h) and rows of numbers.  Several compounds are
fitted together (shared c and v0, one tau0 each): give one file per compound to every option, in
the same order (``--dry A.csv B.csv --soap As.csv Bs.csv ...``); ``--names`` names them (default:
the campaign's compounds or the dry file names).

* original approach (default with ``--soap``): mu_diff = dry - soap-water (eqs. 7.3, 7.4);
  ``--water`` gives alpha of water (on top of the soap-water curve);
* modified approach (default without ``--soap``): mu_diff = dry - mu_H (thesis 7.5), mu_H from
  ``--hysteresis`` files or the campaign; ``--soap`` and ``--water`` then give alpha of each.

``--campaign DIR`` (a finished ``rubberfriction run`` folder) provides A_r(v) (eq. 7.5) and mu_H(v)
at the pressure ``--pressure``; ``--compound`` picks its compounds.  The JSON holds tau0 (MPa), c,
v0 (mm/s) with standard errors and 95 % intervals, the residual, the approach and alpha.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any


def _same_count(args: argparse.Namespace, n: int) -> None:
    from rubberfriction.driver.adhesion.errors import AdhesionInputError

    for opt in ("soap", "hysteresis", "area", "water", "names", "compound"):
        files = getattr(args, opt)
        if files is not None and len(files) != n:
            raise AdhesionInputError(f"--{opt} = {files!r}: expected {n} entr"
                                     f"{'y' if n == 1 else 'ies'}, one per --dry file, in the "
                                     "same order")


def _inputs(args: argparse.Namespace) -> tuple[list[Any], list[Any], str]:
    """The compounds' curves, the campaign groups used (for the A_r spread) and the approach."""
    from rubberfriction.driver.adhesion.area import campaign_curves, read_campaign
    from rubberfriction.driver.adhesion.errors import AdhesionInputError
    from rubberfriction.driver.adhesion.fit import CompoundInput
    from rubberfriction.driver.adhesion.measurements import read_curve, read_measurement

    n = len(args.dry)
    _same_count(args, n)
    approach = args.approach or ("original" if args.soap else "modified")
    if args.area is None and args.campaign is None:
        raise AdhesionInputError("no contact area: expected --area AREA.csv or --campaign DIR")
    if args.area is not None and args.campaign is not None:
        raise AdhesionInputError("--area and --campaign both given: expected one source of A_r")
    if approach == "original" and not args.soap:
        raise AdhesionInputError("--approach original: expected --soap SOAP.csv (dry minus "
                                 "soap-water, eqs. 7.3, 7.4)")
    if approach == "modified" and args.hysteresis is None and args.campaign is None:
        raise AdhesionInputError("--approach modified: expected --hysteresis H.csv or --campaign "
                                 "DIR for mu_H (dry minus simulated hysteresis, thesis 7.5)")
    groups: list[Any] = []
    if args.campaign is not None:
        compounds = args.compound
        if compounds is None:
            have = [g.compound for g in read_campaign(args.campaign)
                    if math.isclose(g.pressure, args.pressure, rel_tol=1e-9)]
            if len(have) != n:
                raise AdhesionInputError(f"--campaign {args.campaign}: compounds {have} at p = "
                                         f"{args.pressure:g} MPa for {n} --dry file(s): name "
                                         "them with --compound, one per --dry file")
            compounds = have
        groups = [campaign_curves(args.campaign, c, args.pressure) for c in compounds]
    names = args.names or (args.compound if args.compound else None) or (
        [g.compound for g in groups] if groups else [Path(f).stem for f in args.dry])
    out = []
    for k in range(n):
        area = read_curve(args.area[k], "A_r") if args.area else groups[k].area_curve()
        hyst = None
        if args.hysteresis:
            hyst = read_curve(args.hysteresis[k], "mu_H")
        elif groups and approach == "modified":
            hyst = groups[k].hysteresis_curve()
        out.append(CompoundInput(
            names[k], read_measurement(args.dry[k]), area,
            soap=read_measurement(args.soap[k]) if args.soap else None, hysteresis=hyst,
            water=read_measurement(args.water[k]) if args.water else None))
    return out, groups, approach


def _print(fit: Any, seconds: float) -> None:
    b = fit.bell
    print(f"adhesion fit, {b.approach} approach, p = {b.pressure:g} MPa, {b.n_points} points, "
          f"{len(b.compounds)} compound(s), {seconds:.2f} s:")
    for name, t in zip(b.compounds, b.tau0):
        print(f"  tau0[{name}] = {t.value:.5g} MPa  (se {t.se:.2g}, 95 % {t.low:.4g} .. "
              f"{t.high:.4g})")
    print(f"  c = {b.c.value:.5g}  (se {b.c.se:.2g}, 95 % {b.c.low:.4g} .. {b.c.high:.4g})")
    print(f"  v0 = {b.v0.value:.5g} mm/s = {b.v0.value / 1000:.4g} m/s  (se {b.v0.se:.2g} mm/s, "
          f"95 % {b.v0.low:.4g} .. {b.v0.high:.4g} mm/s)")
    print(f"  residual rms {b.residual_rms:.3g}, max {b.residual_max:.3g} (dof {b.dof})")
    for s in fit.shares:
        kind = "given" if s.given else f"fitted, se {s.se:.2g}, 95 % {s.low:.3g} .. {s.high:.3g}"
        print(f"  alpha[{s.condition}] = {s.alpha:.4g} ({kind}); residual rms "
              f"{s.residual_rms:.3g}")
    for note in list(b.notes) + list(fit.notes):
        print(f"  note: {note}")


def _cmd_fit(args: argparse.Namespace) -> int:
    from rubberfriction.driver.adhesion.fit import fit_adhesion
    from rubberfriction.driver.adhesion.plots import plot_fit
    from rubberfriction.validation import InputError

    from rubberfriction import validation as V

    try:
        V.option("--pressure", args.pressure, what="a pressure", above=0.0, unit="MPa")
        V.option("--alpha", args.alpha, what="an adhesion share", minimum=0.0, maximum=1.0)
        t0 = time.perf_counter()
        inputs, groups, approach = _inputs(args)
        fit = fit_adhesion(inputs, args.pressure, approach=approach, alpha=args.alpha,
                           extrapolate=args.extrapolate)
        seconds = time.perf_counter() - t0
    except InputError as err:
        print(f"rubberfriction adhesion fit: error: {err}", file=sys.stderr)
        return 2
    _print(fit, seconds)
    extra: dict[str, Any] = {"wall_time_s": seconds}
    if groups:
        extra["campaign"] = {"folder": groups[0].folder,
                             "skipped_points": [s for g in groups for s in g.skipped]}
    path = Path(args.json)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(fit.to_json(extra))
    print(f"json: {path}")
    if args.plot:
        ci = [g.area_ratio_ci95 for g in groups] if groups else None
        plot_fit(fit, args.plot, area_ci95=ci)
        print(f"plot: {args.plot}")
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``adhesion`` with its subcommand ``fit`` to the ``rubberfriction`` command."""
    p = subparsers.add_parser("adhesion", help="adhesion: fit the bell law to friction "
                              "measurements (thesis ch. 7)", description=__doc__,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="adhesion_command", metavar="SUBCOMMAND")
    p.set_defaults(func=lambda a: (p.print_help(), 2)[1])
    f = sub.add_parser("fit", help="fit tau0, c, v0 (eq. 7.6, 7.7) and alpha (7.8)",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    f.add_argument("--dry", nargs="+", required=True, metavar="DRY.csv",
                   help="dry friction measurement(s) (v, mu), one per compound")
    f.add_argument("--soap", nargs="+", metavar="SOAP.csv", help="soap-water measurement(s)")
    f.add_argument("--water", nargs="+", metavar="WATER.csv", help="water measurement(s)")
    f.add_argument("--hysteresis", nargs="+", metavar="H.csv",
                   help="simulated hysteresis curve(s) (v, mu_H)")
    f.add_argument("--area", nargs="+", metavar="AREA.csv",
                   help="relative real contact area curve(s) (v, A_r)")
    f.add_argument("--campaign", metavar="DIR",
                   help="finished hysteresis campaign folder: A_r(v) and mu_H(v)")
    f.add_argument("--compound", nargs="+", metavar="NAME",
                   help="the campaign's compound(s), one per --dry file")
    f.add_argument("--names", nargs="+", metavar="NAME", help="names of the compounds")
    f.add_argument("--pressure", type=float, required=True, help="nominal pressure p (MPa)")
    f.add_argument("--approach", choices=("original", "modified"),
                   help="original: dry - soap-water (7.3, 7.4); modified: dry - mu_H (7.5) "
                        "(default: original with --soap, else modified)")
    f.add_argument("--alpha", type=float, help="share alpha in [0, 1] (eq. 7.8): given, "
                                               "not fitted")
    f.add_argument("--extrapolate", action="store_true",
                   help="allow speeds outside the range of the A_r / mu_H / soap-water data "
                        "(linear in log v)")
    f.add_argument("--json", required=True, help="write the fitted parameters as JSON")
    f.add_argument("--plot", help="PNG: A_r(v), mu_diff vs mu_A (fig. 7.6, 7.8)")
    f.set_defaults(func=_cmd_fit)
