"""Separated scales, thesis 6.2 (fig. 6.1): a planner for the two-scale spline-law variant.

-- :class:`SeparatedTwoScale`, two scales: a frictionless
macro run gives the mean contact pressure (step B); micro runs on a (p, v) grid around it (step
C, D) are time-homogenised (step E, eq. 6.2) and a smooth tensor-product spline mu_2(p, v),
eq. (6.6), is fitted to them (step F); the macro run with that law inside the contact (step G,
weak form 6.4) gives mu_1.  Optionally the single-scale reference on the full profile runs
alongside (thesis 6.2.3, fig. 6.4).
"""

from __future__ import annotations

import functools
import math
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.fe.friction_law import SplineLaw, fit_mu_pv
from rubberfriction.driver.multiscale.results import (
    Point,
    PointResult,
    ScaleResult,
    ScaleSet,
    SpecFactory,
)
from rubberfriction.driver.multiscale.statistics import mean_contact_pressure, sample_stats
from rubberfriction.driver.runtime.farm import Task
from rubberfriction.driver.runtime.progress import Stage
from rubberfriction.driver.runtime.store import Outcome, run_key
from rubberfriction.driver.sliding.spec import cost_model


@functools.lru_cache(maxsize=1)
def _fitted_law_cls() -> type:
    """SplineLaw (driver.fe.friction_law) subclass that pickles through to_dict().

    SplineLaw holds its C++ twin, which does not pickle; MPI farming sends laws to workers.
    """
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

    def plan(self) -> list[Stage]:
        """Stages for the campaign's time estimate: frictionless macro, micro grid, macro with
        the law one after another; the reference beside them.  Weight: ``cost_model``."""
        p, pid = self.point.pressure, self.point.id
        macro = cost_model(self.make_spec(self.point, 0, self.macro.samples[0], p, None, "macro0"))
        micro = cost_model(self.make_spec(self.point, 1, self.micro.samples[0], p, None, "micro"))
        n_micro = (len(self.p_given) or len(self.p_factors)) * len(self.v_grid)
        stages = [Stage(pid, (pid, "macro0", 0), ("macro0", self.macro.name), 1, macro),
                  Stage(pid, (pid, "micro", 1), ("micro", self.micro.name), n_micro, micro),
                  Stage(pid, (pid, "macro", 0), ("macro", self.macro.name), 1, macro)]
        if self.reference:
            ref = cost_model(self.make_spec(self.point, 0, self.full_sample, p, None, "reference"))
            stages.append(Stage(f"{pid} reference", (pid, "reference", 0), ("reference", "full"),
                                1, ref))
        return stages

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
