"""Real contact area A_r(v) and hysteresis mu_H(v) of a finished campaign, thesis eq. (7.4), (7.5).

A campaign folder is what ``rubberfriction run SCENE --out DIR`` writes
(:mod:`rubberfriction.driver.multiscale.report`).  Read here:

* ``results.csv``: one row per point (``compound``, ``pressure_MPa``, ``velocity_mm_s``,
  ``status``); ``mu`` is the hysteresis coefficient mu_H of the point when the campaign ran
  without adhesion (``mu_adhesion`` empty), its ``mu_ci95`` the sample spread;
* ``scales.csv``: per point and scale the time- and sample-averaged contact fraction
  ``A_n,c / A_n,0`` of eq. (7.4) (``contact_fraction`` with ``_std``, ``_ci95``, ``_n_used``).

The relative real contact area of a point is the product over all scales, eq. (7.5)::

    A_r(v) = prod_n A_n,c(v) / A_n,0

(the macro fraction from its frictionless pressure runs, the finer ones from their friction
runs, as :mod:`rubberfriction.driver.multiscale.cascade` records them).  Its spread over samples
is propagated to first order from the per-scale 95 % intervals, scales independent:
``ci95(A_r) / A_r = sqrt(sum_n (ci95_n / A_n)^2)``.

Points that failed are left out and named in ``skipped``.  A folder without contact areas
(separated variant, no ``contact_fraction`` column or no finite values) is an
:class:`~rubberfriction.driver.adhesion.errors.AdhesionInputError`.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from rubberfriction.driver.adhesion.errors import AdhesionInputError
from rubberfriction.driver.adhesion.measurements import SpeedCurve


@dataclass(frozen=True)
class ScaleContact:
    """Contact fraction A_n,c / A_n,0 of one scale per speed (eq. 7.4) with its sample spread."""

    index: int
    name: str
    fraction: np.ndarray
    std: np.ndarray  # over samples (ddof = 1), NaN for one sample
    ci95: np.ndarray  # half width of the 95 % interval of the sample mean, NaN for one sample
    n_used: np.ndarray


@dataclass(frozen=True)
class CampaignCurves:
    """A_r(v) and mu_H(v) of one (compound, p) group of a campaign; speeds in mm/s ascending."""

    folder: str
    compound: str
    pressure: float  # MPa
    v: np.ndarray
    mu: np.ndarray  # the campaign's mu per point (mu_H when ``with_adhesion`` is False)
    mu_ci95: np.ndarray
    area_ratio: np.ndarray  # eq. (7.5): product of the per-scale fractions
    area_ratio_ci95: np.ndarray  # first-order spread from the per-scale intervals (docstring)
    scales: tuple[ScaleContact, ...]
    with_adhesion: bool  # the campaign added alpha mu_A on its macro scale: mu is not mu_H
    skipped: tuple[str, ...] = ()

    def area_curve(self) -> SpeedCurve:
        """A_r(v) as a speed curve."""
        return SpeedCurve(self.v, self.area_ratio, "A_r", f"{self.folder} ({self.compound}, "
                          f"p = {self.pressure:g} MPa)")

    def hysteresis_curve(self) -> SpeedCurve:
        """mu_H(v) as a speed curve; an error when the campaign ran with adhesion."""
        if self.with_adhesion:
            raise AdhesionInputError(f"{self.folder}: the campaign ran with adhesion on "
                                     "(results.csv mu_adhesion is set), so its mu is not the pure "
                                     "hysteresis mu_H: expected a campaign with [physics].adhesion "
                                     "= false")
        return SpeedCurve(self.v, self.mu, "mu_H", f"{self.folder} ({self.compound}, p = "
                          f"{self.pressure:g} MPa)")


def relative_area_ci95(fractions: Sequence[float], ci95: Sequence[float]) -> float:
    """95 % spread of A_r = prod_n A_n (eq. 7.5) from the per-scale half widths ``ci95``, first
    order with independent scales: ``A_r sqrt(sum_n (ci95_n / A_n)^2)``; a scale without a
    spread (one sample: NaN) adds nothing."""
    a = np.asarray(fractions, dtype=float)
    ci = np.asarray(ci95, dtype=float)
    ci = np.where(np.isfinite(ci), ci, 0.0)
    return float(np.prod(a) * np.sqrt(np.sum((ci / a) ** 2)))


def _rows(path: Path) -> list[dict[str, str]]:
    if not path.is_file():
        raise AdhesionInputError(f"{path}: not found: expected a finished campaign folder "
                                 "(what 'rubberfriction run SCENE --out DIR' writes)")
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _num(text: str | None) -> float:
    try:
        return float(text) if text not in (None, "") else math.nan
    except ValueError:
        return math.nan


def read_campaign(folder: str | Path) -> list[CampaignCurves]:
    """Every (compound, p) group of a finished campaign folder with its contact areas."""
    folder = Path(folder)
    if not folder.is_dir():
        raise AdhesionInputError(f"campaign folder {str(folder)!r}: not found")
    points = _rows(folder / "results.csv")
    scales = _rows(folder / "scales.csv")
    if not points:
        raise AdhesionInputError(f"{folder / 'results.csv'}: no points")
    if any(p.get("variant") != "rough" for p in points):
        raise AdhesionInputError(f"{folder}: variant {points[0].get('variant')!r} has no contact "
                                 "areas: expected a rough-surface campaign (variant = 'rough')")
    if not scales or "contact_fraction" not in scales[0]:
        raise AdhesionInputError(f"{folder / 'scales.csv'}: has no contact areas (no "
                                 "'contact_fraction' column): expected a finished rough-surface "
                                 "campaign")
    per_point: dict[tuple[str, float, float], list[dict[str, str]]] = {}
    for s in scales:
        key = (s["compound"], _num(s["pressure_MPa"]), _num(s["velocity_mm_s"]))
        per_point.setdefault(key, []).append(s)
    groups: dict[tuple[str, float], list[tuple[float, dict[str, str], list]]] = {}
    skipped: dict[tuple[str, float], list[str]] = {}
    for p in points:
        key = (p["compound"], _num(p["pressure_MPa"]), _num(p["velocity_mm_s"]))
        rows = sorted(per_point.get(key, []), key=lambda s: int(s["scale"]))
        fr = [_num(s.get("contact_fraction")) for s in rows]
        label = f"{key[0]}/p={key[1]:g}/v={key[2]:g}"
        if p["status"] != "ok" or not rows or not all(math.isfinite(f) for f in fr):
            skipped.setdefault(key[:2], []).append(
                f"{label}: {p['status']}" + (f" ({p['reason']})" if p.get("reason") else "")
                + ("" if p["status"] != "ok" else " (no contact fraction on every scale)"))
            continue
        groups.setdefault(key[:2], []).append((key[2], p, rows))
    out = []
    for key in list(groups) + [k for k in skipped if k not in groups]:
        if key not in groups:
            raise AdhesionInputError(f"{folder}: {key[0]}, p = {key[1]:g} MPa has no contact "
                                     f"areas: every point failed or lacks contact fractions "
                                     f"({'; '.join(skipped[key])})")
        out.append(_group(folder, key, sorted(groups[key], key=lambda t: t[0]),
                          tuple(skipped.get(key, ()))))
    return out


def _group(folder: Path, key: tuple[str, float], pts: list, skipped: tuple[str, ...]
           ) -> CampaignCurves:
    n_scales = {len(rows) for _, _, rows in pts}
    if len(n_scales) != 1:
        raise AdhesionInputError(f"{folder / 'scales.csv'}: {key[0]}, p = {key[1]:g} MPa: points "
                                 f"with different numbers of scales {sorted(n_scales)}")
    ns = n_scales.pop()
    col = {name: np.array([[_num(rows[i].get(name)) for i in range(ns)] for _, _, rows in pts])
           for name in ("contact_fraction", "contact_fraction_std", "contact_fraction_ci95",
                        "contact_fraction_n_used")}
    frac = col["contact_fraction"]
    if np.any(frac <= 0) or np.any(frac > 1 + 1e-9):
        raise AdhesionInputError(f"{folder / 'scales.csv'}: {key[0]}, p = {key[1]:g} MPa: "
                                 "contact fractions outside (0, 1]: expected 0 < A_n,c/A_n,0 <= 1")
    first = pts[0][2]
    scales = tuple(ScaleContact(i, first[i]["name"], frac[:, i], col["contact_fraction_std"][:, i],
                                col["contact_fraction_ci95"][:, i],
                                col["contact_fraction_n_used"][:, i]) for i in range(ns))
    area = np.prod(frac, axis=1)  # eq. (7.5)
    area_ci = np.array([relative_area_ci95(f, c) for f, c in
                        zip(frac, col["contact_fraction_ci95"])])
    with_adh = any(math.isfinite(_num(p.get("mu_adhesion"))) for _, p, _ in pts)
    return CampaignCurves(str(folder), key[0], key[1], np.array([v for v, _, _ in pts]),
                          np.array([_num(p.get("mu")) for _, p, _ in pts]),
                          np.array([_num(p.get("mu_ci95")) for _, p, _ in pts]),
                          area, area_ci, scales, with_adh, skipped)


def campaign_curves(folder: str | Path, compound: str | None = None,
                    pressure: float | None = None) -> CampaignCurves:
    """The one (compound, p) group of a campaign the caller asks for (``None``: the only one)."""
    groups = read_campaign(folder)
    found = [g for g in groups if (compound is None or g.compound == compound)
             and (pressure is None or math.isclose(g.pressure, pressure, rel_tol=1e-9))]
    have = ", ".join(f"{g.compound} at p = {g.pressure:g} MPa" for g in groups)
    if not found:
        raise AdhesionInputError(f"campaign {str(folder)!r}: no points for compound = "
                                 f"{compound!r}, p = {pressure!r} MPa: it has {have}")
    if len(found) > 1:
        raise AdhesionInputError(f"campaign {str(folder)!r}: several groups match compound = "
                                 f"{compound!r}, p = {pressure!r} MPa ({have}): name the compound "
                                 "and the pressure")
    return found[0]
