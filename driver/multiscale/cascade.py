"""Multiscale homogenisation: which single-scale runs to do, and how their results combine.

Two variants of thesis ch. 6, each a *planner* for :mod:`.farm` (it hands out the runs whose
inputs are known and is told their outcomes; the farm decides where they run):

Rough road surfaces, thesis 6.3.2 (fig. 6.7, 6.8) -- :class:`RoughCascade`, any number of scales
i = 0 (macro) .. n-1 (finest), one (p, v, compound) point:

1. **pressure down** (frictionless branch): on scale i, k surface samples run frictionless at
   the pressure p_i (p_0 = p, the global pressure).  Each gives its mean contact pressure over
   contact nodes and time steps, eq. (6.11), ``SlidingResult.mean_pressure``; the sample
   average is the pressure of the next scale, eq. (6.12):
   ``p_{i+1} = (1/n_k) sum_k p_avg,i(k)``.  Scales 0 .. n-2.
2. **friction up** (frictional branch): on the finest scale, j samples run frictionless at
   p_{n-1}; their time-homogenised coefficients of friction mu_avg(j) (eq. 6.2, from the
   reaction forces) are averaged over samples, eq. (6.13): ``mu_{n-1} = (1/n_j) sum_j mu_avg(j)``.
   On every coarser scale i = n-2 .. 0, j samples run at p_i *with the Coulomb coefficient
   mu_{i+1}* of the scale below ("the incorporation of the homogenized microscopic friction
   response simplifies ... to a setting of the macroscopic coefficient of friction to
   mu_avg", thesis 6.3.2 step G) and eq. (6.13) averages them to mu_i.  The result is mu_0.
   The combination across scales is therefore *not* a sum of per-scale numbers: each scale's
   run carries the finer scales' friction in its contact law and adds its own hysteresis and
   interlocking on top; mu_i is the "overall" coefficient of fig. 6.29 a.
   Full slip: the global velocity v is applied on every scale (thesis 6.3.2).
3. **contact area** (eq. 7.4, 7.5): the time-averaged contact fraction of each sample,
   averaged over samples; macro from its frictionless runs, finer scales from their friction
   runs (as the thesis does for adhesion); the overall relative contact area is the product
   ``A_r = prod_i A_i,c/A_i,0``.
4. **adhesion** (optional, thesis 7.3, eq. 7.6-7.8): the macro friction runs use
   ``mu* = mu_1 + alpha tau_A(v) A_r / p`` instead of mu_1.

Separated scales, thesis 6.2 (fig. 6.1) -- :class:`SeparatedTwoScale`, two scales: a frictionless
macro run gives the mean contact pressure (step B); micro runs on a (p, v) grid around it (step
C, D) are time-homogenised (step E, eq. 6.2) and a smooth tensor-product spline mu_2(p, v),
eq. (6.6), is fitted to them (step F); the macro run with that law inside the contact (step G,
weak form 6.4) gives mu_1.  Optionally the single-scale reference on the full profile runs
alongside (thesis 6.2.3, fig. 6.4).

Sample statistics (:func:`sample_stats`): mean, standard deviation, 95 % confidence interval
of the mean (Student t) over the samples that succeeded; failed samples are excluded *visibly*
(each average says how many samples it used) and a scale with too many failures is flagged.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from rubberfriction.driver.runtime.farm import Task
from rubberfriction.driver.runtime.store import Outcome, run_key

# ----------------------------------------------------------------------------------------------
# plain data
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Point:
    """One global operating point (compound, p in MPa, v in mm/s)."""

    compound: str
    pressure: float
    velocity: float

    @property
    def id(self) -> str:
        return f"{self.compound}/p={self.pressure:g}/v={self.velocity:g}"


@dataclass(frozen=True)
class ScaleSet:
    """One scale: name, band (lambda_long, lambda_short) in mm and its periodic samples.

    A sample is anything with ``x`` (0 .. period, endpoint included), ``h`` (h[-1] == h[0]) and
    ``period`` -- a :class:`~rubberfriction.driver.surfaces.SurfaceSample`.
    """

    name: str
    band: tuple[float, float]
    samples: tuple[Any, ...]


#: make_spec(point, scale_index, sample, pressure, friction, role) -> SlidingSpec.
#: role: "down" | "up" (cascade), "macro0" | "micro" | "macro" | "reference" (separated).
SpecFactory = Callable[[Point, int, Any, float, Any, str], Any]


@dataclass(frozen=True)
class SampleStats:
    """Average over surface samples with its spread; ``values`` keeps NaN for failed samples."""

    values: tuple[float, ...]
    mean: float
    std: float  # sample standard deviation (ddof = 1), NaN for one sample
    ci95: float  # half width of the 95 % confidence interval of the mean (Student t), NaN for one
    n_used: int
    n_failed: int

    @property
    def n_total(self) -> int:
        return self.n_used + self.n_failed

    @property
    def failed_fraction(self) -> float:
        return self.n_failed / self.n_total if self.n_total else 0.0

    def as_dict(self, prefix: str) -> dict[str, float]:
        return {prefix: self.mean, f"{prefix}_std": self.std, f"{prefix}_ci95": self.ci95,
                f"{prefix}_n_used": self.n_used, f"{prefix}_n_failed": self.n_failed}


def sample_stats(values: Sequence[float]) -> SampleStats:
    """Mean, standard deviation and 95 % CI over the finite values (eq. 6.12 / 6.13 averages).

    Non-finite values are failed samples: excluded from the average and counted in n_failed.
    """
    from scipy import stats

    v = np.asarray(values, dtype=float)
    ok = v[np.isfinite(v)]
    n = int(ok.size)
    mean = float(ok.mean()) if n else math.nan
    std = float(ok.std(ddof=1)) if n > 1 else math.nan
    ci = float(stats.t.ppf(0.975, n - 1) * std / math.sqrt(n)) if n > 1 else math.nan
    return SampleStats(tuple(float(x) for x in v), mean, std, ci, n, int(v.size - n))


def _values(outcomes: Sequence[Outcome], name: str) -> SampleStats:
    """Sample statistics of one result scalar (failed runs count as failed samples)."""
    return sample_stats([o.value(name) if o.ok else math.nan for o in outcomes])


def _first_line(reason: str) -> str:
    return reason.splitlines()[0] if reason else "no reason"


def mean_contact_pressure(outcomes: Sequence[Outcome]) -> SampleStats:
    """Pressure passed to the next scale, eq. (6.12), from each sample's eq. (6.11) value."""
    return sample_stats([o.value("mean_pressure") if o.ok else math.nan for o in outcomes])


def friction_average(outcomes: Sequence[Outcome], quantity: str = "mu_force") -> SampleStats:
    """Sample-averaged homogenised coefficient of friction, eq. (6.13) (``mu_force``: eq. 6.2)."""
    return sample_stats([o.value(quantity) if o.ok else math.nan for o in outcomes])


def relative_contact_area(fractions: Sequence[float]) -> float:
    """Overall relative contact area A_r = prod_i A_i,c / A_i,0, eq. (7.5)."""
    return float(np.prod(np.asarray(fractions, dtype=float)))


def adhesion_mu(tau0: float, c: float, v0: float, alpha: float, v: float, p: float,
                area_ratio: float) -> float:
    """alpha mu_A = alpha tau_A(v) A_r / p, eqs. (7.6), (7.7) (the share added in eq. 7.8)."""
    from rubberfriction.driver.theory.adhesion import BellLaw, mu_adhesion

    return float(alpha * mu_adhesion(BellLaw(tau0, c, v0), v, p, min(max(area_ratio, 0.0), 1.0)))


@dataclass(frozen=True)
class AdhesionLaw:
    """Bell law parameters (eq. 7.6) and the dry/wet share alpha (eq. 7.8)."""

    tau0: float
    c: float
    v0: float
    alpha: float


# ----------------------------------------------------------------------------------------------
# rough-surface cascade (thesis 6.3.2)
# ----------------------------------------------------------------------------------------------


@dataclass
class ScaleResult:
    """Per-scale quantities of one point (thesis fig. 6.29 a, b)."""

    index: int
    name: str
    band: tuple[float, float]
    pressure: float = math.nan  # p_i applied on this scale (eq. 6.12 from above; p on macro)
    pressure_spread: SampleStats | None = None  # the samples of the scale above that gave p_i
    pressure_down: SampleStats | None = None  # this scale's eq. (6.11) values (-> p_{i+1})
    friction_in: float = math.nan  # Coulomb mu in this scale's friction runs (mu_{i+1}; 0 finest)
    mu: SampleStats | None = None  # overall mu_i, eq. (6.13)
    mu_energy: SampleStats | None = None  # the same from dissipated energy
    contact: SampleStats | None = None  # contact fraction A_i,c / A_i,0 (eq. 7.4)
    area_ratio: float = math.nan  # overall A_r of scales 0..i (eq. 7.5)
    dissipation: SampleStats | None = None  # mu_energy x p_i: energy / sliding length / area
    flagged: bool = False
    notes: list[str] = field(default_factory=list)


@dataclass
class PointResult:
    """Result of one operating point."""

    point: Point
    variant: str
    status: str = "running"  # "ok" | "failed"
    reason: str = ""
    mu: SampleStats | None = None  # the global coefficient of friction
    mu_adhesion: float = math.nan  # alpha mu_A added on the macro scale (eq. 7.8)
    area_ratio: float = math.nan
    scales: list[ScaleResult] = field(default_factory=list)
    runs: dict[str, list[tuple[Task, Outcome]]] = field(default_factory=dict)  # stage -> runs
    extra: dict[str, Any] = field(default_factory=dict)  # separated variant: law, reference, times

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def wall_time(self) -> float:
        return float(sum(o.wall_time for runs in self.runs.values() for _, o in runs))


class RoughCascade:
    """Planner of one point of the rough-surface cascade (see the module docstring)."""

    def __init__(self, campaign: str, point: Point, scales: Sequence[ScaleSet],
                 make_spec: SpecFactory,
                 k: int, j: int, *, adhesion: AdhesionLaw | None = None,
                 max_failed_fraction: float = 0.25,
                 mu_quantity: str = "mu_force"):
        n = len(scales)
        if n < 1:
            raise ValueError("a cascade needs at least one scale")
        for s in scales:
            need = j if s is scales[-1] else max(k, j)
            if len(s.samples) < need:
                raise ValueError(f"scale {s.name}: {len(s.samples)} samples, the cascade needs "
                                 f"{need}")
        self.campaign, self.point, self.scales = campaign, point, list(scales)
        self.make_spec, self.k, self.j = make_spec, k, j
        self.adhesion, self.max_failed = adhesion, max_failed_fraction
        self.mu_quantity = mu_quantity
        self.result = PointResult(point, "rough",
                                  scales=[ScaleResult(i, s.name, tuple(s.band)) for i,
                                          s in enumerate(scales)])
        self.result.scales[0].pressure = point.pressure
        self.n = n
        # down stages 0..n-2 (and stage 0 for the macro contact area when adhesion is on)
        self.down_scales = list(range(n - 1)) if n > 1 else ([0] if adhesion else [])
        self._stage: tuple[str, int] | None = ("down", 0) if self.down_scales else ("up", n - 1)
        self._issued = False
        self._collected: list[tuple[int, Task, Outcome] | None] = []
        if not self.down_scales:
            self._enter_up(n - 1)

    # --- planner protocol --------------------------------------------------------------------
    def total(self) -> int:
        return len(self.down_scales) * self.k + self.n * self.j

    def next_tasks(self) -> list[Task]:
        if self._stage is None or self._issued:
            return []
        branch, i = self._stage
        count = self.k if branch == "down" else self.j
        sc = self.result.scales[i]
        friction = float(sc.friction_in) if branch == "up" and sc.friction_in > 0 else None
        tasks = []
        for s in range(count):
            spec = self.make_spec(self.point, i, self.scales[i].samples[s], sc.pressure, friction,
                                  branch)
            label = {"campaign": self.campaign, "point": self.point.id,
                     "compound": self.point.compound,
                     "pressure": self.point.pressure, "velocity": self.point.velocity,
                     "branch": branch,
                     "scale": i, "scale_name": self.scales[i].name, "sample": s,
                     "pressure_in": sc.pressure,
                     "friction_in": 0.0 if friction is None else float(friction)}
            tasks.append(Task(run_key(spec), spec, label))
        self._collected = [None] * count
        self._issued = True
        return tasks

    def record(self, task: Task, outcome: Outcome) -> None:
        s = int(task.label["sample"])
        self._collected[s] = (s, task, outcome)
        if any(c is None for c in self._collected):
            return
        branch, i = self._stage  # type: ignore[misc]
        done = [c for c in self._collected if c is not None]
        self.result.runs[f"{branch}:{i}"] = [(t, o) for _, t, o in done]
        outcomes = [o for _, _, o in done]
        self._issued = False
        if branch == "down":
            self._down_done(i, outcomes)
        else:
            self._up_done(i, outcomes)

    @property
    def finished(self) -> bool:
        return self._stage is None

    # --- stage logic ---------------------------------------------------------------------------
    def _flag(self, sc: ScaleResult, stats: SampleStats, what: str) -> None:
        if stats.n_failed:
            sc.notes.append(f"{what}: {stats.n_failed} of {stats.n_total} samples failed")
        if stats.failed_fraction > self.max_failed:
            sc.flagged = True

    def _fail(self, reason: str) -> None:
        self.result.status, self.result.reason = "failed", reason
        self._stage = None

    def _down_done(self, i: int, outcomes: list[Outcome]) -> None:
        sc = self.result.scales[i]
        st = mean_contact_pressure(outcomes)  # eq. (6.11) per sample, (6.12) over samples
        sc.pressure_down = st
        sc.contact = _values(outcomes, "contact_fraction")
        self._flag(sc, st, "pressure branch")
        if st.n_used == 0:
            return self._fail(f"scale {sc.name}: all {st.n_total} pressure samples failed "
                              f"({_first_line(outcomes[0].reason)})")
        if i + 1 < self.n:
            nxt = self.result.scales[i + 1]
            nxt.pressure, nxt.pressure_spread = st.mean, st
        if i + 1 in self.down_scales:
            self._stage = ("down", i + 1)
        else:
            self._enter_up(self.n - 1)

    def _enter_up(self, i: int) -> None:
        """Friction branch on scale i: Coulomb mu of the scale below (0 on the finest scale),
        plus the adhesive share on the macro scale when adhesion is on (eq. 7.5-7.8)."""
        sc = self.result.scales[i]
        below = self.result.scales[i + 1].mu if i < self.n - 1 else None
        sc.friction_in = below.mean if below is not None else 0.0
        if i == 0 and self.adhesion is not None:
            a = self.adhesion
            A_r = relative_contact_area([s.contact.mean if s.contact else math.nan
                                         for s in self.result.scales])
            self.result.mu_adhesion = adhesion_mu(a.tau0, a.c, a.v0, a.alpha, self.point.velocity,
                                                  self.point.pressure, A_r)
            sc.friction_in += self.result.mu_adhesion  # eq. (7.8)
        self._stage = ("up", i)

    def _up_done(self, i: int, outcomes: list[Outcome]) -> None:
        sc = self.result.scales[i]
        st = friction_average(outcomes, self.mu_quantity)  # eq. (6.13)
        sc.mu = st
        sc.mu_energy = friction_average(outcomes, "mu_energy")
        if i > 0 or sc.contact is None:  # macro contact area from its frictionless runs (7.5)
            sc.contact = _values(outcomes, "contact_fraction")
        sc.dissipation = sample_stats([o.value("mu_energy") * sc.pressure if o.ok else math.nan
                                       for o in outcomes])
        self._flag(sc, st, "friction branch")
        if st.n_used == 0:
            return self._fail(f"scale {sc.name}: all {st.n_total} friction samples failed "
                              f"({_first_line(outcomes[0].reason)})")
        if i == 0:
            self._finish()
        else:
            self._enter_up(i - 1)

    def _finish(self) -> None:
        fr = []
        for sc in self.result.scales:
            fr.append(sc.contact.mean if sc.contact is not None else math.nan)
            sc.area_ratio = relative_contact_area(fr)  # eq. (7.5) over scales 0..i
        self.result.area_ratio = self.result.scales[-1].area_ratio
        self.result.mu = self.result.scales[0].mu
        self.result.status = "ok"
        self._stage = None


# ----------------------------------------------------------------------------------------------
# separated scales with a spline law (thesis 6.2)
# ----------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=1)
def _fitted_law_cls() -> type:
    """SplineLaw (driver.fe.friction_law) subclass that pickles through to_dict().

    SplineLaw holds its C++ twin, which does not pickle; MPI farming sends laws to workers.
    Imported lazily: only the separated variant needs the compiled contact module here.
    """
    from rubberfriction.driver.fe.friction_law import SplineLaw

    class FittedSplineLaw(SplineLaw):
        """A SplineLaw fitted by the separated-scale planner (eq. 6.6); pickles via to_dict."""

        def __reduce__(self):
            return (_law_from_dict, (self.to_dict(),))

    FittedSplineLaw.__module__ = __name__
    return FittedSplineLaw


def _law_from_dict(d: dict) -> Any:
    return _fitted_law_cls().from_dict(d)


def fit_friction_law(p: np.ndarray, v: np.ndarray, mu: np.ndarray, *, degree: int = 3,
                     smoothing: float = 0.0) -> Any:
    """Spline law mu(p, v), eq. (6.6), through micro results (``driver.fe.friction_law.fit_mu_pv``).

    ``mu`` has shape (len(p), len(v)); a grid with failed (NaN) entries is fitted as scattered
    data over its finite entries.  The velocity axis is log10(v) (decades of velocity).
    """
    from rubberfriction.driver.fe.friction_law import fit_mu_pv

    p, v, mu = np.asarray(p, float), np.asarray(v, float), np.asarray(mu, float)
    ok = np.isfinite(mu)
    if ok.all():
        law = fit_mu_pv(p, v, mu, degree=degree, smoothing=smoothing or None)
    else:
        P, V = np.meshgrid(p, v, indexing="ij")
        kmax = min(degree, 3)
        if ok.sum() < (kmax + 1) ** 2:
            kmax = max(1, int(math.isqrt(int(ok.sum()))) - 1)
        if ok.sum() < (kmax + 1) ** 2:
            raise ValueError(f"only {int(ok.sum())} of {mu.size} micro runs succeeded: too few for "
                             f"a spline law")
        law = fit_mu_pv(P[ok], V[ok], mu[ok], degree=kmax, smoothing=smoothing or None)
    return _law_from_dict(law.to_dict())


class SeparatedTwoScale:
    """Planner of one point of the separated-scale variant (thesis 6.2, fig. 6.1, 6.4)."""

    def __init__(self, campaign: str, point: Point, macro: ScaleSet, micro: ScaleSet,
                 full_sample: Any,
                 make_spec: SpecFactory, *, pressures: Sequence[float] = (),
                 pressure_factors: Sequence[float] = (),
                 velocities: Sequence[float] = (), velocity_factors: Sequence[float] = (),
                 reference: bool = True, degree: int = 3, smoothing: float = 0.0):
        self.campaign, self.point, self.macro, self.micro = campaign, point, macro, micro
        self.full_sample, self.make_spec = full_sample, make_spec
        self.p_given, self.p_factors = tuple(pressures), tuple(pressure_factors)
        self.v_given, self.v_factors = tuple(velocities), tuple(velocity_factors)
        self.reference, self.degree, self.smoothing = reference, degree, smoothing
        self.result = PointResult(point, "separated",
                                  scales=[ScaleResult(0, macro.name, tuple(macro.band)),
                                          ScaleResult(1, micro.name, tuple(micro.band))])
        self.result.scales[0].pressure = point.pressure
        self._stage: str | None = "macro0"
        self._issued = False
        self._expect: dict[str, int] = {}
        self._got: dict[str, dict[int, tuple[Task, Outcome]]] = {}
        self.p_grid = np.asarray(sorted(self.p_given), float) if self.p_given else None
        self.v_grid = np.asarray(sorted(self.v_given) if self.v_given
                                 else sorted(f * point.velocity for f in self.v_factors), float)
        self.law: Any = None

    def total(self) -> int:
        n_p = len(self.p_given) or len(self.p_factors)
        return 1 + n_p * len(self.v_grid) + 1 + (1 if self.reference else 0)

    @property
    def finished(self) -> bool:
        return self._stage is None and not self._expect

    def _task(self, role: str, idx: int, spec: Any, **extra: Any) -> Task:
        label = {"campaign": self.campaign, "point": self.point.id, "compound": self.point.compound,
                 "pressure": self.point.pressure, "velocity": self.point.velocity, "branch": role,
                 "scale": 1 if role == "micro" else 0,
                 "scale_name": self.micro.name if role == "micro" else
                 (self.macro.name if role != "reference" else "full"), "sample": idx, **extra}
        return Task(run_key(spec), spec, label)

    def next_tasks(self) -> list[Task]:
        if self._stage is None or self._issued:
            return []
        p = self.point.pressure
        tasks: list[Task] = []
        if self._stage == "macro0":
            spec = self.make_spec(self.point, 0, self.macro.samples[0], p, None, "macro0")
            tasks.append(self._task("macro0", 0, spec, pressure_in=p, friction_in=0.0))
            if self.reference:
                spec = self.make_spec(self.point, 0, self.full_sample, p, None, "reference")
                tasks.append(self._task("reference", 0, spec, pressure_in=p, friction_in=0.0))
        elif self._stage == "micro":
            for a, pi in enumerate(self.p_grid):  # type: ignore[arg-type]
                for b, vi in enumerate(self.v_grid):
                    pt = Point(self.point.compound, float(pi), float(vi))
                    spec = self.make_spec(pt, 1, self.micro.samples[0], float(pi), None, "micro")
                    tasks.append(self._task("micro", a * len(self.v_grid) + b, spec,
                                            pressure_in=float(pi),
                                            velocity_in=float(vi), friction_in=0.0))
        elif self._stage == "macro":
            spec = self.make_spec(self.point, 0, self.macro.samples[0], p, self.law, "macro")
            tasks.append(self._task("macro", 0, spec, pressure_in=p, friction_in=math.nan))
        for t in tasks:
            self._expect[t.label["branch"]] = self._expect.get(t.label["branch"], 0) + 1
        self._issued = True
        return tasks

    def record(self, task: Task, outcome: Outcome) -> None:
        role = task.label["branch"]
        got = self._got.setdefault(role, {})
        got[int(task.label["sample"])] = (task, outcome)
        if len(got) < self._expect.get(role, 0):
            return
        runs = [got[i] for i in sorted(got)]
        self.result.runs[role] = runs
        del self._expect[role]
        if role == "reference":
            o = runs[0][1]
            self.result.extra["mu_reference"] = o.value("mu_force") if o.ok else math.nan
            self.result.extra["reference_status"] = o.status
            self.result.extra["time_reference"] = o.wall_time
            return self._maybe_finish()
        self._issued = False
        if role == "macro0":
            o = runs[0][1]
            sc = self.result.scales[0]
            sc.pressure_down = mean_contact_pressure([o])
            sc.contact = sample_stats([o.value("contact_fraction") if o.ok else math.nan])
            if not o.ok:
                self._stage = None
                self.result.status = "failed"
                self.result.reason = f"frictionless macro run failed: {o.reason}"
                return
            pm = o.value("mean_pressure")
            self.result.extra["macro_mean_pressure"] = pm
            if self.p_grid is None:
                self.p_grid = np.asarray(sorted(f * pm for f in self.p_factors), float)
            self.result.scales[1].pressure = pm
            self._stage = "micro"
        elif role == "micro":
            mu = np.full((len(self.p_grid), len(self.v_grid)), math.nan)  # type: ignore[arg-type]
            for idx, (_, o) in enumerate(runs):
                if o.ok:
                    mu.flat[idx] = o.value("mu_force")
            self.result.extra.update(grid_p=self.p_grid, grid_v=self.v_grid, grid_mu=mu)
            sc = self.result.scales[1]
            sc.mu = sample_stats(mu.ravel())
            sc.flagged = bool(np.isnan(mu).any())
            try:
                self.law = fit_friction_law(self.p_grid, self.v_grid, mu,
                                            degree=self.degree,  # eq. (6.6)
                                            smoothing=self.smoothing)
            except ValueError as err:
                self._stage = None
                self.result.status, self.result.reason = "failed", f"micro friction law: {err}"
                return
            self.result.extra["law"] = self.law.to_dict()
            self._stage = "macro"
        elif role == "macro":
            o = runs[0][1]
            sc = self.result.scales[0]
            sc.mu = sample_stats([o.value("mu_force") if o.ok else math.nan])
            sc.mu_energy = sample_stats([o.value("mu_energy") if o.ok else math.nan])
            self._stage = None
            if not o.ok:
                self.result.status = "failed"
                self.result.reason = f"macro run with the micro law failed: {o.reason}"
            self._maybe_finish()

    def _maybe_finish(self) -> None:
        if self._stage is not None or self._expect or self.result.status == "failed":
            return
        r = self.result
        r.mu = r.scales[0].mu
        r.status = "ok"
        t_multi = sum(o.wall_time for role in ("macro0", "micro", "macro") for _,
                      o in r.runs.get(role, []))
        r.extra["time_multiscale"] = t_multi
        if "mu_reference" in r.extra and r.mu is not None:
            ref = r.extra["mu_reference"]
            r.extra["relative_difference"] = (r.mu.mean - ref) / ref if ref else math.nan
            t_ref = r.extra["time_reference"]
            r.extra["time_ratio"] = t_multi / t_ref if t_ref else math.nan


# ----------------------------------------------------------------------------------------------
# many points at once
# ----------------------------------------------------------------------------------------------


class CampaignPlanner:
    """All points of a scene as one planner: tasks of all points become ready independently, so
    the farm interleaves stages of different points (more runs ready at once, better balance)."""

    def __init__(self, planners: Sequence[Any]):
        self.planners = list(planners)
        self._by_point = {p.point.id: p for p in self.planners}
        if len(self._by_point) != len(self.planners):
            raise ValueError("two planners for the same point")

    def total(self) -> int:
        return sum(p.total() for p in self.planners)

    def next_tasks(self) -> list[Task]:
        out: list[Task] = []
        for p in self.planners:
            out.extend(p.next_tasks())
        return out

    def record(self, task: Task, outcome: Outcome) -> None:
        self._by_point[task.label["point"]].record(task, outcome)

    @property
    def results(self) -> list[PointResult]:
        return [p.result for p in self.planners]


# ----------------------------------------------------------------------------------------------
# sample-count study (thesis 6.4.2, fig. 6.13)
# ----------------------------------------------------------------------------------------------


@dataclass
class SampleCountStudy:
    """Spread of the n-sample mean over random evaluation orders (thesis fig. 6.13 b).

    From N single-sample results mu_1..mu_N: for ``orders`` random permutations, the running mean
    of the first n; ``S[n-1]`` is its standard deviation over the permutations, ``S_exact`` the
    closed form for drawing n of N without replacement, sigma/sqrt(n) sqrt((N-n)/(N-1)) with the
    population standard deviation sigma, against which the Monte Carlo value is checked.
    ``mean_ref`` is the average over all N (the thesis' reference mu_avg^ref).
    """

    values: np.ndarray
    n: np.ndarray
    S: np.ndarray
    S_exact: np.ndarray
    mean_ref: float
    examples: np.ndarray  # (3, N) running means of three random orders (fig. 6.13 b, k = 1..3)
    n_failed: int = 0


def sample_count_study(values: Sequence[float], orders: int = 1000,
                       seed: int = 0) -> SampleCountStudy:
    """S(n), n = 1..N, of the sample mean over ``orders`` random orders (failed = NaN dropped)."""
    v = np.asarray(values, dtype=float)
    ok = v[np.isfinite(v)]
    N = ok.size
    if N < 2:
        raise ValueError(f"a sample-count study needs at least two successful samples, got {N}")
    rng = np.random.default_rng(seed)
    perms = np.argsort(rng.random((orders, N)), axis=1)
    running = np.cumsum(ok[perms], axis=1) / np.arange(1, N + 1)
    n = np.arange(1, N + 1)
    sigma = ok.std(ddof=0)
    S_exact = sigma / np.sqrt(n) * np.sqrt((N - n) / (N - 1))
    return SampleCountStudy(ok, n, running.std(axis=0, ddof=1), S_exact, float(ok.mean()),
                            running[:3],
                            int(v.size - N))
