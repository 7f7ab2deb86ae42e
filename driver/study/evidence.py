"""What the trend table reads from finished campaigns: plain numbers per case.

:class:`Evidence` holds one :class:`PointValue` per campaign point (key ``case:compound@v``,
e.g. ``materials:c1@1000``), the sample-spread study and the sawtooth pair.  It is built from
the campaigns' results (:func:`point_value`, :func:`flash_values`) and saved as
``evidence.json``; the table (``driver/study/trends.py``) reads nothing else, so a table can be
rebuilt from a stored study without any FE run.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any


def point_key(case: str, compound: str, velocity: float) -> str:
    """``case:compound@v`` with v in mm/s as printed by ``%g``."""
    return f"{case}:{compound}@{velocity:g}"


@dataclass
class PointValue:
    """mu of one campaign point with its sample spread and the lowest scale's contact."""

    mu: float
    ci95: float = math.nan  # half width of the 95 % CI of mu over the samples (nan: one sample)
    samples: int = 1  # friction samples per scale that entered
    contact: float = math.nan  # contact fraction of the lowest scale's friction runs
    area_ratio: float = math.nan  # real contact area of all scales, A_r / A_0 (eq. 7.5)
    scale_mu: dict[str, float] = field(default_factory=dict)  # mu_i per scale (eq. 6.13)
    ok: bool = True
    reason: str = ""


@dataclass
class SpreadValue:
    """Thesis 6.4.2: S(n) of the n-sample mean over random orders, from N single-scale runs."""

    scale: str
    N: int
    S1: float
    S10: float
    S10_exact: float  # sigma / sqrt(10) sqrt((N - 10) / (N - 1)) (without replacement)
    mean: float


@dataclass
class SawtoothValue:
    """Thesis 6.4.1: mu of the sharp and the smooth orientation of one sawtooth."""

    sharp: float
    smooth: float
    ok: bool = True
    reason: str = ""


@dataclass
class Evidence:
    """Everything the trend table needs (see the module docstring)."""

    settings: dict[str, Any]
    points: dict[str, PointValue] = field(default_factory=dict)
    spread: SpreadValue | None = None
    sawtooth: SawtoothValue | None = None
    notes: list[str] = field(default_factory=list)

    def save(self, path: Path) -> Path:
        path.write_text(json.dumps(strict_json(asdict(self)), indent=1) + "\n")
        return path

    @classmethod
    def load(cls, path: Path) -> Evidence:
        """Read ``evidence.json`` (null numbers back to NaN)."""
        d = json.loads(path.read_text())

        def nan(v: dict) -> dict:
            return {k: (math.nan if x is None and k not in ("reason", "scale") else x)
                    for k, x in v.items()}

        return cls(settings=d["settings"],
                   points={k: PointValue(**nan(v)) for k, v in d.get("points", {}).items()},
                   spread=SpreadValue(**nan(d["spread"])) if d.get("spread") else None,
                   sawtooth=SawtoothValue(**nan(d["sawtooth"])) if d.get("sawtooth") else None,
                   notes=list(d.get("notes", [])))


def strict_json(x: Any) -> Any:
    """``x`` with NaN and infinities as None and numpy scalars as Python numbers (strict JSON)."""
    if isinstance(x, dict):
        return {str(k): strict_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [strict_json(v) for v in x]
    if hasattr(x, "item") and not isinstance(x, (str, bytes)):  # numpy scalars
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _num(x: Any) -> float:
    return math.nan if x is None else float(x)


def point_value(point: Any) -> PointValue:
    """A :class:`PointValue` of a campaign's ``PointResult`` (driver/multiscale/results.py)."""
    scales = list(point.scales)
    low = scales[-1] if scales else None
    return PointValue(
        mu=_num(point.mu.mean) if point.mu is not None else math.nan,
        ci95=_num(point.mu.ci95) if point.mu is not None else math.nan,
        samples=int(low.mu.n_used) if low is not None and low.mu is not None else 0,
        contact=_num(low.contact.mean) if low is not None and low.contact is not None
        else math.nan,
        area_ratio=_num(point.area_ratio),
        scale_mu={s.name: _num(s.mu.mean) for s in scales if s.mu is not None},
        ok=bool(point.status == "ok"), reason=(point.reason or "").strip().split("\n")[0])


def flash_values(result: Any) -> tuple[PointValue, PointValue, list[str]]:
    """Without and with flash temperature, from a hot-layer (or coupled) loop result, and the
    loop's notes (its averaging windows and whether the macro mu became stationary)."""
    ok = bool(result.ok)
    reason = "; ".join(result.notes) if not ok else ""
    iso = PointValue(mu=_num(result.mu_isothermal), ok=math.isfinite(_num(result.mu_isothermal)))
    hot = PointValue(mu=_num(result.mu), ok=ok, reason=reason)
    notes = list(result.notes)
    macro = getattr(result, "macro", None)
    stats = getattr(macro, "stats", None) or {}
    temps, lower = getattr(result, "temperatures", None), getattr(result, "mu_lower", None)
    if temps is not None and lower is not None and len(temps):  # hot-layer mode: the mu(T_S) law
        law = ", ".join(f"{m:.4g} at {T - temps[0]:+.0f} K" for T, m in zip(temps, lower))
        notes.append(f"hot-layer law, the lower scales' mu: {law}")
    if "T_contact_max" in stats:  # how hot the contact got: the size of the flash effect
        notes.append(f"hottest contact node {_num(stats['T_contact_max']):.1f} K; mu "
                     f"{iso.mu:.4g} without, {hot.mu:.4g} with flash temperature")
    return iso, hot, notes
