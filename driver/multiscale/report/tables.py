"""Campaign report, tables: the rows of ``results.csv``, ``scales.csv``, ``samples.csv`` and the
per-point dissipation and stationarity CSVs, the CSV writer, and the per-run quantities they
and the summary share (energy balance, road intrusion, attempts, time per scale).
"""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.adhesion.area import relative_area_ci95
from rubberfriction.driver.multiscale.results import PointResult
from rubberfriction.driver.multiscale.statistics import SampleCountStudy, SampleStats
from rubberfriction.driver.runtime.store import Outcome
from rubberfriction.driver.sliding.window import period_means


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9.=_-]+", "_", text).strip("_")


def _fmt(x: Any) -> Any:
    if isinstance(x, float):
        return "" if math.isnan(x) else f"{x:.6g}"
    return x


def _stats(prefix: str, st: SampleStats | None) -> dict[str, Any]:
    if st is None:
        return {prefix: math.nan, f"{prefix}_std": math.nan, f"{prefix}_ci95": math.nan,
                f"{prefix}_n_used": 0, f"{prefix}_n_failed": 0}
    return st.as_dict(prefix)


def write_csv(path: Path, rows: list[dict[str, Any]]) -> Path:
    keys: list[str] = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt(r.get(k, "")) for k in keys})
    return path


def area_spread(scales: Sequence[Any]) -> float:
    """95 % sample spread of the overall A_r of ``scales`` (eq. 7.5), first order from the
    per-scale contact-fraction intervals (``adhesion.area.relative_area_ci95``); NaN without
    contact fractions."""
    st = [s.contact for s in scales]
    if not st or any(c is None or not math.isfinite(c.mean) or c.mean <= 0 for c in st):
        return math.nan
    return relative_area_ci95([c.mean for c in st], [c.ci95 for c in st])


def point_rows(points: Sequence[PointResult]) -> list[dict[str, Any]]:
    rows = []
    for r in points:
        row: dict[str, Any] = {"variant": r.variant, "compound": r.point.compound,
                               "pressure_MPa": r.point.pressure,
                               "velocity_mm_s": r.point.velocity, "status": r.status,
                               "reason": r.reason}
        row.update(_stats("mu", r.mu))
        if r.variant == "rough":
            row["mu_adhesion"] = r.mu_adhesion
            row["area_ratio"] = r.area_ratio
            row["area_ratio_ci95"] = area_spread(r.scales)
            row["flagged_scales"] = " ".join(s.name for s in r.scales if s.flagged)
        else:
            for k in ("mu_reference", "relative_difference", "time_multiscale", "time_reference",
                      "time_ratio",
                      "macro_mean_pressure"):
                row[k] = r.extra.get(k, math.nan)
        row["runs"] = sum(len(v) for v in r.runs.values())
        row["runs_failed"] = sum(not o.ok for v in r.runs.values() for _, o in v)
        row["wall_time_s"] = r.wall_time
        rows.append(row)
    return rows


def scale_rows(points: Sequence[PointResult]) -> list[dict[str, Any]]:
    rows = []
    for r in points:
        intrusion = scale_intrusion(r)
        balance_of = energy_balance_by_scale([r])  # both branches, this point
        for s in r.scales:
            row: dict[str, Any] = {"compound": r.point.compound, "pressure_MPa": r.point.pressure,
                                   "velocity_mm_s": r.point.velocity, "scale": s.index,
                                   "name": s.name,
                                   "lambda_long_mm": s.band[0], "lambda_short_mm": s.band[1],
                                   "pressure": s.pressure}
            sp = s.pressure_spread
            row.update({"pressure_std": sp.std if sp else math.nan,
                        "pressure_ci95": sp.ci95 if sp else math.nan,
                        "pressure_n_used": sp.n_used if sp else 0,
                        "pressure_n_failed": sp.n_failed if sp else 0})
            row.update(_stats("mean_contact_pressure", s.pressure_down))
            row["friction_in"] = s.friction_in
            row.update(_stats("mu", s.mu))
            row.update(_stats("mu_energy", s.mu_energy))
            row.update(_stats("contact_fraction", s.contact))
            row["area_ratio"] = s.area_ratio
            row["area_ratio_ci95"] = area_spread(r.scales[: s.index + 1])
            row.update(_stats("dissipation_MPa", s.dissipation))
            bal = balance_of.get(s.name)
            row["energy_balance_mean"] = bal[2] if bal else math.nan
            row["energy_balance_max"] = bal[3] if bal else math.nan
            row["road_intrusion_max"] = intrusion.get(s.index, math.nan)
            row["flagged"] = s.flagged
            row["notes"] = "; ".join(s.notes)
            rows.append(row)
    return rows


def sample_rows(points: Sequence[PointResult]) -> list[dict[str, Any]]:
    rows = []
    for r in points:
        for stage, runs in r.runs.items():
            for t, o in runs:
                lab = t.label
                rows.append({"point": r.point.id, "branch": lab.get("branch"),
                             "scale": lab.get("scale"),
                             "scale_name": lab.get("scale_name"), "sample": lab.get("sample"),
                             "pressure_in": lab.get("pressure_in"),
                             "velocity_in": lab.get("velocity_in", r.point.velocity),
                             "friction_in": lab.get("friction_in"), "status": o.status,
                             "failure": o.failure,
                             "reason": o.reason.splitlines()[0] if o.reason else "",
                             "attempt": o.attempt,
                             "mean_pressure": o.value("mean_pressure"),
                             "mu_force": o.value("mu_force"),
                             "mu_energy": o.value("mu_energy"),
                             "energy_balance": energy_balance(o),
                             **dict(zip(("balance_contact", "balance_rubber"),
                                        balance_parts(o))),
                             "contact_fraction": o.value("contact_fraction"),
                             "window_drift": o.value("window_drift"),
                             "mu_error": o.value("mu_error"),
                             "contact_drift": o.value("contact_drift"),
                             "contact_error": o.value("contact_error"),
                             "converged": o.value("converged"),
                             "stabilisation_share": o.value("stabilisation_share"),
                             "min_det_F": o.value("min_det_F"),
                             "road_intrusion": o.value("road_intrusion"),
                             "contact_elements": o.value("contact_elements"),
                             "wall_time_s": o.wall_time, "reused": o.reused, "key": o.key})
    return rows


#: |energy balance| above which the summary counts a run as not energy-consistent: converged runs
#: on steep partial contact balance within it (``forms.viscoelastic``, exact dissipation;
#: docs/notes-energy.md)
ENERGY_BALANCE_TOL = 0.02


def energy_balance(o: Outcome) -> float:
    """mu_energy / mu_force - 1 of one run (NaN unless both are finite and mu_force > 0).

    In a steady periodic state the work of the friction force is what the run dissipates (eq.
    2.8), so 0 up to the O(dt^2) of the time integration.  The viscous dissipation is the exact
    one of the finite-strain model (``forms.viscoelastic``: branch stress work minus the change
    of the branches' stored energy; the small-strain density |H|^2 / (2 G tau) it replaced
    overestimated on steep contact, docs/notes-energy.md).  Where the rest goes,
    :func:`balance_parts`: the contact (its resolution, and its implicit step at coarse steps)
    and the rubber (stored energy that changes over the window, stabilised sub-steps)."""
    mf, me = o.value("mu_force"), o.value("mu_energy")
    if not (math.isfinite(mf) and math.isfinite(me) and mf > 0.0):
        return math.nan
    return me / mf - 1.0


def balance_parts(o: Outcome) -> tuple[float, float]:
    """The energy balance of one run split by where the friction work goes besides the
    dissipation, each over mu_force (NaN where the run has no split; docs/notes-energy.md):

    - contact: what the contact interface takes up itself (``mu_interface``: the road's work
      minus the frictional dissipation minus the trapezoidal work on the rubber): the mortar
      contact's non-conservation (it shrinks with the contact elements) and, at steps of an
      element and more, the implicit step's booking of the contact forces;
    - rubber: the rest, work on the rubber that is not dissipated in the window: stored energy
      that changes over it (not a periodic steady state; the period-end history jump),
      stabilised sub-steps, the trapezoidal rule's error.

    balance = -(contact + rubber)."""
    mf, b = o.value("mu_force"), energy_balance(o)
    contact = o.value("mu_interface") / mf
    if not (math.isfinite(b) and math.isfinite(contact)):
        return math.nan, math.nan
    return contact, -(b + contact)


def energy_balance_by_scale(points: Sequence[PointResult]
                            ) -> dict[str, tuple[int, int, float, float]]:
    """Per scale name over the points: (runs beyond ENERGY_BALANCE_TOL, successful runs with a
    balance, mean balance, largest |balance|)."""
    acc: dict[str, list[float]] = {}
    for r in points:
        for rs in r.runs.values():
            for t, o in rs:
                b = energy_balance(o) if o.ok else math.nan
                if math.isfinite(b):
                    acc.setdefault(str(t.label.get("scale_name")), []).append(b)
    return {k: (sum(abs(x) > ENERGY_BALANCE_TOL for x in v), len(v), float(np.mean(v)),
                float(np.max(np.abs(v)))) for k, v in acc.items()}


def handed_on(task: Any) -> str:
    """The result a run hands on, which its window waits for (sliding.window.WINDOW_QUANTITIES):
    the contact fraction on the pressure branch (the reciprocal of the pooled pressure of eq.
    6.11), mu on the friction branch."""
    return "contact_fraction" if task.label.get("branch") == "down" else "mu_force"


#: the window drift column of each handed-on result
DRIFT_OF = {"contact_fraction": "contact_drift", "mu_force": "window_drift"}


#: road intrusion (contact element lengths, ``sliding.intrusion``) from which a run does not
#: resolve its road: the road's peaks reach an element deep into the rubber face
INTRUSION_TOL = 1.0


def scale_intrusion(result: PointResult) -> dict[int, float]:
    """Largest road intrusion of the successful runs of each scale of a point (both branches),
    by scale index; scales without a recorded intrusion are left out."""
    out: dict[int, float] = {}
    for runs in result.runs.values():
        for t, o in runs:
            x = o.value("road_intrusion")
            if o.ok and math.isfinite(x):
                i = int(t.label.get("scale"))
                out[i] = max(out.get(i, 0.0), x)
    return out


def attempts_used(points: Sequence[PointResult]) -> dict[str, int]:
    """How many successful runs each fallback attempt produced (``sliding.SlidingRun.attempts``;
    runs stored without the record count as "")."""
    out: dict[str, int] = {}
    for r in points:
        for runs in r.runs.values():
            for _, o in runs:
                if o.ok:
                    out[o.attempt] = out.get(o.attempt, 0) + 1
    return out


def time_by_scale(points: Sequence[PointResult]) -> dict[str, float]:
    """Wall time of the runs per scale name (computed and reused alike: the cost of the scale)."""
    out: dict[str, float] = {}
    for r in points:
        for runs in r.runs.values():
            for t, o in runs:
                name = str(t.label.get("scale_name"))
                out[name] = out.get(name, 0.0) + o.wall_time
    return out


def depth_edges(centres: np.ndarray) -> np.ndarray:
    """Bin edges of contiguous depth bins from 0 given their centres (e_0 = 0,
    e_k+1 = 2 c_k - e_k)."""
    edges = np.zeros(len(centres) + 1)
    for k, c in enumerate(centres):
        edges[k + 1] = 2.0 * c - edges[k]
    return edges


def dissipation_rows(r: PointResult, store: Any) -> list[dict[str, Any]]:
    """Per scale and friction-branch sample: the stored dissipation by depth (thesis fig. 6.29 c),
    mJ/mm^3 per mm slid, with each bin's share of the run's window energy."""
    rows = []
    for stage, runs in r.runs.items():
        if not stage.startswith("up"):
            continue
        for t, o in runs:
            if not o.ok or not store.has(o.key):
                continue
            dd = store.load(o.key).dissipation_by_depth
            if dd is None or not len(dd[0]):
                continue
            z, d = np.asarray(dd[0]), np.asarray(dd[1])
            e = d * np.diff(depth_edges(z))
            share = e / e.sum() if e.sum() > 0 else np.zeros_like(e)
            for zk, dk, sk in zip(z, d, share):
                rows.append({"point": r.point.id, "scale": t.label.get("scale"),
                             "scale_name": t.label.get("scale_name"),
                             "sample": t.label.get("sample"),
                             "depth_mm": float(zk), "dissipation": float(dk), "share": float(sk)})
    return rows


def stationarity_rows(r: PointResult, store: Any) -> list[dict[str, Any]]:
    """Period means of what each run of a point waits for (driver.sliding.window): mu on the
    friction branch, the contact fraction on the pressure branch (the reciprocal of the pressure
    it passes down), per whole period of its cell, with each period's ratio to the run's averaged
    value and whether the period is in the averaging window."""
    rows = []
    for runs in r.runs.values():
        for t, o in runs:
            if not o.ok or not store.has(o.key):
                continue
            run = store.load(o.key)
            ser, spec = run.series, json.loads(run.inputs["spec"])
            period = float(spec.get("period", 0.0))
            name = handed_on(t)
            series = "contact_length" if name == "contact_fraction" else "mu_force"
            if not period > 0.0 or series not in ser or "s" not in ser or not len(ser["s"]):
                continue  # a finite block, or a run that kept no such series
            q = np.asarray(ser[series]) / (period if series == "contact_length" else 1.0)
            means = period_means(np.asarray(ser["s"]), q, period)
            lo = float(run.stats.get("window_start", math.nan))
            value = o.value(name)
            for k, m in enumerate(means):
                rows.append({"point": r.point.id, "branch": t.label.get("branch"),
                             "scale": t.label.get("scale"), "scale_name": t.label.get("scale_name"),
                             "sample": t.label.get("sample"), "quantity": name, "period": k + 1,
                             "mean": float(m), "ratio": float(m / value) if value else math.nan,
                             "in_window": bool((k + 1) * period > lo + 1e-9 * period),
                             "key": o.key})
    return rows


def study_rows(study: SampleCountStudy) -> list[dict[str, Any]]:
    return [{"n": int(k), "S": float(s), "S_exact": float(se), "mean_ref": study.mean_ref}
            for k, s, se in zip(study.n, study.S, study.S_exact)]


def campaign_json(result: Any) -> str:
    """The campaign's provenance as JSON (``campaign.json``)."""
    def default(o: Any) -> Any:
        if isinstance(o, (np.floating, np.integer)):
            return o.item()
        if isinstance(o, float) and math.isnan(o):
            return None
        return str(o)

    return json.dumps(result.provenance(), indent=2, default=default)
