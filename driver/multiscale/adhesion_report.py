"""Report of a scene with ``[adhesion] fit_from`` (thesis 7.4, 7.5; fig. 7.6, 7.7, 7.10).

Written into ``<output>/adhesion/`` after :func:`~.campaign.run_adhesion_fit`:

* ``fit.json`` -- the fitted bell law (tau0 per compound in MPa, c, v0 in mm/s, with standard
  errors and 95 % intervals), residual, approach, alpha per surface condition
  (:meth:`~rubberfriction.driver.adhesion.fit.AdhesionFit.to_dict`), the campaigns' folders and
  the wall times of the fit stage and of the extra macro runs;
* ``fit.png`` -- A_r(v), mu_diff and the fitted mu_A (fig. 7.6, 7.8 a, b);
* ``adhesion.csv`` -- per compound and speed: mu_H (alpha = 0: the hysteresis campaign), A_r,
  the fitted mu_A = tau_A A_r / p, for every macro campaign alpha mu_A and its mu (eq. 7.8), and
  the measurements interpolated in log v (empty outside their range);
* ``mu_v.png`` -- mu_H, mu(alpha) of the campaigns (solid) beside the measurements (dashed),
  fig. 7.7 / 7.10;
* ``fit_<approach>.json``, ``fit_<approach>.png`` -- the fit by the other approach, for
  comparison (original: dry minus soap-water, eqs. 7.3, 7.4; modified: dry minus the campaign's
  mu_H, 7.5); the macro campaigns use the scene's approach only;
* ``summary.txt`` (also printed).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction.driver.adhesion.fit import AdhesionFit, on_speeds
from rubberfriction.driver.adhesion.plots import plot_fit
from rubberfriction.driver.multiscale.report.plots import _plt
from rubberfriction.driver.multiscale.report.tables import area_spread, write_csv
from rubberfriction.driver.multiscale.results import PointResult

CONDITIONS = ("dry", "water", "soap")


def _by_speed(points: list[PointResult], compound: str) -> dict[float, PointResult]:
    return {r.point.velocity: r for r in points if r.point.compound == compound}


def _measured_at(curve: Any, v: float) -> float:
    if curve is None or not curve.range[0] <= v <= curve.range[1]:
        return math.nan
    return float(on_speeds(curve, np.array([v]))[0])


def adhesion_rows(hysteresis: Any, fit: AdhesionFit, runs: dict[float, Any]
                  ) -> list[dict[str, Any]]:
    """One row per compound and speed of the hysteresis campaign (see the module docstring)."""
    rows = []
    for c in fit.inputs:
        hyst = _by_speed(hysteresis.points, c.name)
        per_alpha = {a: _by_speed(res.points, c.name) for a, res in runs.items()}
        for v in sorted(hyst):
            r = hyst[v]
            row: dict[str, Any] = {"compound": c.name, "pressure_MPa": r.point.pressure,
                                   "velocity_mm_s": v, "status": r.status,
                                   "mu_H": r.mu.mean if r.ok and r.mu else math.nan,
                                   "mu_H_ci95": r.mu.ci95 if r.ok and r.mu else math.nan,
                                   "area_ratio": r.area_ratio}
            row["mu_A_fitted"] = (float(fit.bell.mu_adhesion(c.name, np.array([v]),
                                                             np.array([r.area_ratio]))[0])
                                  if r.ok and 0 < r.area_ratio <= 1 else math.nan)
            for a, pts in per_alpha.items():
                q = pts.get(v)
                ok = q is not None and q.ok and q.mu is not None
                row[f"alpha_mu_A[alpha={a:.4g}]"] = q.mu_adhesion if q is not None else math.nan
                row[f"mu[alpha={a:.4g}]"] = q.mu.mean if ok else math.nan  # type: ignore
                row[f"mu_ci95[alpha={a:.4g}]"] = q.mu.ci95 if ok else math.nan  # type: ignore
            for cond in CONDITIONS:
                row[f"measured_{cond}"] = _measured_at(getattr(c, cond), v)
            rows.append(row)
    return rows


def plot_mu_v(hysteresis: Any, fit: AdhesionFit, runs: dict[float, Any], path: Path) -> Path:
    """Fig. 7.7 / 7.10: measurements (dashed, open markers) and the campaigns (solid): mu_H
    (alpha = 0) and mu with alpha mu_A on the macro scale for each alpha."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    styles = ("-", "-.", ":", (0, (5, 1)))
    for k, c in enumerate(fit.inputs):
        color = f"C{k}"
        for cond, marker in zip(CONDITIONS, ("s", "^", "v")):
            meas = getattr(c, cond)
            if meas is not None:
                ax.plot(meas.v, meas.values, "--", marker=marker, mfc="none", color=color,
                        lw=1, label=f"{c.name}: measured {cond}")
        for j, (label, pts) in enumerate([("mu_H (alpha = 0)", hysteresis.points)]
                                         + [(f"mu, alpha = {a:.3g}", res.points)
                                            for a, res in runs.items()]):
            rs = sorted((r for r in pts if r.point.compound == c.name and r.ok and r.mu),
                        key=lambda r: r.point.velocity)
            ax.errorbar([r.point.velocity for r in rs], [r.mu.mean for r in rs],
                        yerr=[r.mu.ci95 if r.mu.n_used > 1 else 0.0 for r in rs],
                        ls=styles[j % len(styles)], marker="o", ms=4, color=color, capsize=2,
                        label=f"{c.name}: {label}")
    ax.set_xscale("log")
    ax.set_xlabel("sliding speed v (mm/s)")
    ax.set_ylabel("coefficient of friction mu")
    ax.set_title(f"{fit.bell.approach} approach: campaigns (solid) and measurements (dashed), "
                 "thesis fig. 7.7 / 7.10", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _fit_lines(fit: AdhesionFit, head: str) -> list[str]:
    b = fit.bell
    lines = [f"{head} ({b.approach} approach, p = {b.pressure:g} MPa, {b.n_points} points): "
             + ", ".join(f"tau0[{n}] = {t.value:.4g} +- {t.high - t.value:.2g} MPa"
                         for n, t in zip(b.compounds, b.tau0))
             + f", c = {b.c.value:.4g} +- {b.c.high - b.c.value:.2g}, v0 = {b.v0.value:.4g} mm/s "
             f"({b.v0.low:.4g} .. {b.v0.high:.4g}, 95 %); residual rms {b.residual_rms:.3g}"]
    for s in fit.shares:
        kind = "given" if s.given else f"fitted, 95 % {s.low:.3g} .. {s.high:.3g}"
        lines.append(f"  alpha[{s.condition}] = {s.alpha:.4g} ({kind}), residual rms "
                     f"{s.residual_rms:.3g}")
    for note in list(b.notes) + list(fit.notes):
        lines.append(f"  note: {note}")
    return lines


def summary(fit: AdhesionFit, runs: dict[float, Any], times: dict[str, float],
            other: AdhesionFit | str | None = None) -> str:
    lines = _fit_lines(fit, "adhesion fit")
    lines.append("  macro campaigns with alpha mu_A (eq. 7.8): " + ", ".join(
        f"alpha = {a:.4g} -> {res.output} ({res.n_runs - res.n_reused} new runs)"
        for a, res in runs.items()))
    lines.append(f"  wall time: hysteresis campaign and fit {times['campaigns_and_fit_s']:.1f} s, "
                 f"macro runs with adhesion {times['macro_runs_s']:.1f} s")
    if isinstance(other, AdhesionFit):
        lines += _fit_lines(other, "for comparison, not used in the macro runs: fit")
    elif other:
        lines.append(f"  for comparison: {other}")
    return "\n".join(lines)


def write_adhesion_report(out: Path, scene: Any, hysteresis: Any, fit: AdhesionFit,
                          runs: dict[float, Any], times: dict[str, float],
                          quiet: bool = False, other: AdhesionFit | str | None = None
                          ) -> list[Path]:
    """Write the files of the module docstring into ``out``; ``other``: the fit by the other
    approach (or why there is none)."""
    out.mkdir(parents=True, exist_ok=True)
    extra = {"scene": scene.name, "hysteresis_campaign": str(hysteresis.output),
             "macro_campaigns": {f"{a:.4g}": str(r.output) for a, r in runs.items()},
             "wall_time_s": times}
    (out / "fit.json").write_text(fit.to_json(extra))
    ci = []  # the A_r spread at the area curve's speeds (the ok points, ascending v)
    for c in fit.inputs:
        rs = sorted((r for r in hysteresis.points if r.point.compound == c.name and r.ok),
                    key=lambda r: r.point.velocity)
        ci.append(np.array([area_spread(r.scales) for r in rs]))
    files = [out / "fit.json", plot_fit(fit, out / "fit.png", area_ci95=ci),
             write_csv(out / "adhesion.csv", adhesion_rows(hysteresis, fit, runs)),
             plot_mu_v(hysteresis, fit, runs, out / "mu_v.png")]
    if isinstance(other, AdhesionFit):
        name = other.bell.approach
        (out / f"fit_{name}.json").write_text(other.to_json({"scene": scene.name,
                                                             "used_in_macro_runs": False}))
        files += [out / f"fit_{name}.json", plot_fit(other, out / f"fit_{name}.png", area_ci95=ci)]
    text = summary(fit, runs, times, other)
    (out / "summary.txt").write_text(text + "\n")
    files.append(out / "summary.txt")
    if not quiet:
        print(text)
        print(f"adhesion report: {out}/ (fit.json, fit.png, adhesion.csv, mu_v.png)")
    return files
