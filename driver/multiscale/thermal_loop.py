"""Flash temperature end to end: the thermal multiscale loop (thesis 8.3.2-8.3.4, fig. 8.1).

The procedure of fig. 8.4 b (lower right) that the thesis proposed and ran by hand, automated:

A. the isothermal cascade (chapter 6, ``cascade.RoughCascade``) gives mu(T0); the thermomechanical
   macro run (``thermal.macro``: block on the flat road, frictional heating) starts with
   mu_const + mu(T0) in its contact (mu_const: a constant part the lower scales do not give, the
   thesis' adhesive part, 8.3.2, or the 0.6 of 8.4.3).  With the scene's bell law
   (``CascadeRunner(adhesion=)``) every cascade adds alpha mu_A = alpha tau_A(v) A_r / p on its top
   scale (eq. 7.6-7.8) with the real contact area A_r of that cascade: the flash temperature then
   acts on the adhesive part through A_r (hot, softer rubber touches more); tau_A(v) is the law's,
   not shifted by temperature;
B. at each homogenisation point s_i (sliding distance) the rubber temperature below the active
   contact nodes is averaged over x, eq. (8.1) (``thermal.profile.average_profile``);
C. the profile becomes n_p partitions over ``partition_depth`` (8.3.3), continued down each
   lower-scale block's height by partitions doubling in thickness at the macro field's mean
   (``Partitions.block``): the temperature layers of every lower-scale run
   (``SlidingSpec.temperature_layers``: WLF-shifted relaxation per cell);
D. the whole cascade runs again with those layers (pressure branch down, friction branch up, all
   scales and samples), through the campaign store: its keys contain the layer temperatures.
   Warm starts (``CascadeRunner(states=)``, the scene's ``[thermal] warm_start``): every run
   slides on from the final state of the same run (branch, scale, sample) at the point before,
   the isothermal cascade's at the first (``LayeredSpecs``, ``SlidingSpec.initial_state``): the
   rubber keeps its deformation and Prony histories while it heats, as it does on the road,
   and the run needs no compression and no run-in period: fewer periods than from rest, fewer
   still with one-period blocks (``warm_window``, the scenes' ``warm_window_periods = 1``;
   docs/performance.md).  The thesis restarted every
   lower-scale run from rest; ``warm_start = false`` does that;
E. the homogenised mu(s_i) goes back into the running macro contact (``Contact.set_friction``),
   which continues from its state at s_i (no recomputation from t = 0).

The last point is the end of the slide.  Points: ``divisions`` equal parts of the slide (n_d,
thesis 8.4.3) or an explicit list.

The macro road (``rough``): flat (the cascade's own macro scale stands for the road's macro band
and the macro contact gets the whole cascade's mu), or the rough macro band of the scene's road
(thesis figs. 8.2, 8.17 a; ``thermal_scene.macro_inputs``, the road of the given mode): the macro
block then IS the macro scale, its contact gets the mu the cascade hands to its macro scale
(:func:`lower_mu`: the scales below plus alpha mu_A) and its own hysteresis on the band enters
through F_x / F_z.

The point's mu (thesis 8.5.3: "time homogenization after a stationary coefficient of friction was
reached in the macroscopic simulation"): the time average of the macro mu over the stationary
part of the slide (``window.stationary_mean``, the converged rule on equal blocks of the slide),
with its window, drift and whether it is stationary; the macro mu is F_x / F_z on the rough road
and the contact's mu on the flat one (there the block adds only its edges).  On the rough road the
isothermal reference is the same macro run with the isothermal mu and the bulk at T0 (thesis
8.5.3's mechanical macro run), averaged by the same rule.

Resume and MPI: the macro run is deterministic and runs on rank 0; every lower-scale run goes
through the store, so a rerun of a killed loop recomputes the macro run (seconds) and only the
lower-scale runs that are missing.  A warm-started run's key contains its initial state (the
parent's final state, read back from the store), so a resumed loop builds the same keys.  Each
cascade is farmed over all ranks of ``comm``: the workers wait between homogenisation points
(rank 0 tells them "cascade" or "done").
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from rubberfriction import validation as V
from rubberfriction.driver.multiscale.cascade import CampaignPlanner, RoughCascade
from rubberfriction.driver.multiscale.results import Point, PointResult, ScaleSet
from rubberfriction.driver.runtime.farm import run_farm
from rubberfriction.driver.sliding.spec import InitialState, SlidingSpec
from rubberfriction.driver.sliding.window import STATIONARY_BLOCKS, StationaryMean, stationary_mean
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.thermal.conduction import block_levels
from rubberfriction.driver.thermal.macro import (
    MacroSettings,
    ThermalCoupler,
    ThermalMacroResult,
    run_thermal_macro,
)
from rubberfriction.driver.thermal.profile import (
    Partitions,
    TemperatureProfile,
    average_profile,
    partition_profile,
    uniform_partitions,
)
from rubberfriction.forms.compound import Thermal


@dataclass(frozen=True)
class LoopSettings:
    """Homogenisation points: ``points`` (sliding distances in mm, increasing, the last at most the
    slide) or else ``divisions`` equal parts of the slide; n_p partitions over
    ``partition_depth`` mm (thesis 8.4.2: 0.09); ``mu_const`` added to the lower scales' mu on the
    macro scale.  ``auto_dT`` > 0 K: automatic points instead (thesis 8.4.3: short intervals where
    the surface temperature changes fast): a point whenever the mean surface temperature of the
    active contact (eq. 8.1 at z = 0) has moved by auto_dT since the last one, at most
    ``max_points``, and at the end of the slide."""

    divisions: int = 4
    points: tuple[float, ...] = ()
    n_partitions: int = 4
    partition_depth: float = 0.09
    mu_const: float = 0.0
    auto_dT: float = 0.0
    max_points: int = 16
    rough: bool = False  # the macro block on the rough macro band (module doc)
    blocks: int = STATIONARY_BLOCKS  # the stationary mean's blocks of the slide
    tol: float = 0.01  # and its tolerance (relative)

    def __post_init__(self) -> None:
        V.integer("blocks", self.blocks, minimum=1)
        V.positive("tol", self.tol)
        V.nonnegative("auto_dT", self.auto_dT, "K")
        V.integer("max_points", self.max_points, minimum=1)
        V.integer("divisions", self.divisions, minimum=1)
        V.integer("n_partitions", self.n_partitions, minimum=1)
        V.positive("partition_depth", self.partition_depth, "mm")
        V.nonnegative("mu_const", self.mu_const)
        p = np.asarray(self.points, float)
        if p.size and (not np.all(np.isfinite(p)) or p[0] <= 0 or np.any(np.diff(p) <= 0)):
            raise V.InputError(f"points = {list(self.points)!r} mm: expected increasing sliding "
                               "distances > 0")

    def distances(self, slide: float) -> np.ndarray:
        """The planned homogenisation points s_1 < ... < s_m = slide (mm); automatic points
        (auto_dT) come on top of the slide's end."""
        if self.auto_dT > 0:
            return np.array([float(slide)])
        if self.points:
            p = np.asarray(self.points, float)
            if p[-1] > slide * (1 + 1e-12):
                raise V.InputError(f"points: {p[-1]:g} mm lies beyond the slide of {slide:g} mm")
            return p if abs(p[-1] - slide) <= 1e-9 * slide else np.append(p, slide)
        return slide * np.arange(1, self.divisions + 1) / self.divisions


@dataclass
class Interval:
    """One homogenisation point: the macro state at s_end and what the lower scales made of it."""

    index: int
    s_end: float
    t_end: float
    mu_in: float  # lower-scale mu used on the macro scale up to s_end (without mu_const)
    profile: TemperatureProfile
    partitions: Partitions
    cascade: PointResult
    mu_out: float  # the cascade's mu at s_end (nan if it failed: mu_in is kept)
    wall: float  # s spent in the cascade


@dataclass
class ThermalLoopResult:
    point: Point
    isothermal: PointResult
    macro: ThermalMacroResult | None
    intervals: list[Interval] = field(default_factory=list)
    settings: LoopSettings = field(default_factory=LoopSettings)
    wall: float = math.nan
    notes: list[str] = field(default_factory=list)
    error: str = ""  # the loop stopped (an exception in a homogenisation step)
    wall_isothermal: float = math.nan  # s in the isothermal cascade (the isothermal point's cost)
    s_final: float = math.inf  # sliding distance of the last homogenisation point (the slide's end)
    average: StationaryMean | None = None  # the point's mu: stationary mean of the macro mu
    iso_macro: ThermalMacroResult | None = None  # rough road: the isothermal macro run
    iso_average: StationaryMean | None = None  # and its stationary mean

    @property
    def mu_isothermal(self) -> float:
        """Flat road: mu_const + the isothermal cascade's mu; rough road: the stationary mean of
        the isothermal macro run's F_x / F_z (nan where it did not run)."""
        if self.settings.rough:
            return _mean(self.iso_average)
        return self.settings.mu_const + _mu(self.isothermal)

    @property
    def mu_end(self) -> float:
        """mu_const + the lower scales' mu at the end of the slide (the last cascade's, on the
        rough road the part handed to the macro scale); nan unless the macro run finished, every
        homogenisation point was reached and the last cascade succeeded."""
        if (self.macro is None or not self.macro.ok or self.error or not self.intervals
                or self.intervals[-1].s_end < self.s_final * (1.0 - 1e-6)):
            return math.nan
        return self.settings.mu_const + self.intervals[-1].mu_out

    @property
    def mu(self) -> float:
        """The point's mu: the stationary mean of the macro mu (module doc); nan where
        :attr:`mu_end` is (a loop that did not finish).  ``stationary`` says whether a window
        passed; if not, this is the last half's mean and the point says so in its notes."""
        return _mean(self.average) if np.isfinite(self.mu_end) else math.nan

    @property
    def stationary(self) -> bool:
        return self.average is not None and self.average.stationary

    @property
    def ok(self) -> bool:
        return np.isfinite(self.mu)


def _mean(avg: StationaryMean | None) -> float:
    return avg.mean if avg is not None else math.nan


def lower_mu(result: PointResult, rough: bool) -> float:
    """The lower scales' mu on the macro contact (without mu_const): the whole cascade's on the
    flat road; on the rough macro band the mu the cascade hands to its macro scale
    (``friction_in``: its scale below plus alpha mu_A, eq. 7.8), since the macro block is the
    macro scale there (its hysteresis on the band would count twice).  nan if the cascade failed."""
    if not rough:
        return _mu(result)
    if not result.ok or not result.scales:
        return math.nan
    return float(result.scales[0].friction_in)


def isothermal_macro(spec: SlidingSpec, rubber: Thermal, thermal: MacroSettings, friction: float,
                     wall_limit: float = 0.0) -> ThermalMacroResult:
    """The isothermal macro run of thesis 8.5.3 (rough road): constant ``friction``, the bulk at
    T0 (``bulk_wlf`` off): the heat field is computed but acts on nothing mechanical."""
    return run_thermal_macro(dataclasses.replace(spec, friction=friction), rubber,
                             dataclasses.replace(thermal, bulk_wlf=False), wall_limit=wall_limit)


def macro_average(macro: ThermalMacroResult | None, contact_mu: np.ndarray | None,
                  blocks: int, tol: float) -> StationaryMean | None:
    """The stationary mean of a macro run's mu: its F_x / F_z (``contact_mu`` None: the rough
    road) or the contact's mu per step (the flat road)."""
    if macro is None or not macro.series:
        return None
    y = macro.series["mu"] if contact_mu is None else contact_mu
    return stationary_mean(macro.series["s"], y, blocks, tol)


def average_note(what: str, avg: StationaryMean | None) -> str:
    """The point's note on its averaging window."""
    return f"{what}: {avg.describe()}" if avg is not None else f"{what}: no series to average"


def window_temperature_note(macro: ThermalMacroResult | None, avg: StationaryMean | None,
                            T0: float) -> str:
    """The contact temperature (eq. 8.1's mean over the active contact nodes, series
    ``T_active``) at the start and the end of the averaging window, against T0: the window's mu
    can pass the stationarity rule while the contact still warms (a flat part of the law, or a
    law diluted by mu_const), and the note says so.  Empty without a series or a window."""
    if (macro is None or not macro.series or "T_active" not in macro.series or avg is None
            or not math.isfinite(avg.lo)):
        return ""
    s, T = np.asarray(macro.series["s"], float), np.asarray(macro.series["T_active"], float)
    ok = np.isfinite(T)
    if not ok.any():
        return ""
    a, b = np.interp([avg.lo, avg.hi], s[ok], T[ok]) - T0
    return (f"contact temperature over the window (eq. 8.1): T0 {a:+.3g} K at s = {avg.lo:.4g} "
            f"mm, T0 {b:+.3g} K at {avg.hi:.4g} mm ({(b - a) / (avg.hi - avg.lo):+.2g} K/mm)")


def _mu(result: PointResult) -> float:
    return float(result.mu.mean) if result.ok and result.mu is not None else math.nan


#: a lower-scale run of a cascade: (branch, scale index, sample index)
RunSlot = tuple[str, int, int]


class LayeredSpecs:
    """The cascade's spec factory with temperature layers on every run (step C).

    Warm starts (``states``, a function of a store key giving that run's kept final state or
    None): every run keeps its final state if ``keep`` (a later cascade may start from it), and a
    run whose slot (branch, scale, sample) has a parent in ``parents`` (the store key of the same
    slot's run at the previous homogenisation point) slides on from the parent's state instead
    of from rest, comparing ``warm_window`` periods per block of its window rule where that is
    > 0 (``window.converged_window``)."""

    def __init__(self, make_spec: Callable[..., SlidingSpec], partitions: Partitions | None,
                 scales: Sequence[ScaleSet] = (), parents: dict[RunSlot, str] | None = None,
                 states: Callable[[str], dict | None] | None = None, warm_window: int = 0,
                 keep: bool = True):
        self.keep = keep
        self.make_spec, self.partitions = make_spec, partitions
        self.scales, self.parents, self.states = list(scales), dict(parents or {}), states
        self.warm_window = warm_window  # > 0: window_periods of a warm-started run
        self._loaded: dict[str, dict | None] = {}  # states read (plan() asks for them too)

    def __call__(self, point: Point, i: int, sample: Any, pressure: float, friction: Any,
                 branch: str) -> SlidingSpec:
        spec = self.make_spec(point, i, sample, pressure, friction, branch)
        if self.partitions is not None:  # the macro field over this block's height (8.3.3)
            layers, background = self.partitions.block(block_height(spec))
            spec = dataclasses.replace(spec, temperature_layers=layers, temperature=background)
        if self.states is None:
            return spec
        spec = dataclasses.replace(spec, keep_state=self.keep)
        index = next((n for n, s in enumerate(self.scales[i].samples) if s is sample), -1)
        key = self.parents.get((branch, i, index))
        if key and key not in self._loaded:
            self._loaded[key] = self.states(key)
        state = self._loaded.get(key) if key else None
        if state is None:
            return spec
        spec = dataclasses.replace(spec, initial_state=InitialState.stored(state, key))
        return dataclasses.replace(spec, window_periods=self.warm_window or spec.window_periods)


def block_height(spec: SlidingSpec) -> float:
    """The height of a lower-scale run's block (``sliding.model.geometry``'s rule: the given
    height, else the block length, else the period)."""
    return float(spec.block_height or spec.block_length or spec.period)


def run_slots(result: PointResult) -> dict[RunSlot, str]:
    """The store keys of a cascade's runs that finished (status ok) by slot: where the next
    homogenisation point's runs start from."""
    out = {}
    for runs in result.runs.values():
        for task, outcome in runs:
            if outcome.ok:
                lab = task.label
                out[(str(lab["branch"]), int(lab["scale"]), int(lab["sample"]))] = outcome.key
    return out


class CascadeRunner:
    """Runs one cascade of a point over all ranks (step D); rank 0 calls it, the workers wait in
    :meth:`serve` until rank 0 says "done".  ``progress``: None, or a function of the cascade's
    title returning a new progress display (``runtime.progress.Progress``) for each cascade.
    ``states``: warm starts (:class:`LayeredSpecs`), a function of a store key giving the final
    state that run kept (``runtime.store.Store.load_state``); None: every run from rest.
    ``warm_window`` > 0: the warm runs' periods per block of the window rule (1: faster, looser;
    scene key ``[thermal] warm_window_periods``)."""

    def __init__(self, campaign: str, point: Point, scales: Sequence[ScaleSet], make_spec,
                 k: int, j: int, execute, comm=None, progress=None,
                 max_failed_fraction: float = 0.25, adhesion: BellLaw | None = None,
                 states: Callable[[str], dict | None] | None = None, warm_window: int = 0):
        self.states, self.warm_window = states, warm_window
        # the scene's bell law: alpha mu_A on the top scale of every cascade
        self.adhesion = adhesion
        self.campaign, self.point, self.scales = campaign, point, list(scales)
        self.make_spec, self.k, self.j = make_spec, k, j
        self.execute, self.comm, self.progress = execute, comm, progress
        self.max_failed = max_failed_fraction
        self.count = 0

    def __call__(self, partitions: Partitions | None, parents: dict[RunSlot, str] | None = None,
                 keep: bool = True) -> PointResult:
        """One cascade with these temperature layers; with warm starts (``states``) its runs
        slide on from the final states of ``parents`` (slot -> store key, :func:`run_slots`)
        and keep their own final states if ``keep`` (False: no later cascade starts from them,
        and the store stays smaller; docs/performance.md)."""
        return self.many([partitions], parents, keep)[0]

    def many(self, partitions: Sequence[Partitions | None],
             parents: dict[RunSlot, str] | None = None, keep: bool = True) -> list[PointResult]:
        """Independent cascades of the point (the hot-layer grid), one per entry of
        ``partitions``, farmed as one campaign so that their runs fill all ranks; the results
        in that order."""
        planners = [RoughCascade(self.campaign, self.point, self.scales,
                                 LayeredSpecs(self.make_spec, parts, self.scales, parents,
                                              self.states, self.warm_window, keep),
                                 self.k, self.j,
                                 adhesion=self.adhesion, max_failed_fraction=self.max_failed)
                    for parts in partitions]
        if self.comm is not None and self.comm.Get_size() > 1:
            self.comm.bcast("cascade", root=0)
        first, last = self.count + 1, self.count + len(planners)
        title = f"cascade {first}" if first == last else f"cascades {first}-{last}"
        title += f" ({self.point.velocity:g} mm/s)" if self.point else ""
        progress = self.progress(title) if self.progress is not None else None
        run_farm(lambda: CampaignPlanner(planners), self.execute, progress, self.comm)
        self.count = last
        return [p.result for p in planners]

    def serve(self) -> None:
        """Worker ranks: take part in every cascade rank 0 starts, until it says done."""
        while self.comm.bcast(None, root=0) == "cascade":
            run_farm(lambda: None, self.execute, None, self.comm)

    def done(self) -> None:
        if self.comm is not None and self.comm.Get_size() > 1:
            self.comm.bcast("done", root=0)


class LoopObserver:
    """SlidingRun observer after the ThermalCoupler: stops at each homogenisation point, runs the
    cascade with the current profile and hands its mu to the macro contact (steps B-E)."""

    def __init__(self, coupler, distances: np.ndarray, settings: LoopSettings,
                 cascade: CascadeRunner, mu_start: float, log: Callable[[str], None] | None = None,
                 parents: dict[RunSlot, str] | None = None):
        self.coupler, self.distances, self.settings = coupler, distances, settings
        self.cascade, self.mu_start, self.log = cascade, mu_start, log
        self.start_parents = dict(parents or {})  # the isothermal cascade's runs (warm starts)
        self.parents = dict(self.start_parents)  # each slot's latest finished run
        self.intervals: list[Interval] = []
        self.error: str | None = None
        self.next = 0  # index of the next planned point

    def on_start(self, run) -> None:  # a fallback attempt starts the slide again
        self.intervals = []
        self.parents = dict(self.start_parents)
        self.error = None
        self.next = 0
        self.T_last = self.coupler.settings.T0
        self.mu_now = self.mu_start
        run.contact.set_friction(self.settings.mu_const + self.mu_start)

    def on_step(self, run, k: int, t: float) -> None:
        if self.error is not None:
            return
        try:
            self._step(run, t)
        except Exception as err:  # noqa: BLE001 -- reported: the loop's mu is nan, never silent
            self.error = f"{type(err).__name__}: {err}"

    def _step(self, run, t: float) -> None:
        i, auto = len(self.intervals), self.settings.auto_dT > 0
        if (self.next >= len(self.distances) or self.coupler.heat is None
                or self.coupler.error is not None):
            return
        s = float(run.spec.velocity) * (t - run.t_start)
        planned = s >= self.distances[self.next] - 1e-6 * max(1.0, self.distances[self.next])
        if not (planned or auto):
            return
        st = run.contact.state()
        active = self.coupler.interface_active(st)
        if not active.any():
            if planned and self.log:
                self.log(f"  point {i + 1}: no contact node active at s = {s:.4g} mm; mu kept")
            return
        _, z, T = self.coupler.heat.block_grid()
        profile = average_profile(z, T, active)
        if not planned:  # automatic: a point when the surface temperature moved by auto_dT
            if (abs(profile.mean[0] - self.T_last) < self.settings.auto_dT
                    or i + 1 >= self.settings.max_points):
                return
        else:
            self.next += 1
        self.T_last = float(profile.mean[0])
        parts = partition_profile(profile, self.settings.n_partitions,
                                  self.settings.partition_depth)
        wall = time.perf_counter()
        last = planned and self.next == len(self.distances)  # no later point starts from it
        result = self.cascade(parts, self.parents, keep=not last)
        self.parents.update(run_slots(result))  # a slot whose run failed keeps its last state
        wall = time.perf_counter() - wall
        run.exclude_from_wall_limit(wall)  # the macro run's wall clock counts its own work only
        mu_out = lower_mu(result, self.settings.rough)
        iv = Interval(i + 1, s, t, self.mu_now, profile, parts, result, mu_out, wall)
        self.intervals.append(iv)
        if self.log:
            temps = ", ".join(f"{T_:.1f}" for _, T_ in parts.layers)
            state = (f"mu {mu_out:.4g}" if np.isfinite(mu_out)
                     else f"cascade failed ({result.reason}); mu kept")
            self.log(f"  point {i + 1}{'' if auto else f'/{len(self.distances)}'} at "
                     f"s = {s:.4g} mm: surface {profile.mean[0]:.2f} K (std {profile.std[0]:.2f}, "
                     f"{profile.n_active} nodes), partitions [{temps}] K -> {state} "
                     f"({wall:.1f} s)")
        if np.isfinite(mu_out):
            self.mu_now = mu_out
            run.contact.set_friction(self.settings.mu_const + mu_out)


def isothermal_partitions(spec: SlidingSpec, thermal: MacroSettings, loop: LoopSettings
                          ) -> Partitions:
    """The isothermal cascade's layers: T0 on the partition bounds of the later cascades (layer
    bounds are mesh lines of the lower-scale blocks: the same meshes in every cascade, only
    temperatures differ), from the macro block's levels (``spec``: the macro run)."""
    levels = block_levels(spec.block_height, thermal.first_layer, thermal.grading)
    return uniform_partitions(levels, loop.n_partitions, loop.partition_depth, thermal.T0)


def run_thermal_loop(spec: SlidingSpec, rubber: Thermal, thermal: MacroSettings,
                     loop: LoopSettings, cascade: CascadeRunner, *, wall_limit: float = 0.0,
                     log: Callable[[str], None] | None = None) -> ThermalLoopResult:
    """The loop of the module docstring for one point on rank 0 (``spec``: the macro run; its
    friction is replaced).  The workers of ``cascade.comm`` must be in ``cascade.serve()``;
    :meth:`CascadeRunner.done` releases them (the caller's job, after its last point)."""
    wall = time.perf_counter()
    iso = cascade(isothermal_partitions(spec, thermal, loop))  # A: isothermal mu(T0)
    out = ThermalLoopResult(cascade.point, iso, None, settings=loop,
                            wall_isothermal=time.perf_counter() - wall)
    mu0 = lower_mu(iso, loop.rough)
    if not np.isfinite(mu0):
        out.notes.append(f"isothermal cascade failed: {iso.reason}")
        out.wall = time.perf_counter() - wall
        return out
    if log:
        log(f"  isothermal mu(T0) = {mu0:.4g} (+ mu_const {loop.mu_const:g})")
    distances = loop.distances(spec.slide_distance)
    out.s_final = float(distances[-1])
    spec = dataclasses.replace(spec, friction=loop.mu_const + mu0)
    coupler = ThermalCoupler(rubber, thermal)
    observer = LoopObserver(coupler, distances, loop, cascade, mu0, log, run_slots(iso))
    out.macro = run_thermal_macro(spec, rubber, thermal, observers=(observer,),
                                  wall_limit=wall_limit, coupler=coupler)
    out.intervals = observer.intervals
    if observer.error is not None:
        out.error = f"thermal loop stopped at point {len(out.intervals) + 1}: {observer.error}"
        out.notes.append(out.error)
    elif not out.intervals or out.intervals[-1].s_end < out.s_final * (1.0 - 1e-6):
        out.notes.append(f"the slide's end (s = {out.s_final:g} mm) was not reached as a "
                         "homogenisation point "
                         f"({out.macro.sliding.reason or 'no active contact there'})")
    if loop.rough:
        out.average = macro_average(out.macro, None, loop.blocks, loop.tol)
        out.iso_macro = isothermal_macro(spec, rubber, thermal, loop.mu_const + mu0, wall_limit)
        out.iso_average = macro_average(out.iso_macro, None, loop.blocks, loop.tol)
        out.notes.append(average_note("isothermal macro mu", out.iso_average))
    else:
        blocks = (len(distances) if not loop.points and loop.auto_dT == 0 else loop.blocks)
        out.average = macro_average(out.macro, contact_steps(out), blocks, loop.tol)
    out.notes.append(average_note("macro mu", out.average))
    if note := window_temperature_note(out.macro, out.average, thermal.T0):
        out.notes.append(note)
    out.wall = time.perf_counter() - wall
    return out


def contact_steps(res: ThermalLoopResult) -> np.ndarray | None:
    """The flat road's macro mu per macro step: mu_const + the lower scales' mu of the interval
    (s_i-1, s_i] the step ends in, the cascade's at s_i (its mu_in where that cascade failed);
    nan beyond the last point.  With the points at equal divisions these are the blocks of the
    stationary mean: its rule compares the last points' mu."""
    if res.macro is None or not res.macro.series:
        return None
    s = res.macro.series["s"]
    ends = np.array([iv.s_end for iv in res.intervals])
    vals = np.array([iv.mu_out if np.isfinite(iv.mu_out) else iv.mu_in for iv in res.intervals])
    k = np.searchsorted(ends * (1 + 1e-9) + 1e-12, s)
    y = np.full(s.shape, math.nan)
    inside = k < len(ends)
    y[inside] = res.settings.mu_const + vals[k[inside]]
    return y


# ----------------------------------------------------------------------------------------------
# hot-layer mode (thesis 8.5.3): the lower scales once, for a grid of surface temperatures
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class HotLayerSettings:
    """Surface temperatures T_S - T0 of the grid (K, increasing, the first 0: the isothermal
    point), the hot layer's thickness (T_S) and the depth of the second partition (at
    T_1 = (T_S + T0) / 2), mm; ``mu_const`` as in the coupled loop.  Thesis 8.5.3: 5 and 20 um."""

    rises: tuple[float, ...] = (0.0, 5.0, 10.0, 20.0, 40.0, 80.0)
    layer: float = 0.005
    transition: float = 0.020
    mu_const: float = 0.0
    rough: bool = False  # the macro block on the rough macro band (module doc)
    blocks: int = STATIONARY_BLOCKS  # the stationary mean's blocks of the slide
    tol: float = 0.01  # and its tolerance (relative)

    def __post_init__(self) -> None:
        V.integer("blocks", self.blocks, minimum=1)
        V.positive("tol", self.tol)
        r = np.asarray(self.rises, float)
        if r.size < 2 or r[0] != 0.0 or np.any(np.diff(r) <= 0):
            raise V.InputError(f"rises = {list(self.rises)!r} K: expected at least two "
                               "increasing values starting at 0 (the isothermal point)")
        V.positive("layer", self.layer, "mm")
        if not self.layer < self.transition:
            raise V.InputError(f"layer = {self.layer!r} mm, transition = {self.transition!r} mm: "
                               "expected 0 < layer < transition")
        V.nonnegative("mu_const", self.mu_const)


def hot_layer_partitions(T_S: float, T0: float, settings: HotLayerSettings) -> Partitions:
    """The hot layer of fig. 8.17 b: T_S over ``layer``, T_1 = (T_S + T0) / 2 down to
    ``transition``, T0 below."""
    layers = ((settings.layer, float(T_S)),
              (settings.transition - settings.layer, 0.5 * (T_S + T0)))
    return Partitions(layers, float(T0), np.array([0.0, settings.layer, settings.transition]))


@dataclass
class HotLayerResult:
    point: Point
    temperatures: np.ndarray  # T_S grid, K
    mu_lower: np.ndarray  # the lower scales' mu at each T_S (nan where the cascade failed)
    cascades: list[PointResult]
    macro: ThermalMacroResult | None
    settings: HotLayerSettings
    wall: float = math.nan
    notes: list[str] = field(default_factory=list)
    law: Any = None  # mu_const + mu_lower as mu(p, v, T), linear in T (the macro run's friction)
    T_law_max: float = math.nan  # the law's highest surface temperature, K (never used beyond)
    error: str = ""  # the point was refused (the contact beyond the extended law)
    average: StationaryMean | None = None  # the point's mu: stationary mean of the macro mu
    iso_macro: ThermalMacroResult | None = None  # rough road: the isothermal macro run
    iso_average: StationaryMean | None = None  # and its stationary mean

    @property
    def mu_isothermal(self) -> float:
        """Flat road: mu_const + the isothermal cascade's mu; rough road: the stationary mean of
        the isothermal macro run's F_x / F_z."""
        if self.settings.rough:
            return _mean(self.iso_average)
        return self.settings.mu_const + float(self.mu_lower[0])

    @property
    def mu_end(self) -> float:
        """The macro contact's mu at the end of the slide: mu_const + the mu(T_S) law at the macro
        run's contact temperature then (``T_contact``, pressure-weighted over the contact nodes).
        Not F_x / F_z of the macro block, which on the flat road adds the block's own hysteresis
        and edge effects (on the two-scale test case as large as the lower scales' change for a
        10 K rise; docs/verification.md).  nan for a refused point (``error``)."""
        if self.error or self.macro is None or not self.macro.ok or not self.macro.series:
            return math.nan
        T_c = self.macro.series["T_contact"][-1]
        return float(self.law(self.point.pressure, self.point.velocity, T_c))

    def contact_mu(self) -> np.ndarray | None:
        """The flat road's macro mu per macro step: the law at the surface temperature T_S of
        eq. (8.1), the plain mean over the contact nodes (series ``T_active``)."""
        if self.macro is None or not self.macro.series:
            return None
        p, v = self.point.pressure, self.point.velocity
        return np.array([float(self.law(p, v, T)) if np.isfinite(T) else math.nan
                         for T in self.macro.series["T_active"]])

    @property
    def mu(self) -> float:
        """The point's mu: the stationary mean of the macro mu (module doc): F_x / F_z on the rough
        road, :meth:`contact_mu` on the flat one; nan unless the macro run finished within the
        law (a refused point: ``error``).  ``stationary`` says whether a window passed (if not:
        the last half's mean, noted)."""
        if self.error or self.macro is None or not self.macro.ok or not self.macro.series:
            return math.nan
        return _mean(self.average)

    @property
    def stationary(self) -> bool:
        return self.average is not None and self.average.stationary

    @property
    def ok(self) -> bool:
        return np.isfinite(self.mu)


#: extensions of the hot-layer grid when the macro contact got hotter than its highest T_S
#: (:func:`run_hot_layer`): each adds one cascade at twice the largest rise
MAX_LAW_EXTENSIONS = 2

#: the largest bound, relative to the point's mu, on what the contact nodes hotter than the
#: extended law can change (:func:`law_tail_bound`); beyond it the point is refused
LAW_TAIL_TOL = 0.01


def run_hot_layer(spec: SlidingSpec, rubber: Thermal, thermal: MacroSettings,
                  hot: HotLayerSettings, cascade: CascadeRunner, *, wall_limit: float = 0.0,
                  log: Callable[[str], None] | None = None) -> HotLayerResult:
    """Hot-layer mode: one cascade per surface temperature (independent: farmed together over all
    ranks, every run from rest), a mu(T_S) law (linear in T between the grid points), then the
    thermomechanical macro run with that law: mu follows the computed surface temperature node
    by node, with no down-passing.  The point's mu: the module doc's stationary mean (flat road:
    of the law at eq. 8.1's T_S per step; rough: of F_x / F_z, beside the isothermal macro run's).

    The law is never used beyond its highest surface temperature T_top (the spline would hold
    mu(T_top) there, which is no physics): when the hottest contact node of the macro run
    (stats ``T_contact_max``) exceeds T_top, the grid gains a cascade at twice the largest rise
    and the macro run is redone with the extended law, at most ``MAX_LAW_EXTENSIONS`` times
    (noted).  A run still beyond it is accepted only when the normal load on the nodes beyond
    bounds their effect on the point's mu within ``LAW_TAIL_TOL`` (:func:`law_tail_verdict`;
    the flash case's block corner, a few per cent of the load at the leading edge); otherwise,
    or when an extension's cascade failed, the point is refused (``error``, status failed,
    :func:`law_refusal`).

    No warm starts here: no physical path joins the grid's steady states, and slid on from the
    T0 cascade's states the default road's micro runs at 1 m/s went astray (docs/performance.md;
    README "Flash temperature on the default road")."""
    wall = time.perf_counter()
    T0 = thermal.T0
    temps = T0 + np.asarray(hot.rises, float)
    results = cascade.many([hot_layer_partitions(T_S, T0, hot) for T_S in temps])  # side by side
    mus = [lower_mu(r, hot.rough) for r in results]
    if log:
        for T_S, r, mu in zip(temps, results, mus):
            _log_hot_cascade(log, T_S, r, mu)
    out = HotLayerResult(cascade.point, temps, np.array(mus), results, None, hot)
    good = np.isfinite(out.mu_lower)
    if not good[0] or good.sum() < 2:
        out.notes.append("the isothermal or too many hot-layer cascades failed: no mu(T_S) law")
        out.wall = time.perf_counter() - wall
        return out
    if not good.all():
        out.notes.append(f"{int((~good).sum())} hot-layer cascades failed; the law interpolates "
                         "over them")
    _hot_layer_macro(out, spec, rubber, thermal, wall_limit)
    beyond = ""  # the refusal, unless the nodes beyond the extended law are shown not to matter
    while True:
        T_seen = out.macro.stats.get("T_contact_max", math.nan)
        if not law_exceeded(out.T_law_max, T_seen):
            break
        added = out.temperatures[len(hot.rises):] - T0
        if added.size >= MAX_LAW_EXTENSIONS:
            beyond = law_refusal(T_seen, out.T_law_max, T0, added)
            break
        T_S = T0 + 2.0 * (out.temperatures[-1] - T0)
        r = cascade.many([hot_layer_partitions(T_S, T0, hot)])[0]
        mu = lower_mu(r, hot.rough)
        if log:
            log(f"  the contact reached T0 {T_seen - T0:+.3g} K, above the law's T0 "
                f"{out.T_law_max - T0:+.3g} K: the grid gains T_S = T0 {T_S - T0:+.3g} K")
            _log_hot_cascade(log, T_S, r, mu)
        out.temperatures = np.append(out.temperatures, T_S)
        out.mu_lower = np.append(out.mu_lower, mu)
        out.cascades.append(r)
        if not np.isfinite(mu):
            out.error = (f"refused: the contact reached T0 {T_seen - T0:+.3g} K, above the "
                         f"hot-layer law's highest surface temperature T0 "
                         f"{out.T_law_max - T0:+.3g} K, and the cascade extending it to T0 "
                         f"{T_S - T0:+.3g} K failed ({r.reason}); add higher "
                         "[thermal].hot_layer_rises values")
            break
        _hot_layer_macro(out, spec, rubber, thermal, wall_limit)
        out.notes.append(f"the hot-layer law was extended to T0 {T_S - T0:+.3g} K: the contact "
                         f"had reached T0 {T_seen - T0:+.3g} K")
    if hot.rough:
        out.average = macro_average(out.macro, None, hot.blocks, hot.tol)
        m0 = hot.mu_const + float(out.mu_lower[0])
        out.iso_macro = isothermal_macro(spec, rubber, thermal, m0, wall_limit)
        out.iso_average = macro_average(out.iso_macro, None, hot.blocks, hot.tol)
        out.notes.append(average_note("isothermal macro mu", out.iso_average))
    else:
        out.average = macro_average(out.macro, out.contact_mu(), hot.blocks, hot.tol)
    if beyond and not out.error:
        out.error = law_tail_verdict(out, beyond)
    if out.error:
        out.notes.append(out.error)
    out.notes.append(average_note("macro mu", out.average))
    if note := window_temperature_note(out.macro, out.average, T0):
        out.notes.append(note)
    out.wall = time.perf_counter() - wall
    return out


def _log_hot_cascade(log: Callable[[str], None], T_S: float, r: PointResult, mu: float) -> None:
    log(f"  hot layer T_S = {T_S:.2f} K: lower scales' mu {mu:.4g} "
        f"({r.wall_time:.1f} s of runs)")


def _hot_layer_macro(out: HotLayerResult, spec: SlidingSpec, rubber: Thermal,
                     thermal: MacroSettings, wall_limit: float) -> None:
    """The mu(T_S) law through the grid's good cascades (mu_const added) and the macro run with
    it, into ``out`` (law, T_law_max, macro)."""
    from rubberfriction.driver.fe.friction_law import fit_mu_pvT

    good = np.isfinite(out.mu_lower)
    T, m = out.temperatures[good], out.settings.mu_const + out.mu_lower[good]
    grid = np.broadcast_to(m, (2, 2, T.size)).copy()  # constant in p and v
    out.law = fit_mu_pvT([0.0, 1.0e3], [1.0e-9, 1.0e7], T, grid, degree=1)
    out.T_law_max = float(T.max())
    out.macro = run_thermal_macro(dataclasses.replace(spec, friction=out.law), rubber, thermal,
                                  wall_limit=wall_limit)


def load_share_above(macro: ThermalMacroResult | None, T_top: float, lo: float,
                     hi: float) -> float:
    """The mean over the macro steps with lo <= s <= hi of the share of the contact's normal load
    on slave nodes hotter than ``T_top`` (``contact_loads``); nan without them."""
    if macro is None or not macro.contact_loads or not macro.series:
        return math.nan
    rows = _window_rows(macro.series["s"], lo, hi)
    loads = macro.contact_loads
    T, load = np.asarray(loads["T"], float)[rows], np.asarray(loads["load"], float)[rows]
    total = load.sum(axis=1)
    carried = total > 0.0
    if not carried.any():
        return math.nan
    hot = np.where(T > T_top, load, 0.0).sum(axis=1)
    return float(np.mean(hot[carried] / total[carried]))


def _window_rows(s: Any, lo: float, hi: float) -> np.ndarray:
    """The macro series rows with lo <= s <= hi (the averaging window's steps)."""
    s = np.asarray(s, float)
    return (s >= lo - 1e-12) & (s <= hi + 1e-12)


def law_tail_bound(share: float, mu_lower: np.ndarray) -> float:
    """How far the contact nodes beyond the law can move mu (absolute): there the macro run holds
    the law's top value mu_const + m_top, while the true value lies between mu_const and it
    when the lower scales' mu falls with T_S at the top of the grid and stays >= 0 (hysteresis):
    |d mu| <= share m_top, with ``share`` the normal load's share on those nodes.  On the rough
    road that bounds F_x / F_z; on the flat road the macro contact's friction, hence its heat.
    inf when the law rises at its top (no bound)."""
    m = np.asarray(mu_lower, float)
    m = m[np.isfinite(m)]
    if m.size < 2 or m[-1] > m[-2] or not math.isfinite(share):
        return math.inf
    return share * max(float(m[-1]), 0.0)


def law_tail_verdict(out: HotLayerResult, refusal: str) -> str:
    """After the last extension: '' (accepted, with a note) when the nodes beyond the law carry
    too little load to move the point's mu by more than LAW_TAIL_TOL (:func:`law_tail_bound`),
    else ``refusal`` with that bound."""
    avg = out.average
    mu = _mean(avg)
    window = avg is not None and math.isfinite(avg.lo)
    share = load_share_above(out.macro, out.T_law_max, avg.lo, avg.hi) if window else math.nan
    bound = law_tail_bound(share, out.mu_lower)
    T0 = out.temperatures[0]
    if window and not out.settings.rough:
        T = np.asarray(out.macro.series.get("T_active", []), float)
        T = T[_window_rows(out.macro.series["s"], avg.lo, avg.hi)] if T.size else T
        if T.size and np.nanmax(T) > out.T_law_max:
            return (f"{refusal}; the point's own contact temperature (eq. 8.1) reached T0 "
                    f"{np.nanmax(T) - T0:+.3g} K in the averaging window")
    what = (f"{100 * share:.3g} % of the normal load over the averaging window lay on contact "
            f"nodes hotter than the law's T0 {out.T_law_max - T0:+.3g} K, where the macro run "
            f"held its top value") if math.isfinite(share) else "no contact-load history"
    if math.isfinite(mu) and mu > 0.0 and bound <= LAW_TAIL_TOL * mu:
        out.notes.append(f"{what}: the true mu there lies between mu_const and it, so those nodes "
                         f"move mu by at most {bound:.3g} ({100 * bound / mu:.2g} %, accepted "
                         f"within {100 * LAW_TAIL_TOL:g} %)")
        return ""
    return (f"{refusal}; {what}, a bound of {bound:.3g} on mu, above "
            f"{100 * LAW_TAIL_TOL:g} % of it")


def law_exceeded(T_top: float, T_seen: float) -> bool:
    """Whether the macro contact's hottest node ``T_seen`` lies above the hot-layer law's highest
    surface temperature ``T_top`` (K; beyond 1e-9 K; a nan never does)."""
    return math.isfinite(T_seen) and T_seen > T_top + 1e-9


def law_refusal(T_seen: float, T_top: float, T0: float, added: np.ndarray) -> str:
    """The one-line reason of a hot-layer point refused after ``MAX_LAW_EXTENSIONS``."""
    rises = ", ".join(f"{r:+.3g}" for r in added)
    return (f"refused: the contact reached T0 {T_seen - T0:+.3g} K, above the hot-layer law's "
            f"highest surface temperature T0 {T_top - T0:+.3g} K after {len(added)} extensions "
            f"(T0 {rises} K); add higher [thermal].hot_layer_rises values")
