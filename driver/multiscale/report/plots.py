"""Campaign report, plots (matplotlib, Agg): mu(v) and mu(p) with the analytical baselines, A_r(v),
the quantities over scales, dissipation over depth, time homogenisation, the separated variant's
law and comparison, the sample-count study.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.multiscale import baseline
from rubberfriction.driver.multiscale.report.tables import _slug, area_spread
from rubberfriction.driver.multiscale.results import PointResult
from rubberfriction.driver.multiscale.separated import _law_from_dict
from rubberfriction.driver.multiscale.statistics import SampleCountStudy, SampleStats


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
