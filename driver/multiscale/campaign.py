"""From a scene to results: scales and samples, run specs, planners, farm, store, report.

The glue between the modules with one job each: :mod:`.scene` (what to compute) ->
:func:`build_scales` (surface scales and periodic samples, :mod:`.surfaces`) ->
:class:`SpecBuilder` (one :class:`~rubberfriction.driver.sliding.run.SlidingSpec` per run from the
scene's numerical settings) -> :mod:`.homogenise` planners -> :mod:`.farm` (serial or MPI) with
the :mod:`.store` -> :mod:`.report`.  :func:`run_scene` is what ``rubberfriction run`` calls.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

# MPI is initialised here, before anything imports DOLFINx/PETSc (which would initialise it with
# MPI_THREAD_FUNNELED): the farm's dispatcher thread on rank 0 needs MPI_THREAD_MULTIPLE.
from mpi4py import MPI  # isort: skip

from rubberfriction.driver.runtime.farm import Executor, default_runner, hard_timeout, run_farm
from rubberfriction.driver.multiscale.cascade import CampaignPlanner, RoughCascade
from rubberfriction.driver.multiscale.results import Point, PointResult, ScaleSet
from rubberfriction.driver.multiscale.separated import SeparatedTwoScale
from rubberfriction.driver.runtime.progress import Progress
from rubberfriction.driver.multiscale.scene import Scene, SceneError
from rubberfriction.driver.runtime.store import Outcome, Store, code_version, git_describe


@dataclass(frozen=True)
class PeriodicSample:
    """A periodic surface sample built here (sine waves): x 0..period inclusive, h[-1] == h[0]."""

    x: np.ndarray
    h: np.ndarray
    period: float
    source: str = "generated"

    @property
    def rms_height(self) -> float:
        return float(np.std(self.h[:-1]))

    @property
    def rms_slope(self) -> float:
        return float(np.sqrt(np.mean((np.diff(self.h) / np.diff(self.x)) ** 2)))


def sine_sample(amplitudes: list[float], wavelengths: list[float], length: float,
                points_per_wavelength: int) -> PeriodicSample:
    """sum_i a_i sin(2 pi x / lambda_i) on [0, length], sampled with points_per_wavelength vertices
    per shortest wavelength (endpoint included)."""
    m = int(round(points_per_wavelength * length / min(wavelengths)))
    x = np.linspace(0.0, length, m + 1)
    h = sum(a * np.sin(2.0 * np.pi * x / lam) for a, lam in zip(amplitudes, wavelengths))
    h = np.asarray(h, dtype=float)
    h[-1] = h[0]
    return PeriodicSample(x, h, float(length))


@dataclass
class Scales:
    """The scales of a scene with their samples (and the full-profile sample for a reference)."""

    sets: list[ScaleSet]
    full_sample: Any = None
    description: str = ""
    provenance: dict = field(default_factory=dict)


def build_scales(scene: Scene, n_samples: int) -> Scales:
    """Band-pass scales (eq. 6.10, 6.14) and ``n_samples`` periodic samples per scale (6.3.1)."""
    s = scene.surface
    if s.source == "sines":
        sets = []
        names = list(s.names) or _scale_names(len(s.wavelengths))
        for i, (a, lam) in enumerate(zip(s.amplitudes, s.wavelengths)):
            L = s.block_lengths[i] if s.block_lengths else s.periods_per_block * lam
            if abs(L / lam - round(L / lam)) > 1e-9:
                raise SceneError(f"{scene.source}: [surface].block_lengths[{i}] = {L:g}: expected "
                                 f"a whole number of wavelengths {lam:g} mm (a periodic sample)")
            band = (s.edges[i], s.edges[i + 1]) if s.edges else (lam, lam)
            smp = sine_sample([a], [lam], L, s.points_per_wavelength)
            sets.append(ScaleSet(names[i], band, tuple([smp] * n_samples)))
        L0 = sets[0].samples[0].period
        full = None
        for lam in s.wavelengths:
            if abs(L0 / lam - round(L0 / lam)) > 1e-9:
                break
        else:
            full = sine_sample(list(s.amplitudes), list(s.wavelengths), L0, s.points_per_wavelength)
        desc = "sines: " + " + ".join(f"{a:g} sin(2 pi x / {lam:g})" for a,
                                      lam in zip(s.amplitudes, s.wavelengths))
        return Scales(sets, full, desc, {"source": "sines", "amplitudes": list(s.amplitudes),
                                         "wavelengths": list(s.wavelengths)})
    from rubberfriction.driver.surfaces import (
        SurfaceError,
        default_road,
        load_profile,
        multiscale_from_measurements,
    )

    try:
        if s.source == "default_road":
            road = default_road(edges=s.edges)
        else:
            profiles = [load_profile(p) for p in s.files]
            road = multiscale_from_measurements(profiles, s.edges, names=list(s.names) or None,
                                                block_lengths=list(s.block_lengths) or None,
                                                name=scene.name)
        if s.names:
            for sc, nm in zip(road.scales, s.names):
                sc.name = nm
        if s.block_lengths:
            for sc, b in zip(road.scales, s.block_lengths):
                sc.block_length = float(b)
        samples = road.extract_samples(n=n_samples, seed=s.seed, top_fraction=s.top_fraction)
    except SurfaceError as err:
        raise SceneError(f"{scene.source}: [surface] (source = {s.source!r}, edges = "
                         f"{list(s.edges)}): {err}") from None
    sets = [ScaleSet(sc.name, tuple(sc.band), tuple(smp)) for sc, smp in zip(road.scales, samples)]
    full = None
    if scene.variant == "separated" and scene.separated is not None and scene.separated.reference:
        full = _full_sample(scene, road)
    return Scales(sets, full, road.describe(), road.to_dict())


def _full_sample(scene: Scene, road: Any) -> Any:
    """A macro-length sample of the sum of both bands (reference run of the separated variant)."""
    from rubberfriction.driver.surfaces import extract_samples

    a, b = road.scales
    if a.profile.x.shape != b.profile.x.shape or not np.allclose(a.profile.x, b.profile.x):
        raise SceneError(f"{scene.source}: [separated].reference = true needs both scales cut from "
                         f"one "
                         "measurement (the full profile is their sum); set reference = false")
    full = a.profile.with_h(a.profile.h + b.profile.h)
    full.meta.update(a.profile.meta)
    return extract_samples(full, a.block_length, 1, scene.surface.seed, carrier=a.carrier,
                           top_fraction=scene.surface.top_fraction)[0]


def _scale_names(n: int) -> list[str]:
    from rubberfriction.driver.surfaces.multiscale import scale_names

    return scale_names(n)


def refined_master(x: np.ndarray, h: np.ndarray, period: float, lam_min: float,
                   points_per_wavelength: int) -> tuple[np.ndarray, np.ndarray]:
    """The rigid master polyline of a periodic sample with at least ``points_per_wavelength``
    vertices per shortest wavelength ``lam_min`` of its band: band-limited interpolation
    (``surfaces.samples.refine_periodic``) by a whole factor, so every measured point stays a
    vertex.  Samples already that fine, non-uniform ones and ``points_per_wavelength = 0`` pass
    as they are.  The default road's micro2 samples (0.04-0.003 mm band at 0.0005 mm spacing,
    rms slope 4) have 6 points per shortest wavelength; refined to 36, the default scene's micro2
    failures went from 5 of 6 runs to 1 of 6."""
    from rubberfriction.driver.surfaces.profile import UNIFORM_RTOL
    from rubberfriction.driver.surfaces.samples import refine_periodic

    n = x.size
    if points_per_wavelength <= 0 or n < 4 or not period > 0.0:
        return x, h
    dx = period / n
    if not np.allclose(np.diff(x), dx, rtol=UNIFORM_RTOL, atol=0.0):
        return x, h
    factor = math.ceil(points_per_wavelength * dx / lam_min - 1e-9)
    if factor <= 1:
        return x, h
    return x[0] + np.arange(n * factor) * (dx / factor), refine_periodic(h, factor)


class SpecBuilder:
    """SlidingSpec of one run from the scene's settings (the ``make_spec`` of the planners)."""

    def __init__(self, scene: Scene, compounds: dict[str, Any]):
        self.scene = scene
        self.compounds = compounds

    def __call__(self, point: Point, scale: int, sample: Any, pressure: float, friction: Any,
                 role: str) -> Any:
        from rubberfriction.driver.sliding.spec import SlidingSpec, default_h_contact

        num = self.scene.numerics
        window, slide = num.window_start, num.slide_periods
        if role == "micro" and self.scene.separated is not None:
            sep = self.scene.separated
            window, slide = sep.micro_window_start, sep.micro_slide_periods
        x, h, period = np.asarray(sample.x, float), np.asarray(sample.h,
                                                               float), float(sample.period)
        if x.size > 1 and abs(x[-1] - x[0] - period) < 1e-9 * period:
            x, h = x[:-1], h[:-1]  # one period given: the closing vertex repeats the first
        band = getattr(sample, "band", None)
        lam_band = float(band[1]) if band is not None and np.isfinite(band[1]) and band[1] > 0 \
            else None  # the band's short edge, where the sample knows its band
        if lam_band is not None:
            x, h = refined_master(x, h, period, lam_band, num.master_points_per_wavelength)
        base = SlidingSpec(surface_x=x, surface_h=h, period=period, pressure=float(pressure),
                           velocity=float(point.velocity), compound=self.compounds[point.compound],
                           temperature=self.scene.conditions.T0, friction=friction,
                           element=num.element,
                           contact=num.contact, elements_per_wavelength=num.elements_per_wavelength,
                           grading=num.grading, compression_steps=num.compression_steps,
                           window_start=window, max_cutbacks=num.max_cutbacks,
                           penalty_alpha=num.penalty_alpha)
        # contact element size: the shortest wavelength of the sample / elements_per_wavelength;
        # the shortest wavelength is the band's short edge (thesis 6.5.1), else (or if shorter)
        # the run's estimate from slope sign changes
        hc = float(default_h_contact(base))
        if lam_band is not None:
            hc = min(hc, lam_band / num.elements_per_wavelength)
        return dataclasses.replace(base, h_contact=hc, step_length=num.step_per_element * hc,
                                   slide_distance=slide * period)


def load_compounds(scene: Scene) -> dict[str, Any]:
    """Compounds of the scene by the name written in it; elastic (no Prony) without hysteresis."""
    from rubberfriction.forms.materials import load_compound

    out = {}
    for i, (name, path) in enumerate(zip(scene.conditions.compounds,
                                         scene.conditions.compound_paths)):
        try:
            c = load_compound(path)
        except ValueError as err:
            raise SceneError(f"{scene.source}: [conditions].compounds[{i}] = {name!r}: "
                             f"{err}") from None
        if not scene.physics.hysteresis:
            c = dataclasses.replace(c, prony=None)  # no history variables are built
        out[name] = c
    return out


def points(scene: Scene) -> list[Point]:
    c = scene.conditions
    return [Point(name, p, v) for name in c.compounds for p in c.pressures for v in c.velocities]


def make_planner(scene: Scene, scales: Scales, make_spec: Callable[..., Any]) -> CampaignPlanner:
    """One planner per (compound, p, v) point, combined."""
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
                                 scene.samples.friction, adhesion=scene.adhesion,
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

    def provenance(self) -> dict:
        return {"scene": self.scene.name, "scene_source": self.scene.source,
                "variant": self.scene.variant,
                "code_version": code_version(), "git_describe": git_describe(),
                "started": self.started,
                "wall_time_s": self.wall_time, "workers": self.workers, "runs": self.n_runs,
                "runs_reused": self.n_reused, "runs_failed": self.n_failed,
                "surface": self.scales.provenance if self.scales else {}}


def _comm() -> Any:
    return MPI.COMM_WORLD


def open_store(out: Path, comm: Any, fresh: bool = False) -> Store:
    """The campaign store ``<out>/store``; rank 0 takes the campaign lock (and with ``fresh``
    moves an existing store aside first).  Collective over ``comm``; errors reach every rank."""
    rank, size = comm.Get_rank(), comm.Get_size()
    err: Exception | None = None
    store: Store | None = None
    if rank == 0:
        try:
            out.mkdir(parents=True, exist_ok=True)
            if fresh and (out / "store").exists():
                stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
                (out / "store").rename(out / f"store-{stamp}")
            store = Store(out / "store")
            store.lock()  # raises if another campaign runs in this folder
        except Exception as e:  # noqa: BLE001 -- shared with the other ranks below
            err = e
    if size > 1:
        err_any = comm.bcast(repr(err) if err else None, root=0)
        if err_any and rank != 0:
            raise RuntimeError(f"rank 0 could not open the output folder: {err_any}")
    if err is not None:
        raise err
    return store if store is not None else Store(out / "store")


def _runner_and_timeout(scene: Scene, runner: Callable[[Any], Any] | None
                        ) -> tuple[Callable[[Any], Any], float]:
    """The run function and the watchdog time of a campaign: the default runner stops each run
    itself at ``run_timeout`` (a stored 'timeout' failure), so its watchdog only needs to catch
    runs stuck in compiled code; a caller's runner gets the watchdog at ``run_timeout``."""
    timeout = scene.numerics.run_timeout
    if runner is not None:
        return runner, timeout
    return default_runner(wall_limit=timeout), hard_timeout(timeout)


def run_scene(scene: Scene, *, output: str | Path | None = None, quiet: bool = False,
              fresh: bool = False,
              retry_failed: bool = False, runner: Callable[[Any], Any] | None = None,
              comm: Any = None,
              report: bool = True) -> CampaignResult | None:
    """Run (or resume) a scene.  Every rank of ``comm`` calls this; rank 0 returns the result.

    ``fresh``: move the existing store aside (``store-<time>``, nothing is deleted) and compute
    everything again.  ``retry_failed``: recompute runs stored as failed (physics failures are
    otherwise reused like results; runs that raised are always retried).
    """
    comm = _comm() if comm is None else comm
    rank = comm.Get_rank()
    out = Path(output) if output is not None else scene.output
    runner, timeout = _runner_and_timeout(scene, runner)  # fails early, identically on all ranks
    started = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    store = open_store(out, comm, fresh=fresh)
    try:
        executor = Executor(store, runner, retry_failed=retry_failed,
                            timeout=timeout,
                            settings={"scene": scene.name, "scene_source": scene.source})
        progress = Progress(quiet=quiet) if rank == 0 else None
        holder: dict[str, Any] = {}

        def planner_factory() -> CampaignPlanner:
            n = max(scene.samples.pressure, scene.samples.friction)
            holder["scales"] = scales = build_scales(scene, n)
            return make_planner(scene, scales, SpecBuilder(scene, load_compounds(scene)))

        t0 = time.perf_counter()
        planner, outcomes = run_farm(planner_factory, executor, progress, comm)
        if rank != 0:
            return None
        assert planner is not None
        result = CampaignResult(scene, out, planner.results, outcomes, holder.get("scales"),
                                time.perf_counter() - t0, progress.workers if progress else 1,
                                started, store)
        if report:
            from rubberfriction.driver.multiscale.report import write_report

            write_report(result, quiet=quiet)
        return result
    finally:
        store.unlock()


def campaign_json(result: CampaignResult) -> str:
    def default(o: Any) -> Any:
        if isinstance(o, (np.floating, np.integer)):
            return o.item()
        if isinstance(o, float) and math.isnan(o):
            return None
        return str(o)

    return json.dumps(result.provenance(), indent=2, default=default)


def run_sample_study(scene: Scene, *, scale: str | int | None = None, n: int = 30,
                     pressure: float | None = None,
                     velocity: float | None = None, compound: str | None = None, orders: int = 1000,
                     output: str | Path | None = None, quiet: bool = False,
                     runner: Callable[[Any], Any] | None = None, comm: Any = None) -> dict | None:
    """Thesis 6.4.2 / fig. 6.13: n frictionless samples of one scale at (p, v), then S(n).

    Runs go through the same store as the scene's campaign (same output folder), so a study
    reuses runs a campaign already did and vice versa.  Returns (on rank 0) a dict with the
    study (:class:`~rubberfriction.driver.multiscale.cascade.SampleCountStudy`), the outcomes and the
    files written.
    """
    from rubberfriction.driver.runtime.farm import StaticPlanner, Task
    from rubberfriction.driver.multiscale.statistics import sample_count_study
    from rubberfriction.driver.runtime.store import run_key

    comm = _comm() if comm is None else comm
    rank = comm.Get_rank()
    out = Path(output) if output is not None else scene.output
    runner, timeout = _runner_and_timeout(scene, runner)
    names = _scale_names(scene.n_scales) if not scene.surface.names else list(scene.surface.names)
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
        executor = Executor(store, runner, timeout=timeout,
                            settings={"scene": scene.name, "study": "samples"})
        progress = Progress(quiet=quiet) if rank == 0 else None
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
        from rubberfriction.driver.multiscale.report import _write_csv, plot_sample_study, study_rows

        folder = out / "samples-study"
        folder.mkdir(parents=True, exist_ok=True)
        stem = f"{holder['scale'].name}_p{p:g}_v{v:g}_{comp}"
        files = [_write_csv(folder / f"{stem}.csv", study_rows(study)),
                 _write_csv(folder / f"{stem}_samples.csv",
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
