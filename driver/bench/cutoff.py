"""Benchmark: how much of mu comes from the scales the cut-off decides.

    rubberfriction bench cutoff [--scene four_scale] [--max-slopes 1.0 1.3 2.0]
                                [--edges 20 3 0.3 0.04 0.003 0.0002] [--velocities 10 100 1000]
                                [--pressure 0.3] [--samples 1 2] [--no-fe] [--out DIR]
    mpirun -n 2 rubberfriction bench cutoff ...     # the FE campaigns farm their runs

The scene's road is cut by the slope rule (``[surface] cutoff = "slope"``) at each
``max_slope``; the stated ``--edges`` reach below the scene's own so that a larger limit has
spectrum to keep (the four-scale road continues its power law on an ultra-fine 'scan').  For
each limit: the kept edges, Persson's theories (line and isotropic, driver.theory) on exactly the
kept spectrum, and (unless ``--no-fe``) the FE cascade's mu(v) with its sample spread, all at the
scene's compound, pressure and temperature.  Printed as a table, written to ``cutoff.csv`` and
plotted (``cutoff.png``: mu(v) per limit, FE with error bars, theory dashed).  Each limit's FE
campaign keeps its own store (``<out>/max_slope=<m>/store``): a rerun resumes.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path
from typing import Any

from rubberfriction.driver.multiscale.baseline import evaluate, request_from_scene
from rubberfriction.driver.multiscale.campaign import run_scene
from rubberfriction.driver.scenes import Scene, SceneError, load_scene, override
from rubberfriction.driver.scenes import with_surface
from rubberfriction.driver.surfaces.multiscale import scale_names

#: the theories shown next to the FE (both Persson: line roughness and isotropic)
MODELS = ("persson-1d", "persson-2d")


def cut_scene(scene: Scene, max_slope: float, edges: tuple[float, ...]) -> Scene:
    """The scene with its road cut by the slope rule at ``max_slope`` from the stated ``edges``
    (names: the scene's for its own scales, micro3, micro4, ... below)."""
    n = len(edges) - 1
    base = list(scene.surface.stated.names if scene.surface.stated else scene.surface.names)
    base = base or scale_names(scene.surface.n_scales)
    names = (base + [f"micro{i}" for i in range(len(base) - 1, n + 1)])[:n]
    return with_surface(scene, cutoff="slope", max_slope=max_slope, edges=tuple(edges),
                        names=tuple(names))


def point_rows(scene: Scene, max_slope: float, fe: dict[float, Any] | None) -> list[dict]:
    """Rows per velocity: the kept spectrum, theory and (``fe``: v -> PointResult) FE mu."""
    theory = evaluate(request_from_scene(scene, models=MODELS))
    curves = {c.model: c for c in theory.curves}
    rep = scene.surface.cutoff_report
    rows = []
    for i, v in enumerate(scene.conditions.velocities):
        r = fe.get(v) if fe else None
        mu = r.mu if r is not None and r.ok else None
        rows.append({"max_slope": max_slope, "lowest_edge_mm": scene.surface.edges[-1],
                     "scales": scene.n_scales, "cumulative_slope": rep.cumulative_slope,
                     "v_mm_s": v, "mu_fe": mu.mean if mu else math.nan,
                     "mu_fe_ci95": mu.ci95 if mu else math.nan,
                     "mu_fe_samples": mu.n_used if mu else 0,
                     **{f"mu_{m}": float(curves[m].mu[i]) if m in curves else math.nan
                        for m in MODELS}})
    return rows


def plot(rows: list[dict], path: Path) -> Path:
    """mu(v) per max_slope: FE with error bars, Persson isotropic (x, dashed) and line (+,
    dotted)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.5))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    for k, m in enumerate(sorted({r["max_slope"] for r in rows})):
        rs = [r for r in rows if r["max_slope"] == m]
        v = [r["v_mm_s"] for r in rs]
        lab = f"max_slope {m:g} (to {rs[0]['lowest_edge_mm'] * 1e3:.3g} um)"
        fe = [r["mu_fe"] for r in rs]
        if any(math.isfinite(x) for x in fe):
            err = [r["mu_fe_ci95"] if math.isfinite(r["mu_fe_ci95"]) else 0.0 for r in rs]
            ax.errorbar(v, fe, yerr=err, fmt="o-", color=f"C{k}", capsize=3, label=f"FE, {lab}")
        ax.plot(v, [r["mu_persson-2d"] for r in rs], "x--", color=f"C{k}",
                label=f"Persson 2D, {lab}")  # markers: one velocity is a point, not a line
        ax.plot(v, [r["mu_persson-1d"] for r in rs], "+:", color=f"C{k}")
    ax.set_xscale("log")
    ax.set_xlabel("sliding velocity v (mm/s)")
    ax.set_ylabel("coefficient of friction mu (hysteresis)")
    ax.set_title("cut-off sensitivity (x dashed: Persson 2D; + dotted: Persson line roughness)",
                 fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench cutoff", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="four_scale", help="shipped scene or file (four_scale)")
    ap.add_argument("--max-slopes", nargs="+", type=float, default=[1.0, 1.3, 2.0])
    ap.add_argument("--edges", nargs="+", type=float,
                    default=[20.0, 3.0, 0.3, 0.04, 0.003, 0.0002],
                    help="stated edges, mm (default: the thesis edges and one decade below)")
    ap.add_argument("--velocities", nargs="+", type=float, default=[10.0, 100.0, 1000.0])
    ap.add_argument("--pressure", type=float, help="MPa (default: the scene's first)")
    ap.add_argument("--samples", nargs=2, type=int, default=[1, 2], metavar=("K", "J"))
    ap.add_argument("--no-fe", action="store_true", help="theory only (seconds)")
    ap.add_argument("--out", default="rf-bench/cutoff")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if any(not m > 0 for m in a.max_slopes) or any(not v > 0 for v in a.velocities):
        ap.error("--max-slopes and --velocities: expected values > 0")
    if min(a.samples) < 1:
        ap.error(f"--samples {a.samples[0]} {a.samples[1]}: expected counts >= 1")
    try:
        base = load_scene(a.scene).with_samples(*a.samples)
        cond = {"velocities": tuple(a.velocities)}
        if a.pressure is not None:
            cond["pressures"] = (a.pressure,)
        base = override(base, conditions=cond)
        scenes = {m: cut_scene(base, m, tuple(a.edges)) for m in a.max_slopes}
    except SceneError as err:
        ap.error(str(err))
    out = Path(a.out)
    rows: list[dict] = []
    for m, scene in scenes.items():
        fe = None
        if not a.no_fe:
            res = run_scene(override(scene, name=f"cutoff-{m:g}"),
                            output=out / f"max_slope={m:g}", quiet=a.quiet, report=False)
            if res is None:  # an MPI worker rank
                continue
            fe = {r.point.velocity: r for r in res.points}
        rows.extend(point_rows(scene, m, fe))
        print(f"[cutoff] max_slope {m:g}: edges " + ", ".join(
            f"{e:.4g}" for e in scene.surface.edges) + " mm", flush=True)
    if not rows:
        return 0
    print(f"\ncut-off sensitivity, scene {base.name}, p = {base.conditions.pressures[0]:g} MPa")
    print(f"{'max_slope':>9} {'to (um)':>8} {'n':>2} {'v mm/s':>8} {'mu FE':>8} {'+-95%':>7} "
          f"{'Persson1D':>9} {'Persson2D':>9}")
    for r in rows:
        print(f"{r['max_slope']:9g} {r['lowest_edge_mm'] * 1e3:8.3g} {r['scales']:2d} "
              f"{r['v_mm_s']:8g} {r['mu_fe']:8.4g} {r['mu_fe_ci95']:7.2g} "
              f"{r['mu_persson-1d']:9.4g} {r['mu_persson-2d']:9.4g}")
    out.mkdir(parents=True, exist_ok=True)
    with (out / "cutoff.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"table: {out / 'cutoff.csv'}; plot: {plot(rows, out / 'cutoff.png')}")
    return 0
