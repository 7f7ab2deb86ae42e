"""A thermal scene in coupled mode (``[thermal] mode = "coupled"``): the thermal multiscale loop
(``thermal_loop``) for every (compound, p, v), the lower scales from the scene's rough cascade;
or in hot-layer mode (``mode = "hot-layer"``, thesis 8.5.3): the cascade once per surface
temperature of a grid with a hot layer, then the macro run with that mu(T_S) law.

Outputs under ``<output>/``: ``store/`` (every lower-scale run, keyed with its partition
temperatures) and ``thermal/``:

* ``mu_v.png`` -- the lower scales' mu(v) with and without flash temperature and the relative
  change, beside Persson's line-roughness theory with and without its flash temperature;
* ``loop_results.csv`` -- one row per point: the macro road (``road_surface``: flat or rough),
  status (ok, "not stationary": no stationary window, mu is the last half's mean, or failed),
  mu without flash temperature (flat road: the isothermal cascade plus mu_const; rough road: the
  isothermal macro run's stationary mean) and with it (the stationary mean of the macro mu,
  ``thermal_loop`` module doc), their relative difference, whether the window was stationary,
  the window (s from, to, mm) and its drift, mu_end (the macro contact's mu at the slide's
  end), the final surface temperature of the profile (eq. 8.1), the macro run's stabilised
  sub-steps and the dashpots' share of its friction work, wall time, the
  isothermal cascade's wall time (what the isothermal point costs; hot-layer mode: the sum of its
  runs' times, its cascades run side by side) and the ratio of the two (nan where the store
  answered runs: ``reused_runs``);
* ``<point>/intervals.csv`` -- per homogenisation point: s, t, the mu used before it and the mu
  the cascade returned, the per-scale mu, the profile's surface value and spread, the partition
  temperatures and the cascade's wall time;
* ``<point>/profiles.csv`` -- T(z) (eq. 8.1) and its standard deviation at every point;
* ``<point>/loop.png`` -- macro mu(s) with the homogenisation points, the lower scales' mu per
  interval, the T(z) profiles with their std bands and the partitions (thesis fig. 8.3 a, 8.4 a);
* ``<point>/series.csv``, ``interface.csv``, ``temperature.xdmf``, ``thermal.png`` -- the macro run
  (as in the given mode, ``thermal_scene.write_run``);
* hot-layer mode: ``<point>/hot_layer.csv`` (T_S, the lower scales' mu and the per-scale mu) and
  ``hot_layer.png`` (mu(T_S) and the macro mu(s)) instead of the interval files.

MPI: rank 0 runs the macro runs and the loop; every cascade is farmed over all ranks.
"""

from __future__ import annotations

import csv
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction.driver.multiscale.campaign import open_store, runner_and_timeout
from rubberfriction.driver.multiscale.results import Point
from rubberfriction.driver.multiscale.scales import build_scales
from rubberfriction.driver.scenes import Scene, SceneError
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
from rubberfriction.driver.multiscale.thermal_loop import (
    CascadeRunner,
    HotLayerResult,
    HotLayerSettings,
    LoopSettings,
    ThermalLoopResult,
    run_hot_layer,
    run_thermal_loop,
)
from rubberfriction.driver.multiscale.thermal_scene import (
    _csv,
    _materials,
    _T0,
    macro_inputs,
    write_run,
)
from rubberfriction.driver.runtime.farm import Executor, RunReports
from rubberfriction.driver.runtime.progress import Progress


def loop_settings(scene: Scene) -> LoopSettings:
    t = scene.thermal
    return LoopSettings(divisions=t.divisions, points=tuple(t.points), n_partitions=t.partitions,
                        partition_depth=t.partition_depth, mu_const=t.mu_const, auto_dT=t.auto_dT,
                        max_points=t.max_points, rough=t.road_surface == "macro",
                        blocks=t.stationary_blocks, tol=t.stationary_tol)


def hot_layer_settings(scene: Scene) -> HotLayerSettings:
    t = scene.thermal
    return HotLayerSettings(rises=tuple(t.hot_layer_rises), layer=t.hot_layer,
                            transition=t.hot_transition, mu_const=t.mu_const,
                            rough=t.road_surface == "macro", blocks=t.stationary_blocks,
                            tol=t.stationary_tol)


def run_coupled_scene(scene: Scene, *, quiet: bool = False, comm: Any = None,
                      fresh: bool = False) -> list[ThermalLoopResult | HotLayerResult] | None:
    """Every rank calls this; rank 0 returns the loop results (the others None)."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD if comm is None else comm
    t = scene.thermal
    if scene.variant != "rough":
        raise SceneError(f"{scene.source}: [thermal] mode = '{t.mode}' needs variant = \"rough\" "
                         "(the loop redoes the rough cascade at each homogenisation point)")
    loop = loop_settings(scene)
    out = Path(scene.output)
    store = open_store(out, comm, fresh=fresh)
    try:
        reports = RunReports()  # every sliding step of a lower-scale run reaches the progress line
        runner, timeout = runner_and_timeout(scene, None, reports)
        executor = Executor(store, runner, timeout=timeout, reports=reports,
                            settings={"scene": scene.name, "scene_source": scene.source,
                                      "thermal": t.mode})
        compounds = load_compounds(scene)
        n = max(scene.samples.pressure, scene.samples.friction)
        scales = build_scales(scene, n)
        make_spec = SpecBuilder(scene, compounds)
        if comm.Get_rank() != 0:
            CascadeRunner(scene.name, None, scales.sets, make_spec, scene.samples.pressure,
                          scene.samples.friction, executor, comm).serve()
            return None
        results = []
        try:
            progress = None if quiet else (lambda title: Progress(title=title))
            results = _points(scene, loop, scales, make_spec, executor, comm, quiet, progress)
        finally:
            CascadeRunner(scene.name, None, scales.sets, make_spec, 1, 1, executor, comm).done()
        return results
    finally:
        store.unlock()


def _points(scene, loop, scales, make_spec, executor, comm, quiet,
            progress=None) -> list[ThermalLoopResult]:
    t = scene.thermal
    num = scene.numerics
    materials, road = _materials(scene)
    folder = Path(scene.output) / "thermal"
    folder.mkdir(parents=True, exist_ok=True)
    log = None if quiet else (lambda msg: print(msg, flush=True))
    todo = [(name, c, p, v) for name, c in materials for p in scene.conditions.pressures
            for v in scene.conditions.velocities]
    results: list[ThermalLoopResult] = []
    rows = []
    for i, (name, comp, p, v) in enumerate(todo, 1):
        T0 = _T0(scene, comp)
        label = f"{name}_p{p:g}_v{v:g}"
        if log and t.mode == "coupled":
            where = (f"automatic points (every {loop.auto_dT:g} K)" if loop.auto_dT > 0 else
                     f"{len(loop.distances(t.slide_distance))} homogenisation points")
            log(f"[thermal loop] point {i}/{len(todo)}: {label}, {where}, {loop.n_partitions} "
                f"partitions over {loop.partition_depth} mm")
        elif log:
            log(f"[thermal loop] point {i}/{len(todo)}: {label}, hot layer {t.hot_layer} mm at "
                f"T_S, {len(t.hot_layer_rises)} surface temperatures")
        spec, settings = macro_inputs(scene, comp, road, p, v, T0, 0.0)  # friction: from the loop
        cascade = CascadeRunner(scene.name, Point(name, p, v), scales.sets, make_spec,
                                scene.samples.pressure, scene.samples.friction, executor, comm,
                                progress=progress,
                                max_failed_fraction=scene.samples.max_failed_fraction,
                                adhesion=scene.adhesion if scene.physics.adhesion else None,
                                states=(executor.store.load_state
                                        if t.mode == "coupled" and t.warm_start else None),
                                warm_window=t.warm_window_periods)
        wall = time.perf_counter()
        try:
            if t.mode == "hot-layer":
                res = run_hot_layer(spec, comp.thermal, settings, hot_layer_settings(scene),
                                    cascade, wall_limit=num.run_timeout, log=log)
            else:
                res = run_thermal_loop(spec, comp.thermal, settings, loop, cascade,
                                       wall_limit=num.run_timeout, log=log)
        except Exception as err:  # noqa: BLE001 -- a campaign never dies of one point
            res = ThermalLoopResult(Point(name, p, v), None, None, settings=loop)
            res.error = f"{type(err).__name__}: {err}"
            res.notes.append(res.error)
        res.wall = time.perf_counter() - wall
        results.append(res)
        sub = folder / label
        sub.mkdir(exist_ok=True)
        if isinstance(res, HotLayerResult):
            write_hot_layer(res, sub, T0)
        else:
            write_loop(res, sub, T0)
        rows.append(_row(name, p, v, res, T0))
        if log:
            r = rows[-1]
            log(f"[thermal loop]   mu {r['mu_isothermal']:.4g} without, {r['mu_flash']:.4g} with "
                f"flash temperature ({100 * r['change']:+.2f} %; {r['status']}), surface "
                f"{r['T_surface'] - T0:+.3g} K, "
                f"{res.wall:.1f} s{'; ' + '; '.join(res.notes) if res.notes else ''}")
    _write_rows(folder / "loop_results.csv", rows)
    for note in plot_mu_v(scene, rows, folder / "mu_v.png"):
        if log:
            log(f"[thermal loop] {note}")
    if log:
        log(f"[thermal loop] results: {folder / 'loop_results.csv'}, {folder / 'mu_v.png'}")
    return results


def _row(name: str, p: float, v: float, res, T0: float) -> dict:
    if isinstance(res, HotLayerResult):
        iso, mode, points = res.mu_isothermal, "hot-layer", len(res.temperatures)
        s = res.macro.series if res.macro is not None else {}
        T_s = float(s["T_contact"][-1]) if s else math.nan
        T_std = math.nan
        # the isothermal cascade ran side by side with the others: its runs' time is its cost
        wall_iso = res.cascades[0].wall_time if res.cascades else math.nan
        cascades = res.cascades
    else:
        iso = res.mu_isothermal if res.isothermal is not None else math.nan
        last = res.intervals[-1] if res.intervals else None
        mode, points = "coupled", len(res.intervals)
        T_s = last.profile.mean[0] if last else math.nan
        T_std = last.profile.std[0] if last else math.nan
        wall_iso = res.wall_isothermal
        cascades = [c for c in (res.isothermal, *(iv.cascade for iv in res.intervals))
                    if c is not None]
    # a store that answered runs makes the times say nothing about the cost
    reused = sum(o.reused for c in cascades for runs in c.runs.values() for _, o in runs)
    cost = res.wall / wall_iso if wall_iso > 0 and not reused else math.nan
    avg = res.average
    status = ("failed" if not res.ok else "ok" if res.stationary else "not stationary")
    return {"compound": name, "pressure": p, "velocity": v, "mode": mode,
            "macro_road": "rough" if res.settings.rough else "flat", "status": status,
            "mu_isothermal": iso, "mu_flash": res.mu,
            "change": res.mu / iso - 1.0 if iso else math.nan,
            "stationary": bool(res.stationary),
            "mu_window_start": avg.lo if avg else math.nan,
            "mu_window_end": avg.hi if avg else math.nan,
            "mu_window_drift": avg.drift if avg else math.nan,
            "mu_end": res.mu_end,
            "mu_const": res.settings.mu_const, "points": points, "T_surface": T_s,
            "T_surface_std": T_std,
            **_macro_stabilisation(res.macro), "wall": res.wall, "wall_isothermal": wall_iso,
            "cost_vs_isothermal": cost, "reused_runs": reused, "notes": " | ".join(res.notes)}


def _macro_stabilisation(macro) -> dict:
    """The macro run's stabilised sub-steps and the dashpots' share of its friction work."""
    if macro is None:
        return {"macro_stabilised_steps": math.nan, "macro_stabilisation_share": math.nan}
    return {"macro_stabilised_steps": float(macro.sliding.stats.get("stabilised_steps", math.nan)),
            "macro_stabilisation_share": float(macro.sliding.stabilisation_share)}


def _write_rows(path: Path, rows: list[dict]) -> None:
    if not rows:
        return
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def write_loop(res: ThermalLoopResult, folder: Path, T0: float) -> None:
    """intervals.csv, profiles.csv, loop.png and the macro run's files."""
    if res.macro is not None:
        write_run(res.macro, folder, T0)
    if not res.intervals:
        return
    n_p = len(res.intervals[0].partitions.layers)
    names = [sc.name for sc in res.intervals[0].cascade.scales]
    rows = []
    for iv in res.intervals:
        row = {"point": iv.index, "s": iv.s_end, "t": iv.t_end, "mu_in": iv.mu_in,
               "mu_out": iv.mu_out,
               "T_surface": iv.profile.mean[0], "T_surface_std": iv.profile.std[0],
               "active_nodes": iv.profile.n_active}
        for sc in iv.cascade.scales:
            row[f"mu_{sc.name}"] = sc.mu.mean if sc.mu is not None else math.nan
        for k, (d, T) in enumerate(iv.partitions.layers, 1):
            row[f"T_partition_{k}"] = T
        row["T_below"] = iv.partitions.background
        row["cascade_wall"] = iv.wall
        rows.append(row)
    _write_rows(folder / "intervals.csv", rows)
    cols = {"z": res.intervals[0].profile.z}
    for iv in res.intervals:
        cols[f"T_mean_{iv.index}"] = iv.profile.mean
        cols[f"T_std_{iv.index}"] = iv.profile.std
    _csv(folder / "profiles.csv", cols)
    plot_loop(res, folder / "loop.png", T0, names, n_p)


def plot_loop(res: ThermalLoopResult, path: Path, T0: float, scale_names: list[str],
              n_p: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    if res.macro is not None and res.macro.series:
        s = res.macro.series
        ax[0].plot(s["s"], s["mu"], label="macro mu = -F_x / F_z")
    for iv in res.intervals:
        ax[0].axvline(iv.s_end, color="0.7", lw=0.8)
    ax[0].axhline(res.mu_isothermal, color="k", ls=":", label="isothermal mu")
    ax[0].set(xlabel="sliding distance s (mm)", ylabel="mu",
              title="macro run, homogenisation points")
    ax[0].legend(fontsize=8)
    s_edges = [0.0] + [iv.s_end for iv in res.intervals]
    mus = [iv.mu_in for iv in res.intervals]
    ax[1].step(s_edges, mus + mus[-1:], where="post", label="lower scales' mu used")
    ax[1].plot([iv.s_end for iv in res.intervals], [iv.mu_out for iv in res.intervals], "o",
               label="cascade at the point")
    ax[1].set(xlabel="s (mm)", ylabel="mu of the lower scales", title="per interval")
    ax[1].legend(fontsize=8)
    depth = res.settings.partition_depth
    for iv in res.intervals:
        z, m, sd = iv.profile.z, iv.profile.mean - T0, iv.profile.std
        keep = z <= 3 * depth
        line, = ax[2].plot(m[keep], z[keep], label=f"s = {iv.s_end:.3g} mm")
        ax[2].fill_betweenx(z[keep], m[keep] - sd[keep], m[keep] + sd[keep],
                            color=line.get_color(), alpha=0.15)
        b = iv.partitions.bounds
        T_p = np.repeat([T - T0 for _, T in iv.partitions.layers], 2)
        ax[2].plot(T_p, np.repeat(b, 2)[1:-1], color=line.get_color(), ls="--", lw=0.8)
    ax[2].invert_yaxis()
    ax[2].set(xlabel="T - T0 (K)", ylabel="depth below the contact face (mm)",
              title=f"eq. (8.1) profiles +- std, {n_p} partitions (dashed)")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_hot_layer(res: HotLayerResult, folder: Path, T0: float) -> None:
    """hot_layer.csv, hot_layer.png and the macro run's files."""
    if res.macro is not None:
        write_run(res.macro, folder, T0)
    rows = []
    for T_S, mu, c in zip(res.temperatures, res.mu_lower, res.cascades):
        row = {"T_S": T_S, "mu_lower": mu, "mu_macro_scale": res.settings.mu_const + mu}
        for sc in c.scales:
            row[f"mu_{sc.name}"] = sc.mu.mean if sc.mu is not None else math.nan
        rows.append(row)
    _write_rows(folder / "hot_layer.csv", rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(res.temperatures - T0, res.settings.mu_const + res.mu_lower, "o-")
    ax[0].set(xlabel="surface temperature T_S - T0 (K)", ylabel="mu_const + lower scales' mu",
              title=f"hot layer {1e3 * res.settings.layer:g} um at T_S, "
                    f"to {1e3 * res.settings.transition:g} um")
    if res.macro is not None and res.macro.series:
        s = res.macro.series
        ax[1].plot(s["s"], s["mu"], label="macro mu = -F_x / F_z")
        ax[1].axhline(res.mu_isothermal, color="k", ls=":", label="isothermal")
        ax[1].legend(fontsize=8)
    ax[1].set(xlabel="sliding distance s (mm)", ylabel="mu", title="macro run with mu(T_S)")
    fig.tight_layout()
    fig.savefig(folder / "hot_layer.png", dpi=110)
    plt.close(fig)


def plot_mu_v(scene: Scene, rows: list[dict], path: Path) -> list[str]:
    """mu(v) with and without flash temperature per (compound, p), beside Persson's line-roughness
    theory with and without its flash temperature (``theory --flash``, same surface and
    compound): the lower scales' mu (FE mu - mu_const, the part the theory models) and the
    relative change by flash temperature.  Returns notes (a theory failure never breaks it)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rubberfriction.driver.multiscale.baseline import evaluate, request_from_scene

    notes: list[str] = []
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    groups = sorted({(r["compound"], r["pressure"]) for r in rows})
    for g, (name, p) in enumerate(groups):
        sel = sorted((r for r in rows if (r["compound"], r["pressure"]) == (name, p)),
                     key=lambda r: r["velocity"])
        v = np.array([r["velocity"] for r in sel])
        iso = np.array([r["mu_isothermal"] - r["mu_const"] for r in sel])
        hot = np.array([r["mu_flash"] - r["mu_const"] for r in sel])
        c = f"C{g}"
        ax[0].plot(v, iso, "o-", color=c, label=f"FE {name}, {p:g} MPa: isothermal")
        ax[0].plot(v, hot, "s--", color=c, label="FE: with flash temperature")
        ax[1].plot(v, 100 * (hot / iso - 1), "s-", color=c, label=f"FE {name}, {p:g} MPa")
        try:
            comp = dict(zip(scene.conditions.compounds, scene.conditions.compound_paths))[name]
            grid = tuple(np.geomspace(v.min() / 3, v.max() * 3, 30))
            curves = {}
            for flash in (False, True):
                req = request_from_scene(scene, velocities=grid, compound=str(comp),
                                         pressure=float(p), T0=scene.conditions.T0,
                                         models=("persson-1d",), flash=flash)
                curves[flash] = evaluate(req).curves[0]
            ax[0].plot(curves[False].v, curves[False].mu_hysteresis, ":", color=c,
                       label="Persson (line)")
            ax[0].plot(curves[True].v, curves[True].mu_hysteresis, "-.", color=c,
                       label="Persson with flash")
            ax[1].plot(curves[True].v,
                       100 * (curves[True].mu_hysteresis / curves[False].mu_hysteresis - 1), "-.",
                       color=c, label="Persson with flash")
        except Exception as err:  # noqa: BLE001 -- the baseline must never break the outputs
            notes.append(f"{name}, {p:g} MPa: Persson curves not drawn: "
                         f"{type(err).__name__}: {err}")
    ax[0].set(xscale="log", xlabel="v (mm/s)", ylabel="mu of the lower scales (hysteresis)",
              title="with and without flash temperature")
    ax[1].set(xscale="log", xlabel="v (mm/s)", ylabel="change by flash temperature (%)",
              title="relative change")
    for a in ax:
        a.legend(fontsize=7)
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return notes
