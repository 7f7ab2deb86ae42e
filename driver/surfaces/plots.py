"""PNG plots of profiles, spectra, HDCs, samples and the fig. 6.5 comparison.

Figures are drawn with matplotlib's object API on the Agg canvas (no pyplot, no global backend
switch), so plotting works headless and does not disturb other users of matplotlib.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from rubberfriction.driver.surfaces.hdc import HDCFit
from rubberfriction.driver.surfaces.profile import Profile
from rubberfriction.driver.surfaces.psd import PowerLawFit, log_bin
from rubberfriction.driver.surfaces.samples import SurfaceSample

__all__ = [
    "plot_profile",
    "plot_psd",
    "plot_hdc",
    "plot_analysis",
    "plot_samples",
    "plot_decompositions",
    "plot_road_scales",
]


def _save(fig: Figure, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    FigureCanvasAgg(fig)
    fig.savefig(path, dpi=110)
    return path


def _draw_profile(ax, profile: Profile, max_points: int = 200_000) -> None:
    step = max(1, profile.n // max_points)
    ax.plot(profile.x[::step], profile.h[::step], lw=0.5, color="k")
    rep = profile.repaired_mask()
    if rep.any():
        ax.plot(profile.x[rep][::step], profile.h[rep][::step], ".", ms=1.5, color="tab:red",
                label=f"interpolated ({100 * rep.mean():.1f} %)")
        ax.legend(loc="upper right", fontsize=7)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("h (mm)")


def _draw_psd(ax, q: np.ndarray, c: np.ndarray, edges: Sequence[float] | None,
              fit: PowerLawFit | None) -> None:
    ax.loglog(q, c, ",", color="0.7", label="periodogram")
    qb, cb, _ = log_bin(q, c, bins_per_decade=10)
    ax.loglog(qb, cb, "o-", ms=3, color="k", label="log-binned")
    if fit is not None:
        qq = np.geomspace(*fit.q_range, 20)
        ax.loglog(qq, fit(qq), "-", color="tab:orange", lw=2,
                  label=f"fit H = {fit.H:.3f} ({fit.lambda_range[0]:g}-{fit.lambda_range[1]:g} mm)")
    if edges is not None:
        for e in edges:
            ax.axvline(2 * np.pi / e, color="tab:blue", ls="--", lw=0.8)
            ax.text(2 * np.pi / e, ax.get_ylim()[1], f"{e:g} mm", rotation=90, va="top",
                    ha="right", fontsize=7, color="tab:blue")
    ax.set_xlabel("q = 2 pi / lambda (1/mm)")
    ax.set_ylabel("C1D (mm^3, Persson)")
    ax.legend(loc="lower left", fontsize=7)


def _draw_hdc(ax, lam: np.ndarray, c: np.ndarray, fit: HDCFit | None) -> None:
    ax.loglog(lam, c, "o", ms=3, color="k", label="C_HDC, eq. (2.4)")
    if fit is not None:
        ll = np.geomspace(*fit.fit_range, 100)
        ax.loglog(ll, fit(ll), "-", color="tab:orange", lw=2,
                  label=f"eq. (2.5): H = {fit.H:.3f}, xi_par = {fit.xi_par:.3g} mm, "
                        f"xi_perp = {fit.xi_perp:.3g} mm")
        for v in fit.fit_range:
            ax.axvline(v, color="0.5", ls=":", lw=0.8)
    ax.set_xlabel("lambda (mm)")
    ax.set_ylabel("C_HDC (mm^2)")
    ax.legend(loc="lower right", fontsize=7)


def plot_profile(profile: Profile, path: str | Path, *, title: str | None = None) -> Path:
    """The profile h(x), interpolated points in red."""
    fig = Figure(figsize=(10, 3.2))
    ax = fig.add_subplot()
    _draw_profile(ax, profile)
    ax.set_title(title or profile.source, fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def plot_psd(q: np.ndarray, c: np.ndarray, path: str | Path, *,
             edges: Sequence[float] | None = None, fit: PowerLawFit | None = None,
             title: str = "") -> Path:
    """1D PSD with log-binned average, optional power-law fit and band edges (dashed)."""
    fig = Figure(figsize=(6, 4.5))
    ax = fig.add_subplot()
    _draw_psd(ax, q, c, edges, fit)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def plot_hdc(lam: np.ndarray, c: np.ndarray, path: str | Path, *, fit: HDCFit | None = None,
             title: str = "") -> Path:
    """HDC with the eq. (2.5) fit and its fit range (dotted)."""
    fig = Figure(figsize=(6, 4.5))
    ax = fig.add_subplot()
    _draw_hdc(ax, lam, c, fit)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def plot_analysis(profile: Profile, q: np.ndarray, c: np.ndarray, lam: np.ndarray,
                  c_hdc: np.ndarray, path: str | Path, *, edges: Sequence[float] | None = None,
                  psd_fit: PowerLawFit | None = None, hdc_fit: HDCFit | None = None) -> Path:
    """Three panels: profile; PSD with band edges; HDC with its fit."""
    fig = Figure(figsize=(11, 8))
    ax0 = fig.add_subplot(2, 1, 1)
    _draw_profile(ax0, profile)
    ax0.set_title(profile.source, fontsize=9)
    _draw_psd(fig.add_subplot(2, 2, 3), q, c, edges, psd_fit)
    _draw_hdc(fig.add_subplot(2, 2, 4), lam, c_hdc, hdc_fit)
    fig.tight_layout()
    return _save(fig, path)


def plot_samples(samples: Sequence[Sequence[SurfaceSample]], path: str | Path, *,
                 names: Sequence[str] | None = None) -> Path:
    """Samples of every scale, stacked with an offset (cf. thesis fig. 6.17 b)."""
    ns = len(samples)
    fig = Figure(figsize=(4 * max(ns, 1), 6))
    for i, group in enumerate(samples):
        ax = fig.add_subplot(1, ns, i + 1)
        if not group:
            continue
        off = 3.0 * max(s.rms_height for s in group)
        for j, s in enumerate(group):
            color = "tab:blue" if s.source == "measured" else "tab:green"
            ax.plot(s.x, s.h - j * off, lw=0.8, color=color)
            if s.closure is not None and s.closure.length > 0:
                m = s.x >= s.x[-1] - s.closure_length - 1e-12
                ax.plot(s.x[m], s.h[m] - j * off, lw=1.5, color="tab:red")
        label = names[i] if names else f"scale {i}"
        ax.set_title(f"{label}: {group[0].band[0]:g}-{group[0].band[1]:g} mm ({group[0].source})",
                     fontsize=8)
        ax.set_xlabel("x (mm)")
        ax.set_yticks([])
    fig.suptitle("periodic samples (red: connecting spline)", fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def plot_decompositions(result: dict[str, list[Profile]], path: str | Path, *,
                        window: float | None = None) -> Path:
    """Fig. 6.5 analogue: rows = approaches, columns = scales, first ``window`` mm shown."""
    keys = list(result)
    nsc = max(len(v) for v in result.values())
    fig = Figure(figsize=(3.2 * nsc, 2.2 * len(keys)))
    for r, key in enumerate(keys):
        for c, prof in enumerate(result[key]):
            ax = fig.add_subplot(len(keys), nsc, r * nsc + c + 1)
            band = prof.meta.get("band", (np.nan, np.nan))
            w = window if window is not None else 3.0 * band[0]
            m = prof.x - prof.x[0] <= w
            ax.plot(prof.x[m] - prof.x[0], prof.h[m], lw=0.7, color="k")
            ax.set_title(f"{key}: {band[0]:g}-{band[1]:g} mm", fontsize=7)
            ax.tick_params(labelsize=6)
    fig.tight_layout()
    return _save(fig, path)


def plot_road_scales(road: Any, report: Any, path: str | Path, *,
                     title: str | None = None) -> Path:
    """The PSD of each kept band (log-binned periodogram of its band profile) with the stated
    edges, and the cumulative 2D rms slope down the bands against the rule's max_slope
    (``report``: a :class:`~rubberfriction.driver.surfaces.cutoff.CutoffReport`)."""
    from rubberfriction.driver.surfaces.psd import psd_1d

    fig = Figure(figsize=(10, 4.2))
    ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    for i, sc in enumerate(road.scales):
        q, c = psd_1d(sc.profile, window="hann", detrend="linear")
        lo, hi = 2 * np.pi / sc.band[0], 2 * np.pi / sc.band[1]
        keep = (q >= lo) & (q <= hi) & (c > 0)
        qb, cb, _ = log_bin(q[keep], c[keep], bins_per_decade=10)
        ax.loglog(qb, cb, "o-", ms=3, color=f"C{i}", label=f"{sc.name} ({sc.kind})")
    for e in report.stated_edges:
        ax.axvline(2 * np.pi / e, color="0.7", lw=0.8, ls=":")
    ax.set_xlabel("q = 2 pi / lambda (1/mm)")
    ax.set_ylabel("C1D (mm^3)")
    ax.legend(fontsize=8)
    ax.set_title("band PSDs (dotted: stated edges)", fontsize=9)
    rows = [r for r in report.rows if np.isfinite(r.cumulative_slope)]
    x = np.arange(len(rows))
    colours = ["C0" if r.status != "dropped" else "0.6" for r in rows]
    bx.bar(x, [r.cumulative_slope for r in rows], color=colours)
    bx.axhline(report.rule.max_slope, color="C3", ls="--",
               label=f"max_slope {report.rule.max_slope:g}")
    bx.set_xticks(x, [f"{r.name}\n{r.status}" for r in rows], fontsize=8)
    bx.set_ylabel("cumulative 2D rms slope")
    bx.legend(fontsize=8)
    bx.set_title(str(report.rule), fontsize=9)
    fig.suptitle(title or road.name, fontsize=10)
    fig.tight_layout()
    return _save(fig, path)
