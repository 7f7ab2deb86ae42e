"""``rubberfriction run [SCENE]`` (the main job) and ``rubberfriction samples-study [SCENE]``.

    rubberfriction run                         # the embedded default scene (CAPTIF road, 4 scales)
    rubberfriction run my_scene.toml --out results/ --quiet
    rubberfriction run two_sine                # a shipped scene by name (thesis 6.2.3 case)
    rubberfriction run --schema                # every scene key with its default and meaning
    rubberfriction run --show default          # print a shipped scene to start your own from
    rubberfriction run SCENE --check           # validate and count the runs, compute nothing
    mpirun -n 8 rubberfriction run SCENE       # farm the runs over 8 ranks (same results)
    rubberfriction run SCENE --fields up:meso:0  # + XDMF fields of one run for ParaView
    rubberfriction run SCENE --mesh-check      # + each scale's sample 0 again on a 2x finer mesh
    rubberfriction samples-study --scale micro2 --n 30 --pressure 3 --velocity 10

A campaign resumes by default: runs already in ``<output>/store`` are reused (``--fresh`` moves
the store aside and starts again; ``--retry-failed`` recomputes runs stored as physics failures;
runs that raised or that the wall clock stopped are always computed again).  Exit
status: 0 all points ok, 1 some point failed, 2 bad scene or command line.

Fields (``--fields SELECT``): after the campaign the selected runs are recomputed from their
stored inputs (the same deterministic runs, see ``rubberfriction rerun``) with the field writer,
into ``<output>/fields/<point>_<branch>_<scale>_s<sample>/``: ``fields.xdmf`` + ``fields.h5``
(displacement, hydrostatic pressure, von Mises stress, viscous dissipation; open in ParaView)
and ``contact_pressure.csv``.  Serial, on rank 0 only, after the campaign.  SELECT is a
comma-separated list of items: ``all``; a branch (``down`` pressure, ``up`` friction; separated
scenes: ``macro0``, ``reference``, ``micro``, ``macro``); ``[BRANCH:]SCALE[:SAMPLE]`` with a
scale name of the scene (``run --check`` lists them) and a sample index from 0.  An omitted
branch or sample means all: ``meso`` every run on meso, ``meso:0`` sample 0 on both branches,
``up:micro1:1`` one run.  A run the closed-form shortcut computed gets the FE run instead.
"""

from __future__ import annotations

import argparse
import sys
from importlib import resources

# MPI is initialised here, before anything imports DOLFINx/PETSc (which would initialise it with
# MPI_THREAD_FUNNELED): the farm's dispatcher thread on rank 0 needs MPI_THREAD_MULTIPLE.
from mpi4py import MPI  # isort: skip

from rubberfriction import validation as V
from rubberfriction.driver.scenes import (
    SCENES_PACKAGE,
    Scene,
    SceneError,
    load_scene,
    schema_text,
    shipped_scenes,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run a scene (default: the embedded default scene)",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", nargs="?", default=None,
                   help="scene TOML file or shipped scene name (default: the embedded default "
                        "scene)")
    p.add_argument("--out", metavar="DIR", help="output folder (default: the scene's 'output')")
    p.add_argument("--quiet", action="store_true", help="no progress output (scripts)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--resume", dest="fresh", action="store_false",
                      help="reuse finished runs of the output folder's store (default)")
    mode.add_argument("--fresh", dest="fresh", action="store_true",
                      help="move the existing store aside and compute everything again")
    p.add_argument("--retry-failed", action="store_true",
                   help="recompute runs stored as physics failures (runs that raised or that the "
                        "wall clock stopped are always recomputed)")
    p.add_argument("--samples", nargs=2, type=int, metavar=("K", "J"),
                   help="override samples per scale: K pressure-branch, J friction-branch (eq. "
                        "6.12, 6.13)")
    p.add_argument("--check", action="store_true",
                   help="validate the scene, print the plan, compute nothing")
    p.add_argument("--no-theory", dest="theory", action="store_false",
                   help="leave the analytical mu(v) baselines (Persson 1D/2D) out of the report")
    p.add_argument("--fields", metavar="SELECT",
                   help="after the campaign, rerun the selected runs with XDMF fields for "
                        "ParaView into <output>/fields/ (serial, rank 0): all, BRANCH, or "
                        "[BRANCH:]SCALE[:SAMPLE], comma-separated, e.g. meso, meso:0, "
                        "up:micro1:1 (see above)")
    p.add_argument("--fields-every", type=int, default=1, metavar="N",
                   help="with --fields: the fields of every N-th sliding step (default 1)")
    p.add_argument("--mesh-check", metavar="SELECT", nargs="?", const="",
                   help="after the campaign, run the selected runs again with contact elements "
                        "--mesh-factor times shorter and report how much mu moves (default "
                        "selection: sample 0 of every scale of the friction branch; SELECT as "
                        "for --fields)")
    p.add_argument("--mesh-factor", type=int, default=2, metavar="F",
                   help="with --mesh-check: refinement factor of the contact elements "
                        "(default 2)")
    p.add_argument("--schema", action="store_true",
                   help="print every scene key with default and meaning")
    p.add_argument("--show", metavar="NAME", nargs="?", const="default",
                   help=f"print a shipped scene ({', '.join(shipped_scenes())})")
    p.set_defaults(func=_run, fresh=False)

    s = sub.add_parser("samples-study", help="what n surface samples buy: S(n) of the sample mean "
                       "(thesis fig. 6.13)",
                       description="Runs n frictionless samples of one scale at one (p, v) (thesis "
                                   "6.4.2) and reports the standard deviation S(n) of the n-sample "
                                   "mean over random evaluation orders, with a histogram of mu.  "
                                   "Runs share the scene's store.")
    s.add_argument("scene", nargs="?", default=None,
                   help="scene TOML file or shipped name (default: default)")
    s.add_argument("--scale", default=None, help="scale name or index (default: the finest)")
    s.add_argument("--n", type=int, default=30,
                   help="number of samples (default 30; the thesis used 300)")
    s.add_argument("--pressure", type=float, default=None,
                   help="pressure on that scale, MPa (default: scene's first)")
    s.add_argument("--velocity", type=float, default=None,
                   help="velocity, mm/s (default: scene's first)")
    s.add_argument("--compound", default=None, help="compound (default: the scene's first)")
    s.add_argument("--orders", type=int, default=1000,
                   help="random evaluation orders (default 1000)")
    s.add_argument("--out", metavar="DIR", help="output folder (default: the scene's)")
    s.add_argument("--quiet", action="store_true", help="no progress output")
    s.set_defaults(func=_study)


def _rank() -> int:
    return MPI.COMM_WORLD.Get_rank()


def _error(msg: str) -> int:
    if _rank() == 0:
        print(f"rubberfriction: error: {msg}", file=sys.stderr)
    return 2


def _run(args: argparse.Namespace) -> int:
    if args.schema:
        print(schema_text(), end="")
        return 0
    if args.show is not None:
        if args.show not in shipped_scenes():
            return _error(f"--show {args.show!r}: shipped scenes are {', '.join(shipped_scenes())}")
        print(resources.files(SCENES_PACKAGE).joinpath(f"{args.show}.toml").read_text(), end="")
        return 0
    try:
        scene = load_scene(args.scene)
        if args.samples:
            k, j = args.samples
            if k < 1 or j < 1:
                return _error(f"--samples {k} {j}: expected positive sample counts")
            scene = scene.with_samples(k, j)
        if args.out:
            scene = scene.with_output(args.out)
        fields = _field_selection(scene, args)
        mesh = _mesh_selection(scene, args)
    except SceneError as err:
        return _error(str(err))
    if _rank() == 0:
        for w in scene.warnings:
            print(f"rubberfriction: warning: {w}", file=sys.stderr)
    from rubberfriction.driver.multiscale.campaign import check_summary, run_scene

    if scene.physics.thermal:
        return _run_thermal(scene, args)
    if args.check:
        try:  # every compound and surface file the scene names is read, samples are cut
            summary = check_summary(scene)
        except SceneError as err:
            return _error(str(err))
        if _rank() == 0:
            print(summary)
        return 0

    try:
        result = run_scene(scene, quiet=args.quiet, fresh=args.fresh,
                           retry_failed=args.retry_failed, report=args.theory)
    except SceneError as err:
        return _error(str(err))
    except ImportError as err:
        return _error(str(err))
    if result is not None and not args.theory:
        from rubberfriction.driver.multiscale.report import write_report

        write_report(result, quiet=args.quiet, theory=False)
    if mesh is not None:  # every rank: the refined runs are farmed like the campaign's
        from rubberfriction.driver.multiscale.mesh_check import run_mesh_check

        try:
            run_mesh_check(scene, result, mesh, factor=args.mesh_factor, quiet=args.quiet)
        except SceneError as err:
            return _error(str(err))
    if result is None:  # a worker rank
        return 0
    if fields:
        from rubberfriction.driver.multiscale.fields import write_fields

        write_fields(result, fields, every=args.fields_every,
                     progress=None if args.quiet else print)
    if args.quiet:
        print(result.output / "results.csv")
    failed = [r for r in result.points if not r.ok]
    if failed:  # recorded failures (e.g. a run that did not converge), not input errors
        print(f"rubberfriction: {failed_line(failed, len(result.points))}; see "
              f"{result.output / 'results.csv'}", file=sys.stderr)
    return 0 if not failed else 1


def _field_selection(scene: Scene, args: argparse.Namespace) -> list:
    """The parsed ``--fields`` selection (empty without it); a SceneError naming the option."""
    if args.fields is None:
        return []
    if args.fields_every < 1:
        raise SceneError(f"--fields-every {args.fields_every}: expected a whole number >= 1")
    if scene.physics.thermal:
        raise SceneError("--fields: not for thermal scenes (their runs write "
                         "thermal/<run>/temperature.xdmf themselves)")
    if scene.adhesion_fit is not None:
        raise SceneError("--fields: not for an adhesion fit ([adhesion] fit_from); run its "
                         "campaigns' runs with rubberfriction rerun FOLDER KEY --fields DIR")
    from rubberfriction.driver.multiscale.fields import parse_selection

    return parse_selection(args.fields, scene)


def _mesh_selection(scene: Scene, args: argparse.Namespace) -> list | None:
    """The parsed ``--mesh-check`` selection (None without it); a SceneError naming the
    option."""
    if args.mesh_check is None:
        return None
    from rubberfriction.driver.multiscale.mesh_check import mesh_selection

    return mesh_selection(args.mesh_check, scene, args.mesh_factor)


def failed_line(failed: list, total: int) -> str:
    """``N of M point(s) failed (first: <point>: <first line of its reason>)``: the one line
    that ends a campaign with failed points (their details are in the report and the store)."""
    first = failed[0]
    reason = (first.reason or "no reason recorded").strip().splitlines()
    why = reason[0] if reason else "no reason recorded"
    return f"{len(failed)} of {total} point(s) failed (first: {first.point.id}: {why})"


def _run_thermal(scene: Scene, args: argparse.Namespace) -> int:
    """A thermal scene: with given friction the thermomechanical macro runs (no lower scales);
    in coupled mode the thermal multiscale loop (every rank takes part in the cascades)."""
    from rubberfriction.driver.multiscale.thermal_scene import run_thermal_scene

    t = scene.thermal
    if t.mode in ("coupled", "hot-layer") and not args.check:
        from rubberfriction.driver.multiscale.thermal_loop_scene import run_coupled_scene

        try:
            results = run_coupled_scene(scene, quiet=args.quiet, fresh=args.fresh)
        except SceneError as err:
            return _error(str(err))
        if results is None:  # a worker rank
            return 0
        return 0 if all(r.ok for r in results) else 1
    if args.check:
        if _rank() == 0:
            n = (len(scene.conditions.compounds) * len(scene.conditions.pressures)
                 * len(scene.conditions.velocities))
            mode = {"coupled": "coupled loop "
                               f"({t.divisions if not t.points else len(t.points)} "
                               f"homogenisation points, {t.partitions} partitions)",
                    "hot-layer": f"hot layer ({len(t.hot_layer_rises)} "
                                 "surface temperatures)"}.get(t.mode, "given friction")
            print(f"thermal scene {scene.name!r} from {scene.source}: {n} macro runs, {mode}, "
                  f"block {t.block_length} x {t.block_height} mm, slide {t.slide_distance} mm, "
                  f"kappa {t.kappa}, h_c {t.h_c:g}\n  output: {scene.output}")
        return 0
    try:
        rows = run_thermal_scene(scene, quiet=args.quiet)  # every rank: runs dealt out over ranks
    except SceneError as err:
        return _error(str(err))
    if rows is None:  # a worker rank
        return 0
    return 0 if all(r.ok for r in rows) else 1


def _study(args: argparse.Namespace) -> int:
    try:
        V.option("--n", args.n, what="a number of samples", minimum=2, error=SceneError)
        V.option("--orders", args.orders, what="a number of orders", minimum=1, error=SceneError)
        V.option("--pressure", args.pressure, what="a pressure", above=0.0, maximum=1000.0,
                 unit="MPa", error=SceneError)
        V.option("--velocity", args.velocity, what="a velocity", above=0.0, maximum=1e5,
                 unit="mm/s", error=SceneError)
        scene = load_scene(args.scene)
        if args.out:
            scene = scene.with_output(args.out)
        from rubberfriction.driver.multiscale.campaign import run_sample_study

        res = run_sample_study(scene, scale=args.scale, n=args.n, pressure=args.pressure,
                               velocity=args.velocity,
                               compound=args.compound, orders=args.orders, quiet=args.quiet)
    except (SceneError, ImportError) as err:
        return _error(str(err))
    except ValueError as err:  # e.g. fewer than two successful samples
        return _error(str(err))
    if res is None:
        return 0
    st = res["study"]
    print(f"sample-count study: scale {res['scale']}, p = {res['pressure']:g} MPa, v = "
          f"{res['velocity']:g} mm/s, "
          f"{res['compound']}: {st.values.size} samples used, {st.n_failed} failed")
    print(f"  mean of all samples (reference) mu = {st.mean_ref:.4g}, std of one sample = "
          f"{st.values.std(ddof=1):.3g}")
    for n in sorted({1, 2, 5, 10, 20, st.values.size} & set(st.n.tolist())):
        print(f"  S({n:>3}) = +-{st.S[n - 1]:.3g}   (exact without replacement: "
              f"{st.S_exact[n - 1]:.3g})")
    for f in res["files"]:
        print(f"written: {f}")
    return 0
