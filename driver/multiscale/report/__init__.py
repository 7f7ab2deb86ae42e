"""Campaign report: CSV tables, plots (matplotlib, Agg) and a text summary.

Modules: ``tables`` (the CSV rows and writer, the per-run quantities), ``summary`` (the text of
``summary.txt``), ``plots`` (the figures); :func:`write_report` here writes all of it.  The
names other code uses are re-exported here.

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

from pathlib import Path
from typing import Any

from rubberfriction.driver.multiscale.report.plots import (
    draw_theory,
    plot_area,
    plot_curves,
    plot_dissipation,
    plot_sample_study,
    plot_scales,
    plot_separated,
    plot_stationarity,
)
from rubberfriction.driver.multiscale.report.summary import (
    energy_balance_line,
    resolution_line,
    stabilisation_line,
    stationarity_line,
    summary_text,
    timeout_note,
    which_run,
)
from rubberfriction.driver.multiscale.report.tables import (
    DRIFT_OF,
    ENERGY_BALANCE_TOL,
    INTRUSION_TOL,
    _slug,
    area_spread,
    attempts_used,
    balance_parts,
    campaign_json,
    depth_edges,
    dissipation_rows,
    energy_balance,
    energy_balance_by_scale,
    handed_on,
    point_rows,
    sample_rows,
    scale_intrusion,
    scale_rows,
    stationarity_rows,
    study_rows,
    time_by_scale,
    write_csv,
)

__all__ = [
    "DRIFT_OF", "ENERGY_BALANCE_TOL", "INTRUSION_TOL", "area_spread", "attempts_used",
    "balance_parts",
    "campaign_json", "depth_edges", "dissipation_rows", "draw_theory", "energy_balance",
    "energy_balance_by_scale", "energy_balance_line", "handed_on", "plot_area", "plot_curves",
    "plot_dissipation", "plot_sample_study", "plot_scales", "plot_separated",
    "plot_stationarity", "point_rows", "resolution_line", "sample_rows", "scale_intrusion",
    "scale_rows", "stabilisation_line", "stationarity_line", "stationarity_rows", "study_rows",
    "summary_text", "time_by_scale", "timeout_note", "which_run", "write_csv", "write_report",
]


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
