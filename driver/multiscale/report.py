"""Campaign report: CSV tables, plots (matplotlib, Agg) and a text summary.

Files written into the campaign's output folder:

* ``results.csv`` -- one row per (compound, p, v) point: mu with standard deviation, 95 %
  confidence interval and the number of samples the average used / that failed, flagged scales;
  separated variant: reference mu, relative difference, wall times.  These rows are the mu(v)
  and mu(p) curves.
* ``scales.csv`` -- per point and scale (thesis fig. 6.29 a): the pressure applied on the scale
  (eq. 6.12) with the spread of the samples that gave it, the Coulomb mu from the scale below,
  the overall mu (eq. 6.13), mu from dissipated energy, contact fraction (7.4), overall relative
  contact area (7.5), dissipation (mu_energy x p: energy per unit sliding length and nominal
  area, mJ/mm^3 = MPa), the energy balance of the scale's successful runs (mean and largest
  |mu_energy / mu_force - 1|, ``energy_balance``), flags and notes.
* ``samples.csv`` -- every single-scale run (thesis fig. 6.29 b): branch, scale, sample, status,
  failure kind (``physics``, ``error``, ``timeout``: stopped by the wall clock, recomputed on the
  next run) and reason, the fallback attempt that gave the result (e.g. ``nts x2 mesh``), inputs and
  results, wall time, whether it was reused, store key.
* ``area_v.png`` -- fig. 7.6 top: A_r(v) (eq. 7.5) per (compound, p) with its 95 % sample spread
  (``area_ratio_ci95`` in results.csv and scales.csv: first order from the per-scale contact
  fraction intervals) and each scale's contact fraction (eq. 7.4) over v.
* ``mu_v.png``, ``mu_p.png`` -- the curves with 95 % CI error bars.  ``mu_v.png`` also shows,
  per (compound, p), the analytical baselines of the same surface PSD and compound (Persson line
  roughness = plane strain and isotropic eq. 2.10, and Klueppel-Heinrich, at the scene's T0;
  ``baseline.py``)
  in the colour of the FE points; the summary lists them at the FE speeds (``theory:`` lines),
  or why they are missing.  ``write_report(..., theory=False)`` or ``rubberfriction run
  --no-theory`` leaves them out.
* ``scales_<point>.png`` -- fig. 6.29 a (p, mu, A_r over scales with spread);
  ``samples_<point>.png`` -- fig. 6.29 b (per-sample values per scale);
  ``dissipation_<point>.png`` -- fig. 6.29 c (dissipation over depth of the first friction-branch
  sample per scale) and ``dissipation_<point>.csv`` (every friction-branch sample: depth, mJ/mm^3
  per mm slid, share of the window energy; the campaign's runner records it with every run).
* ``stationarity_<point>.png`` / ``.csv`` -- the time homogenisation of every run of a rough
  point (also a failed one): period means of what the run waits for (mu; contact fraction on the
  pressure branch) over its averaged value, the window's periods marked, the tolerance band.
* separated variant: ``friction_law_<point>.png`` (fig. 6.4 a: the spline law with the micro
  raw data) and ``comparison.png`` (fig. 6.4 b, c: mu and wall time, multiscale vs reference).
* ``summary.txt`` (also printed), ``scene.toml`` (the scene as run), ``campaign.json``
  (provenance: code version, git describe, times, counts, surface provenance).
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
from rubberfriction.driver.multiscale import baseline
from rubberfriction.driver.multiscale.results import PointResult
from rubberfriction.driver.multiscale.scales import surface_lines
from rubberfriction.driver.multiscale.separated import _law_from_dict
from rubberfriction.driver.multiscale.statistics import (
    STABILISATION_TOL,
    SampleCountStudy,
    SampleStats,
)
from rubberfriction.driver.runtime.store import Outcome
from rubberfriction.driver.sliding.window import period_means


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, path: Path) -> Path:
    """Lay out, write (PNG, 120 dpi) and close one of the report's figures."""
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    _plt().close(fig)
    return path


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


# ----------------------------------------------------------------------------------------------
# tables
# ----------------------------------------------------------------------------------------------


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
                             "contact_fraction": o.value("contact_fraction"),
                             "window_drift": o.value("window_drift"),
                             "mu_error": o.value("mu_error"),
                             "contact_drift": o.value("contact_drift"),
                             "contact_error": o.value("contact_error"),
                             "converged": o.value("converged"),
                             "stabilisation_share": o.value("stabilisation_share"),
                             "min_det_F": o.value("min_det_F"),
                             "road_intrusion": o.value("road_intrusion"),
                             "wall_time_s": o.wall_time, "reused": o.reused, "key": o.key})
    return rows


#: |energy balance| above which the summary counts a run as not energy-consistent: converged runs
#: on steep partial contact balance within 2 % (``forms.viscoelastic``, exact dissipation)
ENERGY_BALANCE_TOL = 0.02


def energy_balance(o: Outcome) -> float:
    """mu_energy / mu_force - 1 of one run (NaN unless both are finite and mu_force > 0).

    In a steady periodic state the work of the friction force is what the run dissipates (eq.
    2.8), so 0 up to the O(dt^2) of the time integration.  The viscous dissipation is the exact
    one of the finite-strain model (``forms.viscoelastic``: branch stress work minus the change
    of the branches' stored energy; the small-strain density |H|^2 / (2 G tau) it replaced
    overestimated on steep contact: +26 .. +48 % on 7 stored macro/meso runs of the default road,
    now -1.1 .. +2.6 % on 5 of them and +4.5, +7.9 % at 300 and 100 mm/s, docs/notes-energy.md).
    What is left is mostly the contact: on the two macro runs the dissipation equals the work
    the contact forces do on the rubber (0.3 %) but that exceeds F_x ds, the mortar contact being
    non-conservative at its resolution (with contact elements half as long the +7.9 % run
    balances at -1.0 % and its mu_force rises by 24 %).  Besides: stored energy that changes over
    the window (not a periodic steady state), the normal load's work while the block creeps,
    stabilised sub-steps (``stabilisation_share``), the time integration of both sides."""
    mf, me = o.value("mu_force"), o.value("mu_energy")
    if not (math.isfinite(mf) and math.isfinite(me) and mf > 0.0):
        return math.nan
    return me / mf - 1.0


def which_run(task: Any) -> str:
    """A run of a campaign in the summary's words: branch, scale, sample and point."""
    lab = task.label
    return (f"{lab.get('branch')} {lab.get('scale_name')} sample {lab.get('sample')}, "
            f"{lab.get('point')}")


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


def energy_balance_line(points: Sequence[PointResult]) -> str:
    """How far the successful runs' dissipated energy is from their friction work (see
    :func:`energy_balance`): the count beyond ENERGY_BALANCE_TOL and the largest, with its run,
    then per scale the count, the mean and the largest |balance|."""
    balances = ((abs(energy_balance(o)), t) for r in points for rs in r.runs.values()
                for t, o in rs if o.ok)
    runs = [(b, t) for b, t in balances if math.isfinite(b)]
    if not runs:
        return ""
    b, t = max(runs, key=lambda bt: bt[0])
    off = sum(x > ENERGY_BALANCE_TOL for x, _ in runs)
    text = (f"  energy balance (mu_energy / mu_force - 1, 0 in a steady state): {off} of "
            f"{len(runs)} runs beyond {100 * ENERGY_BALANCE_TOL:.0f} %, largest {100 * b:.3g} % "
            f"({which_run(t)})")
    scales = energy_balance_by_scale(points)
    text += "; by scale: " + ", ".join(
        f"{k} {n_off} of {n} (mean {100 * mean:+.2g} %, largest {100 * big:.3g} %)"
        for k, (n_off, n, mean, big) in scales.items())
    if off:
        text += ("; those runs are not energy-consistent: the contact is under-resolved (its "
                 "forces do other work on the rubber than F_x ds: a default-road macro run at "
                 "+7.9 % balances at -1.0 % with contact elements half as long, and its mu_force "
                 "moves by 24 %), the window is not a periodic steady state, or stabilised "
                 "sub-steps carry energy")
    return text


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


def resolution_line(points: Sequence[PointResult]) -> str:
    """How many successful runs do not resolve their road (``sliding.intrusion``: road vertices
    INTRUSION_TOL contact elements or more inside the rubber face, so the contact state is a
    property of the mesh), by scale, with the deepest and its run.  "" when every run resolves
    its road or none recorded it."""
    runs = [(o.value("road_intrusion"), t) for r in points for rs in r.runs.values()
            for t, o in rs if o.ok]
    runs = [(x, t) for x, t in runs if math.isfinite(x)]
    bad = [(x, t) for x, t in runs if x >= INTRUSION_TOL]
    if not bad:
        return ""
    by_scale: dict[str, int] = {}
    for _, t in bad:
        name = str(t.label.get("scale_name"))
        by_scale[name] = by_scale.get(name, 0) + 1
    x, t = max(bad, key=lambda xt: xt[0])
    scales = ", ".join(f"{k} {n}" for k, n in by_scale.items())
    return (f"  road resolution: {len(bad)} of {len(runs)} runs have road peaks >= "
            f"{INTRUSION_TOL:g} contact element inside the rubber ({scales}; deepest "
            f"{x:.3g} elements, {which_run(t)}): their contact state and mu depend on the mesh "
            "(road peaks narrower than the contact elements; README \"Road intrusion\")")


def stationarity_line(points: Sequence[PointResult]) -> str:
    """How stationary the averaging windows of the successful runs were (driver.sliding.window):
    converged / unconverged counts and the largest |window drift| with the run it belongs to."""
    runs = [(t, o) for r in points for rs in r.runs.values() for t, o in rs if o.ok]
    if not runs:
        return ""
    unconv = sum(o.value("converged") == 0.0 for _, o in runs)
    conv = sum(o.value("converged") == 1.0 for _, o in runs)
    drifts = [(abs(o.value(DRIFT_OF[handed_on(t)])), t) for t, o in runs
              if math.isfinite(o.value(DRIFT_OF[handed_on(t)]))]
    text = f"  time homogenisation: {conv} of {len(runs)} runs converged"
    if unconv:
        text += f", {unconv} unconverged within their budget (not averaged)"
    if drifts:
        d, t = max(drifts, key=lambda dt: dt[0])
        text += f"; largest |window drift| {100 * d:.2f} % ({which_run(t)})"
    return text


def stabilisation_line(points: Sequence[PointResult]) -> str:
    """How much of the successful runs' friction the viscous stabilisation of failing sub-steps
    carries (``driver.fe.stabilisation``): runs with stabilised sub-steps in their window, the
    count above STABILISATION_TOL and the largest share, with its run.  "" when none."""
    runs = [(o.value("stabilisation_share"), t) for r in points for rs in r.runs.values()
            for t, o in rs if o.ok]
    used = [(x, t) for x, t in runs if math.isfinite(x) and x > 0.0]
    if not used:
        return ""
    x, t = max(used, key=lambda xt: xt[0])
    above = sum(y > STABILISATION_TOL for y, _ in used)
    text = (f"  stabilisation (thesis 6.3.3): {len(used)} of {len(runs)} runs have stabilised "
            f"sub-steps in their window, largest share of the friction work {100 * x:.2g} % "
            f"({which_run(t)})")
    if above:
        text += (f"; {above} above {100 * STABILISATION_TOL:.0f} %, not averaged")
    return text


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


# ----------------------------------------------------------------------------------------------
# text
# ----------------------------------------------------------------------------------------------


def _pm(st: SampleStats | None) -> str:
    if st is None or math.isnan(st.mean):
        return "n/a"
    if st.n_used > 1:
        spread = f" +- {st.ci95:.3g} (95% CI, std {st.std:.3g})"
    else:
        spread = " (one sample: no spread)"
    fail = f", {st.n_failed} failed" if st.n_failed else ""
    return f"{st.mean:.4g}{spread} [{st.n_used} samples{fail}]"


def timeout_note(n_timed_out: int) -> str:
    """The summary's line about runs the wall clock stopped ("" when there are none)."""
    if n_timed_out <= 0:
        return ""
    runs = "1 run" if n_timed_out == 1 else f"{n_timed_out} runs"
    they = "it is" if n_timed_out == 1 else "they are"
    return (f"{runs} stopped by the wall clock (run_timeout); {they} recomputed on the next run "
            "of the scene")


def summary_text(result: Any) -> str:
    sc = result.scene
    lines = [f"scene {sc.name!r} ({sc.variant}) from {sc.source}: {len(result.points)} point(s), "
             f"{result.n_runs} single-scale runs ({result.n_reused} reused, {result.n_failed} "
             f"failed), {result.wall_time:.1f} s on {result.workers} worker(s)"]
    note = timeout_note(result.n_timed_out)
    if note:
        lines.append(f"  {note}")
    if result.scales is not None and sc.variant == "rough" and sc.surface.source != "sines":
        lines.extend("  " + line for line in surface_lines(sc, result.scales))
    for r in result.points:
        head = f"  {r.point.id}: "
        if not r.ok:
            lines.append(head + f"FAILED: {r.reason}")
            continue
        lines.append(head + f"mu = {_pm(r.mu)}")
        if r.variant == "rough":
            if not math.isnan(r.mu_adhesion):
                lines.append(f"      adhesive share alpha mu_A = {r.mu_adhesion:.4g} (eq. 7.8)")
            intrusion = scale_intrusion(r)
            for s in r.scales:
                flag = "  FLAGGED: too many failed samples" if s.flagged else ""
                if intrusion.get(s.index, 0.0) >= INTRUSION_TOL:
                    flag += f"  road unresolved ({intrusion[s.index]:.3g} elements deep)"
                lines.append(f"      {s.name:<8} p = {s.pressure:.4g} MPa  mu = {_pm(s.mu)}  A/A0 "
                             f"= {s.contact.mean if s.contact else math.nan:.3g}  A_r = "
                             f"{s.area_ratio:.3g}{flag}")
        elif "mu_reference" not in r.extra:
            lines.append("      multiscale wall time "
                         f"{r.extra.get('time_multiscale', math.nan):.1f}"
                         " s (no single-scale reference: [separated].reference = false)")
        else:
            e = r.extra
            lines.append(f"      reference (single scale, full profile): mu = "
                         f"{e.get('mu_reference', math.nan):.4g}; "
                         f"difference {100 * e.get('relative_difference', math.nan):+.2f} %")
            lines.append(f"      wall time: multiscale {e.get('time_multiscale', math.nan):.1f} s, "
                         f"reference {e.get('time_reference', math.nan):.1f} s (ratio "
                         f"{e.get('time_ratio', math.nan):.3g})")
    shares = time_by_scale(result.points)
    total = sum(shares.values())
    if total > 0:
        lines.append("  run time per scale: " + ", ".join(f"{k} {100 * v / total:.0f} %" for k,
                                                          v in shares.items()))
    stationary = stationarity_line(result.points)
    if stationary:
        lines.append(stationary)
    balance = energy_balance_line(result.points)
    if balance:
        lines.append(balance)
    stabilised = stabilisation_line(result.points)
    if stabilised:
        lines.append(stabilised)
    resolution = resolution_line(result.points)
    if resolution:
        lines.append(resolution)
    used = attempts_used(result.points)
    if used.get("closed form"):
        lines.append(f"  model only what a run requires: {used['closed form']} frictionless "
                     "run(s) in full contact over small slopes are the linear viscoelastic closed "
                     "form (driver.sliding.shortcut), not FE runs")
    if set(used) - {"", "mortar"}:  # say so when fallbacks produced results
        lines.append("  successful runs by attempt: " + ", ".join(
            f"{k or 'unrecorded'} {n}" for k, n in sorted(used.items(), key=lambda kv: -kv[1])))
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# plots
# ----------------------------------------------------------------------------------------------


def _errorbar(ax, x, sts: list[SampleStats | None], **kw) -> Any:
    y = np.array([s.mean if s else math.nan for s in sts])
    e = np.array([s.ci95 if s and s.n_used > 1 else 0.0 for s in sts])
    return ax.errorbar(x, y, yerr=e, capsize=3, marker="o", **kw)


def _theory_summary(curves: Sequence[Any], v_fe: Sequence[float]) -> str:
    """Theory mu at the FE speeds (log-v interpolation of the drawn curves)."""
    v = sorted({float(x) for x in v_fe if x > 0})
    parts = []
    for c in curves:
        mu = np.interp(np.log(v), np.log(np.asarray(c.v, float)), np.asarray(c.mu, float))
        parts.append(f"{c.model} mu = " + ", ".join(f"{m:.4g}" for m in mu))
    return f"at v = {', '.join(f'{x:g}' for x in v)} mm/s: " + "; ".join(parts)


def draw_theory(ax: Any, scene: Any, compound: str, pressure: float, v_fe: Sequence[float],
                color: Any = None, suffix: str = "") -> list[str]:
    """Analytical mu(v) curves of ``scene`` for one FE (compound, p) group on the mu(v) axes.

    Persson line roughness (plane strain, as the FE) and isotropic (eq. 2.10) from the scene's
    surface PSD and compound at its T0 (kelvin; None = the compound's WLF reference, as in the
    FE runs), drawn in ``color`` (the group's FE colour) with ``suffix`` added to the labels.
    Never raises: a failure is returned as a note.  Returns the summary lines.
    """
    head = f"{compound}, p = {pressure:g} MPa"
    try:
        cond = scene.conditions
        path = dict(zip(cond.compounds, cond.compound_paths)).get(compound, compound)
        n_before = len(ax.lines)
        curves, notes = baseline.draw_beside_fe(ax, scene, v_fe=list(v_fe), compound=str(path),
                                                pressure=float(pressure), T0=cond.T0)
        for line in ax.lines[n_before:]:
            if color is not None:
                line.set_color(color)
            line.set_label(f"theory: {line.get_label()}{suffix}")
    except Exception as err:  # noqa: BLE001 -- the baseline must never break the report
        return [f"{head}: theory curves not drawn: {type(err).__name__}: {err}"]
    lines = []
    if curves:
        T0 = scene.conditions.T0
        T = "WLF reference T" if T0 is None else f"T0 = {T0:g} K"
        lines.append(f"{head}, {T}: {_theory_summary(curves, v_fe)}")
    return lines + [f"{head}: {n}" for n in notes]


def plot_curves(points: Sequence[PointResult], out: Path, *, scene: Any | None = None,
                notes: list[str] | None = None) -> list[Path]:
    """mu(v) per (compound, p) and mu(p) per (compound, v), 95 % CI error bars.

    With ``scene`` (the campaign's loaded ``Scene``) the mu(v) plot also shows the analytical
    curves of :func:`draw_theory` per (compound, p); their summary lines and notes are appended
    to ``notes``.
    """
    plt = _plt()
    files = []
    for axis, other, fname, xlabel in (("velocity", "pressure", "mu_v.png",
                                        "sliding velocity v (mm/s)"),
                                       ("pressure", "velocity", "mu_p.png",
                                        "nominal pressure p (MPa)")):
        fig, ax = plt.subplots(figsize=(6, 4))
        groups: dict[tuple[str, float], list[PointResult]] = {}
        for r in points:
            groups.setdefault((r.point.compound, getattr(r.point, other)), []).append(r)
        for (comp, val), rs in groups.items():
            rs = sorted(rs, key=lambda r: getattr(r.point, axis))
            x = [getattr(r.point, axis) for r in rs]
            unit = "MPa" if other == "pressure" else "mm/s"
            fe = _errorbar(ax, x, [r.mu if r.ok else None for r in rs],
                           label=f"{comp}, {other[0]} = {val:g} {unit}")
            if axis == "velocity" and scene is not None:
                color = fe.lines[0].get_color()
                suffix = f" ({comp}, p = {val:g} MPa)" if len(groups) > 1 else ""
                found = draw_theory(ax, scene, comp, val, x, color=color, suffix=suffix)
                if notes is not None:
                    notes.extend(found)
            for r in rs:
                if r.ok and r.mu is not None:
                    ax.annotate(f"n={r.mu.n_used}", (getattr(r.point, axis), r.mu.mean), fontsize=7,
                                textcoords="offset points", xytext=(4, 4))
        if axis == "velocity":
            ax.set_xscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("coefficient of friction mu")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        files.append(_save(fig, out / fname))
    return files


def plot_area(points: Sequence[PointResult], out: Path) -> list[Path]:
    """Thesis fig. 7.6 top: the relative real contact area A_r(v) (eq. 7.5) per (compound, p) with
    its 95 % sample spread, and the contact fraction of each scale (eq. 7.4) over v
    (``area_v.png``; nothing without rough-surface points that have contact areas)."""
    groups: dict[tuple[str, float], list[PointResult]] = {}
    for r in points:
        if r.variant == "rough" and r.ok and math.isfinite(r.area_ratio):
            groups.setdefault((r.point.compound, r.point.pressure), []).append(r)
    if not groups:
        return []
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8))
    for g, ((comp, p), rs) in enumerate(groups.items()):
        rs = sorted(rs, key=lambda r: r.point.velocity)
        v = [r.point.velocity for r in rs]
        err = [area_spread(r.scales) for r in rs]
        axs[0].errorbar(v, [r.area_ratio for r in rs],
                        yerr=[e if math.isfinite(e) else 0.0 for e in err], marker="o",
                        capsize=3, color=f"C{g}", label=f"{comp}, p = {p:g} MPa")
        for i, name in enumerate(s.name for s in rs[0].scales):
            _errorbar(axs[1], v, [r.scales[i].contact if i < len(r.scales) else None for r in rs],
                      color=f"C{g}", ls=("-", "--", ":", "-.")[i % 4],
                      label=f"{comp}, p = {p:g}: {name}")
    axs[0].set_ylabel("relative real contact area A_r (eq. 7.5)")
    axs[1].set_ylabel("contact fraction A_n,c / A_n,0 (eq. 7.4)")
    for ax in axs:
        ax.set_xscale("log")
        ax.set_xlabel("sliding velocity v (mm/s)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("real contact area over v (thesis fig. 7.6 top; 95 % CI over samples)",
                 fontsize=10)
    return [_save(fig, out / "area_v.png")]


def plot_scales(r: PointResult, out: Path) -> list[Path]:
    """Thesis fig. 6.29 a (overall p, mu, A_r over scales) and b (per-sample values)."""
    plt = _plt()
    files = []
    idx = [s.index + 1 for s in r.scales]
    names = [s.name for s in r.scales]
    fig, axs = plt.subplots(1, 3, figsize=(11, 3.5))
    p_stats = [s.pressure_spread for s in r.scales]
    axs[0].errorbar(idx, [s.pressure for s in r.scales],
                    yerr=[st.ci95 if st and st.n_used > 1 else 0.0 for st in p_stats], marker="o",
                    capsize=3)
    axs[0].set_ylabel("pressure p (MPa)")
    _errorbar(axs[1], idx, [s.mu for s in r.scales])
    axs[1].set_ylabel("overall mu (eq. 6.13)")
    axs[2].plot(idx, [s.area_ratio for s in r.scales], marker="o")
    axs[2].set_yscale("log")
    axs[2].set_ylabel("overall A_r (eq. 7.5)")
    for ax in axs:
        ax.set_xticks(idx, names)
        ax.set_xlabel("scale")
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"{r.point.id}: quantities over scales (thesis fig. 6.29 a)", fontsize=10)
    files.append(_save(fig, out / f"scales_{_slug(r.point.id)}.png"))
    fig, axs = plt.subplots(1, 3, figsize=(11, 3.5))
    for s in r.scales:
        if s.pressure_down is not None:
            axs[0].plot(np.arange(1, s.pressure_down.n_total + 1), s.pressure_down.values, "o-",
                        label=s.name)
        if s.mu is not None:
            axs[1].plot(np.arange(1, s.mu.n_total + 1), s.mu.values, "o-", label=s.name)
        if s.contact is not None:
            axs[2].plot(np.arange(1, s.contact.n_total + 1), s.contact.values, "o-", label=s.name)
    for ax, lab in zip(axs, ("mean contact pressure (eq. 6.11)", "mu per sample",
                             "contact fraction")):
        ax.set_xlabel("surface sample k / j")
        ax.set_ylabel(lab)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{r.point.id}: per-sample values (thesis fig. 6.29 b; failed samples missing)",
                 fontsize=10)
    files.append(_save(fig, out / f"samples_{_slug(r.point.id)}.png"))
    return files


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


def plot_dissipation(r: PointResult, store: Any, out: Path) -> list[Path]:
    """Thesis fig. 6.29 c: dissipation over depth of the first sample of each scale (if stored)."""
    plt = _plt()
    curves = []
    for stage, runs in r.runs.items():
        if not stage.startswith("up") or not runs:
            continue
        t, o = runs[0]
        if not o.ok or not store.has(o.key):
            continue
        dd = store.load(o.key).dissipation_by_depth
        if dd is not None and len(dd[0]):
            curves.append((t.label.get("scale_name"), dd))
    if not curves:
        return []
    fig, ax = plt.subplots(figsize=(5, 4))
    for name, (z, d) in curves:
        ax.plot(d / max(np.max(np.abs(d)), 1e-300), z, label=str(name))
    ax.set_xlabel("relative dissipated energy")
    ax.set_ylabel("depth z (mm)")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return [_save(fig, out / f"dissipation_{_slug(r.point.id)}.png")]


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


def plot_stationarity(rows: list[dict[str, Any]], tol: float, out: Path,
                      point_id: str) -> list[Path]:
    """Period means over the run's averaged value, one line per run (pressure branch dashed), the
    window's periods marked, the convergence tolerance as a band: how each homogenised number of
    a point got there."""
    if not rows:
        return []
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4))
    runs: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        runs.setdefault(row["key"], []).append(row)
    for rs in runs.values():
        k = np.array([x["period"] for x in rs])
        y = np.array([x["ratio"] for x in rs])
        w = np.array([x["in_window"] for x in rs])
        first = rs[0]
        label = (f"{first['branch']} {first['scale_name']} #{first['sample']} "
                 f"({'contact' if first['branch'] == 'down' else 'mu'})")
        line, = ax.plot(k, y, "--" if first["branch"] == "down" else "-", lw=1, label=label)
        ax.plot(k[w], y[w], "o", ms=4, color=line.get_color())
    if tol > 0:
        ax.axhspan(1 - tol, 1 + tol, color="0.85", zorder=0, label=f"+-{100 * tol:g} %")
    ax.set_ylim(0.5, 1.5)
    ax.set_xlabel("period of the cell (dots: averaging window)")
    ax.set_ylabel("period mean / averaged value")
    ax.set_title(f"time homogenisation, {point_id}", fontsize=9)
    ax.legend(fontsize=6, ncol=2)
    ax.grid(True, alpha=0.3)
    return [_save(fig, out / f"stationarity_{_slug(point_id)}.png")]


def plot_separated(points: Sequence[PointResult], out: Path) -> list[Path]:
    """Thesis fig. 6.4: (a) micro law with raw data, (b) mu multiscale vs reference, (c) times."""
    plt = _plt()
    files = []
    for r in points:
        e = r.extra
        if "law" not in e:
            continue
        law = _law_from_dict(e["law"])
        P, V = e["grid_p"], e["grid_v"]
        pp = np.linspace(P.min(), P.max(), 40)
        fig, ax = plt.subplots(figsize=(6, 4))
        for k, v in enumerate(V):
            line, = ax.plot(pp, law(pp, np.full_like(pp, v)), label=f"v = {v:g} mm/s")
            ax.plot(P, e["grid_mu"][:, k], "o", color=line.get_color())
        ax.set_xlabel("micro pressure p (MPa)")
        ax.set_ylabel("micro mu (spline eq. 6.6; dots: runs)")
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
        files.append(_save(fig, out / f"friction_law_{_slug(r.point.id)}.png"))
    ok = [r for r in points if r.ok and "mu_reference" in r.extra]
    if ok:
        fig, axs = plt.subplots(1, 2, figsize=(9, 3.5))
        lab = [r.point.id for r in ok]
        x = np.arange(len(ok))
        axs[0].bar(x - 0.2, [r.extra["mu_reference"] for r in ok], 0.4,
                   label="reference (single scale)")
        axs[0].bar(x + 0.2, [r.mu.mean for r in ok], 0.4,
                   label="multiscale")  # type: ignore[union-attr]
        axs[0].set_ylabel("mu")
        axs[0].legend(fontsize=8)
        axs[1].bar(x - 0.2, [1.0 for _ in ok], 0.4, label="reference")
        axs[1].bar(x + 0.2, [r.extra.get("time_ratio", math.nan) for r in ok], 0.4,
                   label="multiscale")
        axs[1].set_ylabel("relative wall time")
        axs[1].legend(fontsize=8)
        for ax in axs:
            ax.set_xticks(x, lab, fontsize=7)
        fig.suptitle("multiscale vs single-scale reference (thesis fig. 6.4 b, c)", fontsize=10)
        files.append(_save(fig, out / "comparison.png"))
    return files


def plot_sample_study(study: SampleCountStudy, path: Path, title: str = "") -> Path:
    """Thesis fig. 6.13: (a) histogram of mu, (b) running means of three orders and +-S(n)."""
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.8))
    axs[0].hist(study.values, bins=max(5, int(np.sqrt(study.values.size))), color="0.6",
                edgecolor="k")
    axs[0].set_xlabel("mu of one sample")
    axs[0].set_ylabel("frequency m(mu)")
    n = study.n
    for k, run in enumerate(study.examples, start=1):
        axs[1].plot(n, run, lw=1, label=f"order k = {k}")
    axs[1].axhline(study.mean_ref, color="k", lw=1, label=f"reference mean of {n[-1]}")
    axs[1].fill_between(n, study.mean_ref - study.S, study.mean_ref + study.S, color="C0",
                        alpha=0.15,
                        label="+- S(n) (random orders)")
    axs[1].set_xlabel("number of samples n")
    axs[1].set_ylabel("sample mean of mu")
    axs[1].legend(fontsize=7)
    for ax in axs:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title or "sample-count study (thesis fig. 6.13)", fontsize=10)
    return _save(fig, path)


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


# ----------------------------------------------------------------------------------------------
# all of it
# ----------------------------------------------------------------------------------------------


def write_report(result: Any, quiet: bool = False, theory: bool = True) -> list[Path]:
    """Write every table and plot of a finished campaign into its output folder.

    ``theory``: draw the analytical baselines beside the FE mu(v) points (see the module
    docstring); their figures and notes go into the summary as ``theory:`` lines.
    """
    out = Path(result.output)
    out.mkdir(parents=True, exist_ok=True)
    pts = result.points
    files = [write_csv(out / "results.csv", point_rows(pts)),
             write_csv(out / "scales.csv", scale_rows(pts)),
             write_csv(out / "samples.csv", sample_rows(pts))]
    theory_notes: list[str] = []
    files += plot_curves(pts, out, scene=result.scene if theory else None, notes=theory_notes)
    files += plot_area(pts, out)
    for r in pts:
        if r.variant == "rough" and r.ok:
            files += plot_scales(r, out)
            rows = dissipation_rows(r, result.store)
            if rows:
                files.append(write_csv(out / f"dissipation_{_slug(r.point.id)}.csv", rows))
            files += plot_dissipation(r, result.store, out)
        if r.variant == "rough":  # also for a failed point: how far its runs got
            rows = stationarity_rows(r, result.store)
            if rows:
                files.append(write_csv(out / f"stationarity_{_slug(r.point.id)}.csv", rows))
                files += plot_stationarity(rows, result.scene.numerics.convergence_tol
                                           if result.scene.numerics.window == "converged" else 0.0,
                                           out, r.point.id)
    if result.scene.variant == "separated":
        files += plot_separated(pts, out)
    text = summary_text(result)
    if theory_notes:
        text += "\n" + "\n".join(f"  theory: {n}" for n in theory_notes)
    (out / "summary.txt").write_text(text + "\n")
    (out / "scene.toml").write_text(result.scene.text)
    (out / "campaign.json").write_text(campaign_json(result) + "\n")
    files += [out / "summary.txt", out / "scene.toml", out / "campaign.json"]
    if not quiet:
        print(text)
        print(f"report: {out}/ (results.csv, scales.csv, samples.csv, plots)")
    return files
