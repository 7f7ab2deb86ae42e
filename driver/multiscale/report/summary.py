"""Campaign report, summary: the text of ``summary.txt`` (also printed after a campaign), one
line per point and scale and the lines on time homogenisation, energy balance, stabilisation and
road resolution of the runs.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.multiscale.report.tables import (
    DRIFT_OF,
    ENERGY_BALANCE_TOL,
    INTRUSION_TOL,
    attempts_used,
    balance_parts,
    energy_balance,
    energy_balance_by_scale,
    handed_on,
    scale_intrusion,
    time_by_scale,
)
from rubberfriction.driver.multiscale.results import PointResult
from rubberfriction.driver.multiscale.scales import surface_lines
from rubberfriction.driver.multiscale.statistics import STABILISATION_TOL, SampleStats


def which_run(task: Any) -> str:
    """A run of a campaign in the summary's words: branch, scale, sample and point."""
    lab = task.label
    return (f"{lab.get('branch')} {lab.get('scale_name')} sample {lab.get('sample')}, "
            f"{lab.get('point')}")


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
    parts = [balance_parts(o) for r in points for rs in r.runs.values() for _, o in rs if o.ok]
    parts = [p for p in parts if all(math.isfinite(x) for x in p)]
    if parts:
        contact, rubber = (np.array([p[i] for p in parts]) for i in range(2))
        text += (f"; where it goes (samples.csv balance_contact / balance_rubber, mean): the "
                 f"contact {100 * contact.mean():+.2g} % (its resolution), the rubber "
                 f"{100 * rubber.mean():+.2g} %; "
                 f"{int(np.sum(np.abs(rubber) > ENERGY_BALANCE_TOL))} of {len(parts)} runs "
                 f"beyond {100 * ENERGY_BALANCE_TOL:.0f} % in the rubber (stored energy that "
                 f"changes over the window: not a periodic steady state; stabilised sub-steps; "
                 f"docs/notes-energy.md)")
    elif off:
        text += ("; those runs are not energy-consistent: the time step, the contact's "
                 "resolution, a window that is not a periodic steady state or stabilised "
                 "sub-steps (docs/notes-energy.md)")
    text += "; a balanced run need not be mesh-converged (run --mesh-check; docs/scales.md)"
    return text


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


#: the summary's mesh line until ``run --mesh-check`` replaces it with its figures
#: (driver.multiscale.mesh_check)
MESH_NOT_CHECKED = ("  mesh: not checked (rubberfriction run SCENE --mesh-check runs sample 0 of "
                    "each scale's friction runs again with contact elements 2x shorter)")


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
    if sc.variant == "rough":
        lines.append(MESH_NOT_CHECKED)
    used = attempts_used(result.points)
    if used.get("closed form"):
        lines.append(f"  model only what a run requires: {used['closed form']} frictionless "
                     "run(s) in full contact over small slopes are the linear viscoelastic closed "
                     "form (driver.sliding.shortcut), not FE runs")
    if set(used) - {"", "mortar"}:  # say so when fallbacks produced results
        lines.append("  successful runs by attempt: " + ", ".join(
            f"{k or 'unrecorded'} {n}" for k, n in sorted(used.items(), key=lambda kv: -kv[1])))
    return "\n".join(lines)
