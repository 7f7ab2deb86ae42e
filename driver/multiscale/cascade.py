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

The separated-scale variant of thesis 6.2 is :mod:`.separated`; both planners hand their runs to
:mod:`~rubberfriction.driver.runtime.farm` and combine the outcomes with :mod:`.statistics`.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.multiscale.results import (
    Point,
    PointResult,
    ScaleResult,
    ScaleSet,
    SpecFactory,
)
from rubberfriction.driver.multiscale.statistics import (
    STABILISATION_TOL,
    SampleStats,
    friction_average,
    mean_contact_pressure,
    outcome_stats,
    overstabilised,
    sample_stats,
    unconverged,
    usable,
    why_unusable,
)
from rubberfriction.driver.runtime.farm import Task
from rubberfriction.driver.runtime.progress import Stage
from rubberfriction.driver.runtime.store import Outcome, run_key
from rubberfriction.driver.sliding.spec import cost_model
from rubberfriction.driver.theory.adhesion import BellLaw, mu_adhesion


def relative_contact_area(fractions: Sequence[float]) -> float:
    """Overall relative contact area A_r = prod_i A_i,c / A_i,0, eq. (7.5)."""
    return float(np.prod(np.asarray(fractions, dtype=float)))


class RoughCascade:
    """Planner of one point of the rough-surface cascade (see the module docstring)."""

    def __init__(self, campaign: str, point: Point, scales: Sequence[ScaleSet],
                 make_spec: SpecFactory,
                 k: int, j: int, *, adhesion: BellLaw | None = None,
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

    def plan(self) -> list[Stage]:
        """The point's stages in order, pressure branch down then friction branch up (for the
        campaign's time estimate); weight: the model cost of a run on the scale's first sample
        (``sliding.spec.cost_model``; it does not depend on the pressure or friction)."""
        order = [("down", i, self.k) for i in self.down_scales] + [
            ("up", i, self.j) for i in range(self.n - 1, -1, -1)]
        weight = {i: cost_model(self.make_spec(self.point, i, self.scales[i].samples[0],
                                               self.point.pressure, None, "down"))
                  for i in range(self.n)}
        return [Stage(self.point.id, (self.point.id, branch, i), (branch, self.scales[i].name),
                      count, weight[i]) for branch, i, count in order]

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
    def _flag(self, sc: ScaleResult, stats: SampleStats, what: str,
              outcomes: list[Outcome]) -> None:
        n_unconv = unconverged(outcomes)
        n_stab = sum(overstabilised(o) and o.value("converged") != 0.0 for o in outcomes)
        if stats.n_failed > n_unconv + n_stab:
            sc.notes.append(f"{what}: {stats.n_failed - n_unconv - n_stab} of {stats.n_total} "
                            "samples failed")
        if n_unconv:
            sc.notes.append(f"{what}: {n_unconv} of {stats.n_total} samples did not reach a "
                            "stationary window within their sliding budget (not averaged)")
        if n_stab:
            sc.notes.append(f"{what}: {n_stab} of {stats.n_total} samples carried more than "
                            f"{100 * STABILISATION_TOL:.0f} % of their friction work by "
                            "stabilisation (not averaged)")
        if stats.failed_fraction > self.max_failed:
            sc.flagged = True

    def _fail(self, reason: str) -> None:
        self.result.status, self.result.reason = "failed", reason
        self._stage = None

    def _down_done(self, i: int, outcomes: list[Outcome]) -> None:
        sc = self.result.scales[i]
        st = mean_contact_pressure(outcomes)  # eq. (6.11) per sample, (6.12) over samples
        sc.pressure_down = st
        sc.contact = outcome_stats(outcomes, "contact_fraction")
        self._flag(sc, st, "pressure branch", outcomes)
        if st.n_used == 0:
            return self._fail(f"scale {sc.name}: no usable pressure sample of {st.n_total} "
                              f"({'; '.join(why_unusable(o) for o in outcomes)})")
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
            law = self.adhesion
            A_r = relative_contact_area([s.contact.mean if s.contact else math.nan
                                         for s in self.result.scales])
            mu_a = mu_adhesion(law, self.point.velocity, self.point.pressure,
                               min(max(A_r, 0.0), 1.0))  # eq. (7.7)
            self.result.mu_adhesion = float(law.alpha * mu_a)
            sc.friction_in += self.result.mu_adhesion  # eq. (7.8)
        self._stage = ("up", i)

    def _up_done(self, i: int, outcomes: list[Outcome]) -> None:
        sc = self.result.scales[i]
        st = friction_average(outcomes, self.mu_quantity)  # eq. (6.13)
        sc.mu = st
        sc.mu_energy = friction_average(outcomes, "mu_energy")
        if i > 0 or sc.contact is None:  # macro contact area from its frictionless runs (7.5)
            sc.contact = outcome_stats(outcomes, "contact_fraction")
        sc.dissipation = sample_stats([o.value("mu_energy") * sc.pressure if usable(o)
                                       else math.nan
                                       for o in outcomes])
        self._flag(sc, st, "friction branch", outcomes)
        if st.n_used == 0:
            return self._fail(f"scale {sc.name}: no usable friction sample of {st.n_total} "
                              f"({'; '.join(why_unusable(o) for o in outcomes)})")
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


class CampaignPlanner:
    """Several planners as one: the points of a scene, or the cascades of one point at several
    temperatures (hot-layer mode).  Their tasks become ready independently, so the farm
    interleaves their stages (more runs ready at once, better balance); each outcome goes back to
    the planner that handed out its task."""

    def __init__(self, planners: Sequence[Any]):
        self.planners = list(planners)
        self._owner: dict[int, Any] = {}  # id(task) -> its planner, while the task is out

    def total(self) -> int:
        return sum(p.total() for p in self.planners)

    def plan(self) -> list[Stage] | None:
        """The stages of every planner (each point is a chain of its own); None where two share
        a stage key (cascades of one point), which the time estimate could not tell apart."""
        stages = [st for p in self.planners for st in p.plan()]
        return stages if len({st.key for st in stages}) == len(stages) else None

    def next_tasks(self) -> list[Task]:
        out: list[Task] = []
        for p in self.planners:
            for task in p.next_tasks():
                self._owner[id(task)] = p
                out.append(task)
        return out

    def record(self, task: Task, outcome: Outcome) -> None:
        self._owner.pop(id(task)).record(task, outcome)

    @property
    def results(self) -> list[PointResult]:
        return [p.result for p in self.planners]
