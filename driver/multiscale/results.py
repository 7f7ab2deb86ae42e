"""Plain data of a multiscale campaign: operating points, scales with their samples, results.

Shared by the planners of both variants (:mod:`.cascade`, :mod:`.separated`), the campaign and the
report; holds no logic beyond derived properties.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

from rubberfriction.driver.multiscale.statistics import SampleStats
from rubberfriction.driver.runtime.farm import Task
from rubberfriction.driver.runtime.store import Outcome


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
