"""From a scene to results: scales and samples, run specs, planners, farm, store, report.

The glue between the modules with one job each: :mod:`.scene` (what to compute) ->
:mod:`.scales` (surface scales and periodic samples) -> :mod:`.specs` (one
:class:`~rubberfriction.driver.sliding.spec.SlidingSpec` per run from the scene's numerical
settings) -> the planners of :mod:`.cascade` and :mod:`.separated` ->
:mod:`~rubberfriction.driver.runtime.farm` (serial or MPI) with the
:mod:`~rubberfriction.driver.runtime.store` -> :mod:`.report`.  :func:`run_scene` is what
``rubberfriction run`` calls.
"""

from __future__ import annotations

import datetime as _dt
import math
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

# MPI is initialised here, before anything imports DOLFINx/PETSc (which would initialise it with
# MPI_THREAD_FUNNELED): the farm's dispatcher thread on rank 0 needs MPI_THREAD_MULTIPLE.
from mpi4py import MPI  # isort: skip

import numpy as np

from rubberfriction.driver.adhesion.fit import AdhesionFit, CompoundInput, fit_adhesion
from rubberfriction.driver.adhesion.measurements import SpeedCurve, read_measurement
from rubberfriction.driver.multiscale.adhesion_report import write_adhesion_report
from rubberfriction.driver.multiscale.cascade import CampaignPlanner, RoughCascade
from rubberfriction.driver.multiscale.report import write_report
from rubberfriction.driver.multiscale.report.plots import plot_sample_study
from rubberfriction.driver.multiscale.report.tables import study_rows, write_csv
from rubberfriction.driver.multiscale.results import Point, PointResult
from rubberfriction.driver.multiscale.scales import Scales, build_scales, surface_lines
from rubberfriction.driver.scenes import Scene, SceneError, surface_scale_names
from rubberfriction.driver.multiscale.separated import SeparatedTwoScale
from rubberfriction.driver.multiscale.estimate import estimate_wall_time
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds, points
from rubberfriction.driver.multiscale.statistics import (
    sample_count_study,
    usable,
    why_unusable,
)
from rubberfriction.driver.runtime.farm import (
    Executor,
    RunReports,
    StaticPlanner,
    Task,
    hard_timeout,
    run_farm,
)
from rubberfriction.driver.runtime.progress import Progress
from rubberfriction.driver.runtime.store import Outcome, Store, code_version, git_describe, run_key
from rubberfriction.driver.sliding.run import sliding_runner
from rubberfriction.driver.surfaces.multiscale import scale_names
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.validation import InputError


def runs_per_point(scene: Scene) -> tuple[int, str]:
    """Single-scale runs one (compound, p, v) point of the scene needs, and how they add up."""
    n = scene.n_scales
    if scene.variant == "rough":
        k, j = scene.samples.pressure, scene.samples.friction
        down = (n - 1) if n > 1 else (1 if scene.physics.adhesion else 0)
        per = down * k + n * j
        how = f"{down} scale(s) x k={k} pressure samples + {n} scale(s) x j={j} friction samples"
    else:
        sep = scene.separated
        npg = len(sep.pressures) or len(sep.pressure_factors)
        nvg = len(sep.velocities) or len(sep.velocity_factors)
        per = 2 + npg * nvg + (1 if sep.reference else 0)
        how = f"frictionless macro + {npg}x{nvg} micro grid + macro with the law"
        if sep.reference:
            how += " + reference"
    return per, how


def check_scene(scene: Scene) -> Scales:
    """What ``run --check`` does besides validating the TOML: load every compound the scene names
    and build its scales and samples (reads the surface files), so that bad material data or a
    surface that cannot give the samples fails before a campaign starts (SceneError naming the
    field).  Returns the scales."""
    load_compounds(scene)
    return build_scales(scene, max(scene.samples.pressure, scene.samples.friction))


def plan_text(scene: Scene) -> str:
    """The plan of a scene as ``run --check`` prints it: variant, scales (with their
    ``[numerics.<scale>]`` changes), points x runs per point = single-scale runs, output."""
    n = scene.n_scales
    pts = points(scene)
    per, how = runs_per_point(scene)
    extra = ""
    if scene.adhesion_fit is not None:
        j = scene.samples.friction
        extra = (f"  [adhesion] fit_from: then {len(pts)} x j={j} = {len(pts) * j} macro friction "
                 "runs per alpha (alpha = 1 and each fitted alpha in (0, 1); lower scales "
                 "reused)\n")
    per_scale = dict(scene.numerics.scales)
    scales = ", ".join(nm + (" (" + ", ".join(f"{k} = {v!r}" for k, v in per_scale[nm]) + ")"
                             if nm in per_scale else "")
                       for nm in surface_scale_names(scene.surface))
    return (f"scene {scene.name!r} ({scene.variant}, {n} scales) from {scene.source}\n"
            f"  scales: {scales}\n"
            f"  {len(pts)} point(s) x {per} runs ({how}) = {len(pts) * per} single-scale runs\n"
            + extra + f"  output: {scene.output}")


def check_summary(scene: Scene) -> str:
    """What ``run --check`` prints for a (non-thermal) scene: :func:`check_scene` (reads every
    compound and surface file, cuts the samples; a SceneError names a bad one), then the plan
    (:func:`plan_text`), the resolution lines of the samples (``scales.surface_lines``) and, for
    a rough-surface scene, the estimated wall time on 1 rank and on one rank per core
    (:mod:`.estimate`, from stored runs of the scene's output folder where there are any)."""
    scales = check_scene(scene)
    lines = [plan_text(scene), *surface_lines(scene, scales)]
    if scene.variant == "rough":
        folder = scene.output / "store"
        store = Store(folder) if folder.is_dir() else None
        ranks = sorted({1, os.cpu_count() or 1})
        lines += ["  " + estimate_wall_time(scene, scales, r, store).line() for r in ranks]
    return "\n".join(lines)


def make_planner(scene: Scene, scales: Scales, make_spec: Callable[..., Any],
                 laws: dict[str, BellLaw] | None = None) -> CampaignPlanner:
    """One planner per (compound, p, v) point, combined; ``laws``: a bell law per compound
    (fitted, ``[adhesion] fit_from``) instead of the scene's one ``[adhesion]`` law."""
    if scene.variant == "separated":
        sep = scene.separated
        assert sep is not None
        if sep.reference and scales.full_sample is None:
            raise SceneError(f"{scene.source}: [separated].reference = true: the waves do not "
                             "share the macro "
                             "period, so there is no periodic full profile; set reference = false")
        planners = [SeparatedTwoScale(scene.name, pt, scales.sets[0], scales.sets[1],
                                      scales.full_sample, make_spec,
                                      pressures=sep.pressures,
                                      pressure_factors=sep.pressure_factors,
                                      velocities=sep.velocities,
                                      velocity_factors=sep.velocity_factors,
                                      reference=sep.reference, degree=sep.spline_degree,
                                      smoothing=sep.smoothing)
                    for pt in points(scene)]
    else:
        planners = [RoughCascade(scene.name, pt, scales.sets, make_spec, scene.samples.pressure,
                                 scene.samples.friction,
                                 adhesion=laws[pt.compound] if laws else scene.adhesion,
                                 max_failed_fraction=scene.samples.max_failed_fraction)
                    for pt in points(scene)]
    return CampaignPlanner(planners)


@dataclass
class CampaignResult:
    """What a finished campaign hands to the report."""

    scene: Scene
    output: Path
    points: list[PointResult]
    outcomes: dict[str, Outcome]
    scales: Scales | None
    wall_time: float
    workers: int
    started: str
    store: Store

    @property
    def n_runs(self) -> int:
        return len(self.outcomes)

    @property
    def n_reused(self) -> int:
        return sum(o.reused for o in self.outcomes.values())

    @property
    def n_failed(self) -> int:
        return sum(not o.ok for o in self.outcomes.values())

    @property
    def n_timed_out(self) -> int:
        """Runs the wall clock stopped (part of n_failed; recomputed on the next run)."""
        return sum(o.timed_out for o in self.outcomes.values())

    def provenance(self) -> dict:
        return {"scene": self.scene.name, "scene_source": self.scene.source,
                "variant": self.scene.variant,
                "code_version": code_version(), "git_describe": git_describe(),
                "started": self.started,
                "wall_time_s": self.wall_time, "workers": self.workers, "runs": self.n_runs,
                "runs_reused": self.n_reused, "runs_failed": self.n_failed,
                "runs_timed_out": self.n_timed_out,
                "surface": self.scales.provenance if self.scales else {}}


def _comm() -> Any:
    return MPI.COMM_WORLD


def _on_rank0(make: Callable[[], Any], comm: Any) -> Any:
    """``make()`` on rank 0 (None elsewhere); its error reaches every rank (an input error as a
    SceneError with the same message, so the command prints one line on rank 0 and the other
    ranks stop quietly), like :func:`open_store`."""
    rank, size = comm.Get_rank(), comm.Get_size()
    value, err = None, None
    if rank == 0:
        try:
            value = make()
        except Exception as e:  # noqa: BLE001 -- shared with the other ranks below
            err = e
    if size > 1:
        shared = comm.bcast(None if err is None else (isinstance(err, InputError), str(err)),
                            root=0)
        if shared is not None and rank != 0:
            is_input, message = shared
            if is_input:
                raise SceneError(message)
            raise RuntimeError(f"rank 0 could not prepare the campaign: {message}")
    if err is not None:
        raise err
    return value


def open_store(out: Path, comm: Any, fresh: bool = False,
               folder: Path | None = None) -> Store:
    """The campaign store ``<out>/store`` (or ``folder``); rank 0 takes the campaign lock (and
    with ``fresh`` moves an existing store aside first).  Collective over ``comm``; errors reach
    every rank."""
    rank, size = comm.Get_rank(), comm.Get_size()
    folder = out / "store" if folder is None else folder
    err: Exception | None = None
    store: Store | None = None
    if rank == 0:
        try:
            out.mkdir(parents=True, exist_ok=True)
            if fresh and folder.exists():
                stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
                folder.rename(folder.parent / f"store-{stamp}")
            store = Store(folder)
            store.lock()  # raises if another campaign runs in this folder
        except Exception as e:  # noqa: BLE001 -- shared with the other ranks below
            err = e
    if size > 1:
        err_any = comm.bcast(repr(err) if err else None, root=0)
        if err_any and rank != 0:
            raise RuntimeError(f"rank 0 could not open the output folder: {err_any}")
    if err is not None:
        raise err
    return store if store is not None else Store(folder)


def left_out(outcome: Outcome) -> str:
    """Why a successful run stays out of the averages, "" if it enters them (the progress
    line's "left out" count: an unconverged or over-stabilised run is a failed sample)."""
    return "" if usable(outcome) else why_unusable(outcome)


def runner_and_timeout(scene: Scene, runner: Callable[[Any], Any] | None,
                       reports: RunReports) -> tuple[Callable[[Any], Any], float]:
    """The run function and the watchdog time of a campaign: the default runner stops each run
    itself at ``run_timeout`` (a stored 'timeout' failure), so its watchdog only needs to catch
    runs stuck in compiled code, and reports every sliding step to ``reports`` (the progress
    line); a caller's runner gets the watchdog at ``run_timeout``."""
    timeout = scene.numerics.run_timeout
    if runner is not None:
        return runner, timeout
    return sliding_runner(wall_limit=timeout, progress=reports), hard_timeout(timeout)


def run_scene(scene: Scene, *, output: str | Path | None = None, quiet: bool = False,
              fresh: bool = False,
              retry_failed: bool = False, runner: Callable[[Any], Any] | None = None,
              comm: Any = None,
              report: bool = True, laws: dict[str, BellLaw] | None = None,
              store_folder: Path | None = None) -> CampaignResult | None:
    """Run (or resume) a scene.  Every rank of ``comm`` calls this; rank 0 returns the result.

    ``fresh``: move the existing store aside (``store-<time>``, nothing is deleted) and compute
    everything again.  ``retry_failed``: recompute runs stored as physics failures (otherwise
    reused like results; runs that raised or that the wall clock stopped are always recomputed).
    A scene with ``[adhesion] fit_from`` runs :func:`run_adhesion_fit`.  ``laws``: a bell law
    per compound on the macro scale; ``store_folder``: the store (default ``<output>/store``).
    """
    if scene.adhesion_fit is not None:
        return run_adhesion_fit(scene, output=output, quiet=quiet, fresh=fresh,
                                retry_failed=retry_failed, runner=runner, comm=comm,
                                report=report)
    comm = _comm() if comm is None else comm
    rank = comm.Get_rank()
    out = Path(output) if output is not None else scene.output
    reports = RunReports()
    runner, timeout = runner_and_timeout(scene, runner, reports)  # fails early, on all ranks
    started = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    # compounds and scales before the output folder: bad material data or a surface file that
    # cannot give the samples is an input error that leaves no (empty) store behind
    t0 = time.perf_counter()  # the campaign's wall time includes them, as before
    inputs = _on_rank0(lambda: (load_compounds(scene), build_scales(
        scene, max(scene.samples.pressure, scene.samples.friction))), comm)
    store = open_store(out, comm, fresh=fresh, folder=store_folder)
    try:
        executor = Executor(store, runner, retry_failed=retry_failed,
                            timeout=timeout, reports=reports,
                            settings={"scene": scene.name, "scene_source": scene.source})
        progress = Progress(quiet=quiet, unusable=left_out) if rank == 0 else None
        holder: dict[str, Any] = {}

        def planner_factory() -> CampaignPlanner:
            assert inputs is not None  # rank 0
            compounds, holder["scales"] = inputs
            return make_planner(scene, holder["scales"], SpecBuilder(scene, compounds), laws)

        planner, outcomes = run_farm(planner_factory, executor, progress, comm)
        if rank != 0:
            return None
        assert planner is not None
        result = CampaignResult(scene, out, planner.results, outcomes, holder.get("scales"),
                                time.perf_counter() - t0, progress.workers if progress else 1,
                                started, store)
        if report:
            write_report(result, quiet=quiet)
        return result
    finally:
        store.unlock()


def _measurements(scene: Scene) -> dict[str, list[SpeedCurve]]:
    """The ``fit_from`` files read (every rank, before any run: a bad file fails at once), and
    their speeds checked against the scene's velocities unless ``extrapolate``."""
    cfg = scene.adhesion_fit
    assert cfg is not None
    lo, hi = min(scene.conditions.velocities), max(scene.conditions.velocities)
    out: dict[str, list[SpeedCurve]] = {}
    try:
        for cond, files in cfg.files.items():
            out[cond] = [read_measurement(f) for f in files]
            for c in out[cond]:
                outside = c.v[0] < lo * (1 - 1e-12) or c.v[-1] > hi * (1 + 1e-12)
                if outside and not cfg.extrapolate:
                    raise SceneError(f"{scene.source}: [adhesion].fit_from.{cond}: {c.source} "
                                     f"spans {c.v[0]:g} .. {c.v[-1]:g} mm/s, outside the scene's "
                                     f"velocities {lo:g} .. {hi:g} mm/s: expected measurement "
                                     "speeds inside them, or [adhesion].extrapolate = true")
    except InputError as err:
        if isinstance(err, SceneError):
            raise
        raise SceneError(f"{scene.source}: [adhesion].fit_from: {err}") from None
    return out


def fit_campaign(scene: Scene, hysteresis: CampaignResult,
                 measured: dict[str, list[SpeedCurve]], approach: str | None = None
                 ) -> AdhesionFit:
    """Fit the bell law (thesis 7.3-7.5) to the measurements with A_r(v) and mu_H(v) of the
    finished hysteresis campaign (eq. 7.5: ``PointResult.area_ratio``; mu_H: its mu), by the
    scene's approach or the one given."""
    cfg = scene.adhesion_fit
    assert cfg is not None
    approach = cfg.approach if approach is None else approach
    inputs, notes = [], []
    try:
        for k, name in enumerate(scene.conditions.compounds):
            rs = sorted((r for r in hysteresis.points if r.ok and r.point.compound == name),
                        key=lambda r: r.point.velocity)
            if len(rs) < 2:
                raise SceneError(f"{scene.source}: [adhesion].fit_from: compound {name!r} has "
                                 f"{len(rs)} successful point(s) in the hysteresis campaign: "
                                 "expected at least two velocities for A_r(v) and mu_H(v)")
            v = np.array([r.point.velocity for r in rs])
            src = f"hysteresis campaign {hysteresis.output} ({name})"
            area = SpeedCurve(v, np.array([r.area_ratio for r in rs]), "A_r", src)
            mu_h = SpeedCurve(v, np.array([r.mu.mean for r in rs]), "mu_H",  # type: ignore
                              src)
            curves = {cond: files[k] for cond, files in measured.items()}
            if not cfg.extrapolate:
                curves = {cond: _within(c, v[0], v[-1], name, notes, scene.source)
                          for cond, c in curves.items()}
            inputs.append(CompoundInput(name, curves["dry"], area, hysteresis=mu_h,
                                        soap=curves.get("soap"), water=curves.get("water")))
        fit = fit_adhesion(inputs, scene.conditions.pressures[0], approach=approach,
                           alpha=cfg.alpha, extrapolate=cfg.extrapolate)
        return replace(fit, notes=tuple(notes) + fit.notes)
    except InputError as err:
        if isinstance(err, SceneError):
            raise
        raise SceneError(f"{scene.source}: [adhesion].fit_from: {err}") from None


def _other_approach(scene: Scene, hysteresis: CampaignResult,
                    measured: dict[str, list[SpeedCurve]]) -> AdhesionFit | str:
    """The fit by the approach the scene did not choose, for comparison (thesis 7.4 against 7.5:
    the original approach's tau0 carries the soap-water curve's own adhesion); the reason as a
    string where the data do not allow it (no soap-water files) or it fails."""
    cfg = scene.adhesion_fit
    assert cfg is not None
    name = "modified" if cfg.approach == "original" else "original"
    if name == "original" and "soap" not in measured:
        return "original approach not fitted: no soap-water measurement (fit_from.soap)"
    try:
        return fit_campaign(scene, hysteresis, measured, approach=name)
    except Exception as err:  # noqa: BLE001 -- a comparison must not stop the scene or hang ranks
        return f"{name} approach not fitted: {type(err).__name__}: {err}"


def _within(curve: SpeedCurve, lo: float, hi: float, compound: str, notes: list[str],
            source: str) -> SpeedCurve:
    """The measured ``curve`` on the speeds lo..hi (mm/s) where the hysteresis campaign has
    successful points: a failed end point of the campaign leaves the measurements beyond it out
    of the fit (a note says so) instead of stopping the scene; fewer than two speeds left is a
    SceneError."""
    keep = (curve.v >= lo * (1 - 1e-12)) & (curve.v <= hi * (1 + 1e-12))
    if keep.all():
        return curve
    if keep.sum() < 2:
        raise SceneError(f"{source}: [adhesion].fit_from: {curve.source} keeps {int(keep.sum())} "
                         f"speed(s) inside {lo:g} .. {hi:g} mm/s, where compound {compound!r} has "
                         "successful hysteresis points: expected at least two")
    notes.append(f"{compound}: {int((~keep).sum())} speed(s) of {curve.source} outside "
                 f"{lo:g} .. {hi:g} mm/s (the successful points of the hysteresis campaign) left "
                 "out of the fit")
    return replace(curve, v=curve.v[keep], values=curve.values[keep])


def run_adhesion_fit(scene: Scene, *, output: str | Path | None = None, quiet: bool = False,
                     fresh: bool = False, retry_failed: bool = False,
                     runner: Callable[[Any], Any] | None = None, comm: Any = None,
                     report: bool = True) -> CampaignResult | None:
    """``[adhesion] fit_from``, thesis fig. 7.3: (A, B) the hysteresis campaign into
    ``<output>/hysteresis``; (C, D) the bell-law fit of tau0 (per compound), c, v0 to the
    measurements and alpha (:func:`fit_campaign`); (E) the macro friction runs again with
    ``mu* = mu_1 + alpha mu_A`` (eq. 7.8) for alpha = 1 and each fitted alpha in (0, 1), into
    ``<output>/alpha=<a>``.  All share ``<output>/store``: only the macro friction runs are new
    ("a recalculation of the lower scales is omitted", thesis 7.3).  alpha = 0 is the hysteresis
    campaign itself.  ``<output>/adhesion/`` gets the fit and the comparison with the
    measurements (:mod:`.adhesion_report`).  Returns (rank 0) the alpha = 1 campaign."""
    comm = _comm() if comm is None else comm
    rank = comm.Get_rank()
    out = Path(output) if output is not None else scene.output
    measured = _measurements(scene)
    base = replace(scene, adhesion=None, adhesion_fit=None)
    store = out / "store"
    t0 = time.perf_counter()
    hyst = run_scene(base, output=out / "hysteresis", quiet=quiet, fresh=fresh,
                     retry_failed=retry_failed, runner=runner, comm=comm, report=report,
                     store_folder=store)
    fit, message, other = None, None, None
    if rank == 0:
        assert hyst is not None
        try:
            fit = fit_campaign(scene, hyst, measured)
        except SceneError as err:
            message = str(err)
        other = _other_approach(scene, hyst, measured)
    payload = (None if fit is None else
               ([(c, t.value) for c, t in zip(fit.bell.compounds, fit.bell.tau0)],
                fit.bell.c.value, fit.bell.v0.value, [s.alpha for s in fit.shares]), message)
    if comm.Get_size() > 1:
        payload = comm.bcast(payload, root=0)
    law_data, message = payload
    if message is not None:
        raise SceneError(message)
    assert law_data is not None
    tau0, c, v0, shares = law_data
    alphas = [1.0] + sorted({a for a in shares if 0.0 < a < 1.0}, reverse=True)
    t_fit = time.perf_counter() - t0
    runs: dict[float, CampaignResult] = {}
    for alpha in alphas:
        laws = {name: BellLaw(t, c, v0, alpha) for name, t in tau0}
        res = run_scene(base, output=out / f"alpha={alpha:.4g}", quiet=quiet,
                        retry_failed=retry_failed, runner=runner, comm=comm, report=report,
                        laws=laws, store_folder=store)
        if res is not None:
            runs[alpha] = res
    if rank != 0:
        return None
    assert hyst is not None and fit is not None
    write_adhesion_report(out / "adhesion", scene, hyst, fit, runs,
                          {"campaigns_and_fit_s": t_fit,
                           "macro_runs_s": time.perf_counter() - t0 - t_fit}, quiet=quiet,
                          other=other)
    return runs[1.0]


def run_sample_study(scene: Scene, *, scale: str | int | None = None, n: int = 30,
                     pressure: float | None = None,
                     velocity: float | None = None, compound: str | None = None, orders: int = 1000,
                     output: str | Path | None = None, quiet: bool = False,
                     runner: Callable[[Any], Any] | None = None, comm: Any = None) -> dict | None:
    """Thesis 6.4.2 / fig. 6.13: n frictionless samples of one scale at (p, v), then S(n).

    Runs go through the same store as the scene's campaign (same output folder), so a study
    reuses runs a campaign already did and vice versa.  Returns (on rank 0) a dict with the
    study (:class:`~rubberfriction.driver.multiscale.statistics.SampleCountStudy`), the
    outcomes and the files written.
    """
    comm = _comm() if comm is None else comm
    rank = comm.Get_rank()
    out = Path(output) if output is not None else scene.output
    reports = RunReports()
    runner, timeout = runner_and_timeout(scene, runner, reports)
    names = scale_names(scene.n_scales) if not scene.surface.names else list(scene.surface.names)
    if scale is None:
        si = scene.n_scales - 1
    elif isinstance(scale, int) or str(scale).isdigit():
        si = int(scale)
    elif scale in names:
        si = names.index(str(scale))
    else:
        raise SceneError(f"--scale {scale!r}: expected a scale index 0..{scene.n_scales - 1} or "
                         f"one of {names}")
    if not 0 <= si < scene.n_scales:
        raise SceneError(f"--scale {scale!r}: expected a scale index 0..{scene.n_scales - 1}")
    comp = compound or scene.conditions.compounds[0]
    if comp not in scene.conditions.compounds:
        raise SceneError(f"--compound {comp!r}: expected one of the scene's compounds "
                         f"{list(scene.conditions.compounds)}")
    p = float(pressure if pressure is not None else scene.conditions.pressures[0])
    v = float(velocity if velocity is not None else scene.conditions.velocities[0])
    if n < 2:
        raise SceneError(f"--n {n}: expected at least 2 samples")
    store = open_store(out, comm)
    try:
        executor = Executor(store, runner, timeout=timeout, reports=reports,
                            settings={"scene": scene.name, "study": "samples"})
        progress = Progress(quiet=quiet, unusable=left_out) if rank == 0 else None
        holder: dict[str, Any] = {}

        def planner_factory() -> StaticPlanner:
            scales = build_scales(scene, n)
            make_spec = SpecBuilder(scene, load_compounds(scene))
            sset = scales.sets[si]
            holder["scale"] = sset
            pt = Point(comp, p, v)
            tasks = []
            for k, smp in enumerate(sset.samples):
                spec = make_spec(pt, si, smp, p, None, "study")
                tasks.append(Task(run_key(spec), spec,
                                  {"campaign": scene.name, "point": pt.id, "branch": "study",
                                   "scale": si, "scale_name": sset.name,
                                   "sample": k,
                                   "pressure_in": p, "friction_in": 0.0}))
            return StaticPlanner(tasks)

        planner, _ = run_farm(planner_factory, executor, progress, comm)
        if rank != 0:
            return None
        assert isinstance(planner, StaticPlanner)
        outcomes = planner.ordered()
        values = [o.value("mu_force") if o.ok else math.nan for o in outcomes]
        study = sample_count_study(values, orders=orders)
        folder = out / "samples-study"
        folder.mkdir(parents=True, exist_ok=True)
        stem = f"{holder['scale'].name}_p{p:g}_v{v:g}_{comp}"
        files = [write_csv(folder / f"{stem}.csv", study_rows(study)),
                 write_csv(folder / f"{stem}_samples.csv",
                           [{"sample": k, "status": o.status,
                             "reason": o.reason.splitlines()[0] if o.reason else "",
                             "mu_force": o.value("mu_force"),
                             "mean_pressure": o.value("mean_pressure"),
                             "contact_fraction": o.value("contact_fraction"), "key": o.key}
                            for k, o in enumerate(outcomes)]),
                 plot_sample_study(study, folder / f"{stem}.png",
                                   f"{holder['scale'].name}, p = {p:g} MPa, v = {v:g} mm/s, "
                                   f"{comp}: {study.values.size} samples ({study.n_failed} "
                                   f"failed)")]
        return {"study": study, "outcomes": outcomes, "files": files, "scale": holder["scale"].name,
                "pressure": p, "velocity": v, "compound": comp}
    finally:
        store.unlock()
