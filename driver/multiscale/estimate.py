"""How long a rough-surface campaign will take: the wall-time estimate of ``run --check``.

Every planned single-scale run (per point: the pressure branch on all but the lowest scale with
k samples, the friction branch on every scale with j samples) gets a cost in CPU seconds:

* **stored**: a run of this campaign with the same label (point, branch, scale, sample) stored
  by the current code version is taken as reused (0 s; the cascade reuses it when its inputs
  are unchanged, which ``--check`` cannot know without running the branch above);
* **measured**: else the mean wall time of the stored successful runs of the same branch and
  scale (any point) of this store;
* **model**: else the cost model below, from the settings alone.

Cost model.  A run slides ``P`` periods over a sample with ``N = period / h_contact`` contact
elements in steps of ``step_per_element`` elements; each step's Newton iterations assemble and
factorise a graded mesh whose unknowns grow with ``N``.  The CPU time is taken as
``c N^2 P / step_per_element`` (steps x unknowns, the factorisation's log factor and the
iterations per step in ``c``), with ``P`` the expected periods (a window of 2 + 2 periods,
bounded by the scene's limits).  ``c`` (:data:`SECONDS_PER_ELEMENT_STEP`) is calibrated on the
default scene (docs/performance.md); the model holds to about a factor 2-3 across scenes,
glassy high-speed runs being the slow side.  The wall time on ``R`` ranks is the larger of the
CPU time over ``R`` and the cascade's critical path (stages run one after another per point).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from rubberfriction.driver.multiscale.scales import Scales
from rubberfriction.driver.scenes import Scene
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds, points
from rubberfriction.driver.runtime.store import Store, code_version

#: CPU seconds per (contact element x step) of the cost model, calibrated on the default scene.
SECONDS_PER_ELEMENT_STEP = 1.3e-3
#: Periods a run is expected to slide when its window converges (2 + 2, thesis 6.3.3).
EXPECTED_PERIODS = 4


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
                + ", ".join(parts) + "; the model holds to a factor 2-3)")


def _minutes(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 90 else f"{seconds / 60:.1f} min"


def model_seconds(n_elements: float, step_per_element: float, periods: float) -> float:
    """CPU seconds of one run by the cost model (module docstring)."""
    return SECONDS_PER_ELEMENT_STEP * n_elements ** 2 * periods / step_per_element


def _expected_periods(spec: Any) -> float:
    limit = spec.slide_distance / spec.period if spec.period > 0 else EXPECTED_PERIODS
    return float(min(EXPECTED_PERIODS, max(limit, 1.0)))


def estimate_wall_time(scene: Scene, scales: Scales, ranks: int = 1,
                       store: Store | None = None) -> WallTimeEstimate:
    """Estimated wall time of a rough-surface scene's campaign (module docstring)."""
    if scene.variant != "rough":
        raise ValueError("the estimate covers rough-surface (cascade) scenes")
    builder = SpecBuilder(scene, load_compounds(scene))
    n = len(scales.sets)
    k, j = scene.samples.pressure, scene.samples.friction
    stored: dict[tuple, float] = {}
    measured: dict[tuple[str, str], list[float]] = {}
    if store is not None:
        version = code_version()
        for run in store.iter_runs():
            lab = run.label
            if lab.get("campaign") != scene.name:
                continue
            wall = float(run.provenance.get("wall_time", 0.0))
            if run.ok:
                measured.setdefault((lab.get("branch"), lab.get("scale_name")), []).append(wall)
            if run.ok and run.provenance.get("code_version") == version:
                stored[(lab.get("point"), lab.get("branch"), lab.get("scale_name"),
                        lab.get("sample"))] = wall
    runs: list[PlannedRun] = []
    critical = 0.0
    for pt in points(scene):
        stages = [("down", i, k) for i in range(n - 1)] + [("up", i, j) for i in reversed(range(n))]
        if n == 1 and scene.physics.adhesion:
            stages.insert(0, ("down", 0, k))
        path = 0.0
        for branch, i, count in stages:
            name = scales.sets[i].name
            longest = 0.0
            for s in range(count):
                sample = scales.sets[i].samples[s]
                if (pt.id, branch, name, s) in stored:
                    sec, basis = 0.0, "stored"
                elif measured.get((branch, name)):
                    times = measured[(branch, name)]
                    sec, basis = sum(times) / len(times), "measured"
                else:
                    spec = builder(pt, i, sample, pt.pressure, None, branch)
                    n_el = spec.period / spec.h_contact
                    sec = model_seconds(n_el, spec.step_length / spec.h_contact,
                                        _expected_periods(spec))
                    basis = "model"
                runs.append(PlannedRun(pt.id, branch, name, s, sec, basis))
                longest = max(longest, sec)
            path += longest
        critical = max(critical, path)
    return WallTimeEstimate(runs, ranks, critical)
