"""``rubberfriction study trends``: the thesis' trend table, ours next to it.

    mpirun -n 2 rubberfriction study trends --quick --out DIR  # about 8 minutes on 2 cores
    mpirun -n 2 rubberfriction study trends --out rf-results/trends     # the full table
    rubberfriction study trends --out DIR --table-only                  # table from evidence.json
    rubberfriction study trends --check                                 # the cases, no run

Eight rows (thesis 6.4.1, 6.4.2, 6.5.1-6.5.3, 8.5.3): each states the thesis' figure or
sentence, our ratio with its sample spread, whether the sign (and, where the thesis gives one,
the ratio within a factor 1.5) agrees, and where it does not, the evidence.  The cases run on
the four-scale road with a stated cut-off; every case is a scene written to ``<out>/scenes/``
and can be rerun alone with ``rubberfriction run``.  A second call resumes (finished runs are
reused).  Exit status: 0 table written, 2 bad command line.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from mpi4py import MPI  # isort: skip  (MPI before DOLFINx, as `run`)

from rubberfriction import validation as V
from rubberfriction.driver.scenes import SceneError


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("study", help="studies over several campaigns (the thesis' trend table)",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    what = p.add_subparsers(dest="study", metavar="STUDY")
    t = what.add_parser("trends", help="the thesis' trend table reproduced (8 rows)",
                        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    t.add_argument("--quick", action="store_true",
                   help="1 + 2 samples, 20 spread samples, the flash case cut at 0.3 mm with three "
                        "hot-layer temperatures (about 8 minutes on 2 cores, docs/trends.md)")
    t.add_argument("--out", metavar="DIR", default=None,
                   help="output folder (default rf-results/trends or rf-results/trends-quick)")
    t.add_argument("--json", metavar="FILE", help="also write the rows to FILE (JSON)")
    t.add_argument("--cutoff", type=float, metavar="MM",
                   help="the lowest wavelength kept on the four-scale road (default 0.3 mm: "
                        "macro and meso; docs/trends.md)")
    t.add_argument("--samples", nargs=2, type=int, metavar=("K", "J"),
                   help="pressure and friction samples per scale (default 1 3, quick 1 2)")
    t.add_argument("--flash-road", choices=("flat", "macro"), default=None,
                   help="the flash case's thermal macro block on a flat road (default, cheaper) "
                        "or on the road's macro band as in the thesis (8.17 a)")
    t.add_argument("--flash-cutoff", type=float, metavar="MM",
                   help="the flash case's lowest wavelength (default 0.003 mm: the thesis' "
                        "four scales (8.5.3), about 25 minutes on 2 cores; quick: --cutoff)")
    t.add_argument("--flash-mu-const", type=float, metavar="MU", default=None,
                   help="the constant part of mu on the flash case's macro contact: the scales "
                        "below the cut-off and adhesion, which set the frictional heat (default "
                        "0.6, thesis 8.4.3)")
    t.add_argument("--no-flash", dest="flash", action="store_false",
                   help="leave the flash-temperature case out (its row is then 'missing')")
    t.add_argument("--fresh", action="store_true",
                   help="move the cases' stores aside and compute everything again")
    t.add_argument("--table-only", action="store_true",
                   help="rebuild the table from <out>/evidence.json, run nothing")
    t.add_argument("--check", action="store_true", help="print the cases, run nothing")
    t.add_argument("--quiet", action="store_true", help="no progress output")
    t.set_defaults(func=_trends)
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])


def _error(msg: str) -> int:
    if MPI.COMM_WORLD.Get_rank() == 0:
        print(f"rubberfriction: error: {msg}", file=sys.stderr)
    return 2


def _trends(args: argparse.Namespace) -> int:
    from rubberfriction.driver.study.cases import TrendSettings, quick_settings

    settings = quick_settings() if args.quick else TrendSettings()
    try:
        if args.cutoff is not None:
            V.option("--cutoff", args.cutoff, what="a wavelength", minimum=0.003, maximum=3.0,
                     unit="mm", error=SceneError)
            settings = replace(settings, cutoff=args.cutoff)
        if args.flash_cutoff is not None:
            V.option("--flash-cutoff", args.flash_cutoff, what="a wavelength", minimum=0.003,
                     maximum=3.0, unit="mm", error=SceneError)
            settings = replace(settings, flash_cutoff=args.flash_cutoff)
        if args.samples:
            k, j = args.samples
            if k < 1 or j < 1:
                raise SceneError(f"--samples {k} {j}: expected positive sample counts")
            settings = replace(settings, pressure_samples=k, friction_samples=j)
        settings = replace(settings, flash=args.flash)
        if args.flash_road:
            settings = replace(settings, flash_road=args.flash_road)
        if args.flash_mu_const is not None:
            V.option("--flash-mu-const", args.flash_mu_const, what="a friction coefficient",
                     minimum=0.0, maximum=5.0, error=SceneError)
            settings = replace(settings, flash_mu_const=args.flash_mu_const)
        out = Path(args.out or ("rf-results/trends-quick" if args.quick else "rf-results/trends"))
        if args.check:
            return _check(settings, out)
        if args.table_only:
            return _table_only(settings, out, args)
        from rubberfriction.driver.study.run import run_trends

        res = run_trends(settings, out, quiet=args.quiet, fresh=args.fresh)
    except SceneError as err:
        return _error(str(err))
    if res is None:  # a worker rank
        return 0
    return _print(res.files, args, (out / "trends.txt").read_text())


def _check(settings, out: Path) -> int:
    """The cases' scenes validated and listed; for the three cascade campaigns their samples
    are cut and the wall time estimated as ``run --check`` does (one rank per core)."""
    import os

    from rubberfriction.driver.multiscale.campaign import check_scene
    from rubberfriction.driver.multiscale.estimate import estimate_wall_time
    from rubberfriction.driver.runtime.store import Store
    from rubberfriction.driver.study.run import CAMPAIGNS, study_scenes

    if MPI.COMM_WORLD.Get_rank() != 0:
        return 0
    print(f"trend study: {settings.describe()}; output {out}")
    ranks = os.cpu_count() or 1
    for case, scene in study_scenes(settings, out).items():
        print(f"  {case}: {scene.description} -> {out / 'scenes' / (case + '.toml')}")
        if case in CAMPAIGNS:
            folder = scene.output / "store"
            est = estimate_wall_time(scene, check_scene(scene), ranks,
                                     Store(folder) if folder.is_dir() else None)
            print(f"    {est.line()}")
    return 0


def _table_only(settings, out: Path, args: argparse.Namespace) -> int:
    from rubberfriction.driver.study.evidence import Evidence
    from rubberfriction.driver.study.run import write_table

    path = out / "evidence.json"
    if not path.is_file():
        raise SceneError(f"--table-only: {path} not found (run the study first)")
    ev = Evidence.load(path)
    stored = replace(settings, **{k: tuple(v) if isinstance(v, list) else v
                                  for k, v in ev.settings.items()})
    res = write_table(ev, out, stored, float("nan"), {})
    return _print(res.files, args, (out / "trends.txt").read_text())


def _print(files: list[Path], args: argparse.Namespace, text: str) -> int:
    import shutil

    if not args.quiet:
        print(text)
        for f in files:
            print(f"written: {f}")
    if args.json:
        shutil.copyfile(files[0].parent / "trends.json", args.json)
        if not args.quiet:
            print(f"written: {args.json}")
    return 0
