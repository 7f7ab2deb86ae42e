"""Plots of the adhesion fit (matplotlib, Agg): thesis fig. 7.6 and 7.8.

* top: A_r(v) of the campaign per compound (fig. 7.6 top), with the 95 % sample spread when the
  campaign provides it;
* middle: the measured mu_diff(v) (points) and the fitted mu_A(v) = tau_A A_r / p (lines) over
  log v (fig. 7.6 bottom, 7.8 b);
* bottom (when a share alpha was fitted or given): each measured curve against
  mu_H + alpha mu_A (fig. 7.8 c), dry against mu_H + mu_A (alpha = 1).
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from rubberfriction.driver.adhesion.fit import AdhesionFit, on_speeds


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_fit(fit: AdhesionFit, path: str | Path,
             area_ci95: Sequence[np.ndarray | None] | None = None) -> Path:
    """Write the fig. 7.6 / 7.8 panels of ``fit`` to ``path`` (PNG); ``area_ci95`` per compound:
    the 95 % half widths of A_r at the area curve's speeds (None: no error bars)."""
    plt = _plt()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with_share = bool(fit.shares)
    n = 3 if with_share else 2
    fig, axs = plt.subplots(n, 1, figsize=(6, 3.2 * n), sharex=True)
    b = fit.bell
    for k, c in enumerate(fit.inputs):
        color = f"C{k}"
        ci = area_ci95[k] if area_ci95 is not None else None
        yerr = None if ci is None else np.where(np.isfinite(ci), ci, 0.0)
        axs[0].errorbar(c.area.v, c.area.values, yerr=yerr, marker="o", color=color, capsize=3,
                        label=c.name)
        d = fit.mu_diff[k]
        axs[1].plot(d.v, d.values, "o", color=color, label=f"{c.name}: mu_diff")
        vv = np.logspace(np.log10(d.v[0]), np.log10(d.v[-1]), 200)
        area = on_speeds(c.area, vv, log_values=True, extrapolate=True)
        axs[1].plot(vv, b.mu_adhesion(c.name, vv, area), "-", color=color,
                    label=f"{c.name}: mu_A, tau0 = {b.tau0[k].value:.3g} MPa")
        if with_share:
            base = c.soap if b.approach == "original" else c.hysteresis
            if base is None:
                continue
            mu_h = on_speeds(base, vv, extrapolate=True)
            mu_a = b.mu_adhesion(c.name, vv, area)
            axs[2].plot(c.dry.v, c.dry.values, "s", color=color, mfc="none",
                        label=f"{c.name}: dry")
            axs[2].plot(vv, mu_h + mu_a, "-", color=color, label=f"{c.name}: mu_H + mu_A")
            for s, marker, ls in zip(fit.shares, ("^", "v", "x"), ("--", ":", "-.")):
                meas = getattr(c, s.condition, None) if s.condition != "given" else None
                if meas is not None:
                    axs[2].plot(meas.v, meas.values, marker, color=color, mfc="none",
                                label=f"{c.name}: {s.condition}")
                axs[2].plot(vv, mu_h + s.alpha * mu_a, ls, color=color,
                            label=f"{c.name}: mu_H + {s.alpha:.2g} mu_A ({s.condition})")
    axs[0].set_yscale("log")
    axs[0].set_ylabel("A_r (eq. 7.5)")
    axs[0].set_title("relative real contact area (thesis fig. 7.6 top)", fontsize=9)
    axs[1].set_ylabel("mu_diff, mu_A")
    axs[1].set_title(f"{b.approach} approach: c = {b.c.value:.3g}, v0 = {b.v0.value:.3g} mm/s, "
                     f"residual rms {b.residual_rms:.2g}\n(fig. 7.6 bottom, 7.8 b)", fontsize=9)
    if with_share:
        axs[2].set_ylabel("mu")
        axs[2].set_title("measurements vs mu_H + alpha mu_A (eq. 7.8, fig. 7.8 c)", fontsize=9)
    for ax in axs:
        ax.set_xscale("log")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
    axs[-1].set_xlabel("sliding speed v (mm/s)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
