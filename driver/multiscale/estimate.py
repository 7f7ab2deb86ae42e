"""How long a rough-surface campaign will take: the wall-time estimate of ``run --check``.

The plan is the cascade's own (``RoughCascade.plan``: per point the pressure branch down, the
friction branch up, each stage with its run count and the model weight of its runs,
``sliding.spec.cost_model``).  Every planned run gets a cost in CPU seconds:

* **stored**: a run of this campaign with the same label (point, branch, scale, sample) stored
  by the current code version is taken as reused (0 s; the cascade reuses it when its inputs
  are unchanged, which ``--check`` cannot know without running the branch above);
* **measured**: else what the campaign's progress line expects from finished runs
  (``runtime.progress.CostEstimate`` fed with the stored successful runs of this campaign: the
  mean of the same branch and scale, else of the scale, else the weight times their ratio);
* **model**: with no stored run, the weight times :data:`SECONDS_PER_UNIT`, calibrated on the
  default scene (docs/performance.md); it holds to about a factor 2-3 across scenes, glassy
  high-speed runs and micro cells that settle slowly being the slow side.

The wall time on ``R`` ranks is the larger of the CPU time over ``R`` and the cascade's critical
path (the stages of a point run one after another, each waiting for its slowest run).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rubberfriction.driver.multiscale.cascade import RoughCascade
from rubberfriction.driver.multiscale.scales import Scales
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds, points
from rubberfriction.driver.runtime.progress import CostEstimate
from rubberfriction.driver.runtime.store import Store, code_version
from rubberfriction.driver.scenes import Scene

#: CPU seconds per unit of ``sliding.spec.cost_model`` (the weights of ``RoughCascade.plan``),
#: calibrated on the default scene's measured run time (docs/performance.md).
SECONDS_PER_UNIT = 1.15e-5


@dataclass(frozen=True)
class PlannedRun:
    """One single-scale run of the plan and its estimated CPU time (s) with its basis."""

    point: str
    branch: str
    scale: str
    sample: int
    seconds: float
    basis: str  # "stored", "measured" or "model"


@dataclass
class WallTimeEstimate:
    """The plan's runs and the estimated wall time on ``ranks`` ranks."""

    runs: list[PlannedRun]
    ranks: int
    critical_path: float
    notes: list[str] = field(default_factory=list)

    @property
    def cpu_seconds(self) -> float:
        return sum(r.seconds for r in self.runs)

    @property
    def wall_seconds(self) -> float:
        return max(self.cpu_seconds / max(self.ranks, 1), self.critical_path)

    def count(self, basis: str) -> int:
        return sum(r.basis == basis for r in self.runs)

    def line(self) -> str:
        """One line for ``run --check``."""
        parts = [f"{self.count(b)} {b}" for b in ("stored", "measured", "model")
                 if self.count(b)]
        return (f"estimated wall time: {_minutes(self.wall_seconds)} on {self.ranks} rank(s) "
                f"({self.cpu_seconds:.0f} CPU-s over {len(self.runs)} runs: "
                + ", ".join(parts)
                + ("; the model holds to a factor 2-3)" if self.count("model") else ")"))


def _minutes(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 90 else f"{seconds / 60:.1f} min"


def estimate_wall_time(scene: Scene, scales: Scales, ranks: int = 1,
                       store: Store | None = None) -> WallTimeEstimate:
    """Estimated wall time of a rough-surface scene's campaign (module docstring)."""
    if scene.variant != "rough":
        raise ValueError("the estimate covers rough-surface (cascade) scenes")
    builder = SpecBuilder(scene, load_compounds(scene))
    k, j = scene.samples.pressure, scene.samples.friction
    plans = [RoughCascade(scene.name, pt, scales.sets, builder, k, j, adhesion=scene.adhesion,
                          max_failed_fraction=scene.samples.max_failed_fraction).plan()
             for pt in points(scene)]
    weight = {st.group: st.weight for plan in plans for st in plan}
    stored: set[tuple] = set()
    measured = CostEstimate()
    if store is not None:
        version = code_version()
        for run in store.iter_runs():
            lab = run.label
            if lab.get("campaign") != scene.name or not run.ok:
                continue
            group = (lab.get("branch"), lab.get("scale_name"))
            measured.observe(group, weight.get(group, 0.0),
                             float(run.provenance.get("wall_time", 0.0)))
            if run.provenance.get("code_version") == version:
                stored.add((lab.get("point"), *group, lab.get("sample")))
    runs: list[PlannedRun] = []
    critical = 0.0
    for plan in plans:
        path = 0.0
        for st in plan:
            expected = measured.expect(st.group, st.weight)
            basis = "model" if math.isnan(expected) else "measured"
            sec = st.weight * SECONDS_PER_UNIT if basis == "model" else expected
            costs = [(0.0, "stored") if (st.chain, *st.group, s) in stored else (sec, basis)
                     for s in range(st.runs)]
            runs += [PlannedRun(st.chain, *st.group, s, c, b) for s, (c, b) in enumerate(costs)]
            path += max(c for c, _ in costs)
        critical = max(critical, path)
    return WallTimeEstimate(runs, ranks, critical)
