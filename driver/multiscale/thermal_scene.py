"""A thermal scene (``[physics].thermal = true``) whose friction is given (``[thermal].mu`` or a
mu(T_s) curve): one thermomechanical macro run (``driver.thermal.macro``) per compound, pressure
and velocity, with no lower scales.

Outputs under ``<output>/thermal/``:

* ``thermal_results.csv`` -- one row per run: status, mu (force, window average) with its error
  estimate mu_error (half the relative drift of mu over the window, the fixed-window rule of the
  isothermal runs; the contact temperature keeps rising in a finite slide), end values of
  the contact temperature T_C, the hottest rubber surface node, the road behind the block T_R,
  the largest temperature change per step (the staggered scheme's lag), wall time, the sub-steps
  solved with the viscous stabilisation and the dashpots' share of the friction work (above 5 %
  the stabilisation, not the rubber, carries a visible part of mu), the smallest det F;
* ``<run>/series.csv`` -- per sliding step: t, s, mu, T_contact, T_max, T_road_behind, heat in
  block and road, frictional energy, probes;
* ``<run>/interface.csv`` -- the final profile along the block: x, T_block, pressure, frictional
  power density, mu;
* ``<run>/temperature.xdmf`` -- the final temperature field of both bodies (ParaView);
* ``<run>/surface_history.csv`` / ``.png`` -- the rubber surface along the block and the road
  surface (the heated track behind the block) over the sliding distance;
* ``<run>/thermal.png`` -- mu(s), temperatures(s), heat balance and the final interface profile;
* with ``slides`` > 1: ``<run>/slide_<k>/`` holds the files above per slide and
  ``<run>/history.csv`` the whole sequence (global time, slide number or 0 in a pause, mean rubber
  surface temperature, probes); the summary row is the last slide's.

The runs are dealt out over the ranks (each is seconds to minutes).  The road is flat (its
roughness acts through mu) or the macro band of the scene's surface (``road_surface = "macro"``;
then the given mu is that of the scales below), rigid or elastic (``road_mechanics``).
"""

from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from rubberfriction.driver.fe.contact import ThermalSettings
from rubberfriction.driver.fe.friction_law import fit_mu_pvT
from rubberfriction.driver.multiscale.scales import macro_road
from rubberfriction.driver.scenes import Scene, SceneError
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.thermal.macro import (
    MacroSettings,
    ThermalMacroResult,
    flat_road_spec,
    run_thermal_macro,
    run_thermal_slides,
)
from rubberfriction.forms.compound import Road
from rubberfriction.forms.material_files import load_compound, load_road


@dataclass
class ThermalRunSummary:
    compound: str
    pressure: float
    velocity: float
    status: str
    reason: str
    mu_force: float
    T_contact: float
    T_max: float
    T_road_behind: float
    max_step_dT: float
    wall: float
    folder: Path
    steps: float = math.nan
    cutbacks: float = math.nan
    newton_iterations: float = math.nan
    cpu_heat: float = math.nan
    cpu_contact: float = math.nan
    # half the window drift of mu: how far from steady the average may be
    mu_error: float = math.nan
    # sub-steps solved with the viscous stabilisation and the dashpots' share of the window's
    # friction work (driver.fe.stabilisation); smallest det F of the accepted states
    stabilised_steps: float = math.nan
    stabilisation_share: float = math.nan
    min_det_F: float = math.nan

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def friction_of(scene: Scene):
    """The macro friction: a float, or a mu(p, v, T) spline linear in T through mu_curve (constant
    in p and v, clamped beyond the curve's ends)."""
    t = scene.thermal
    if t.mu is not None:
        return float(t.mu)
    T = np.array([a for a, _ in t.mu_curve])
    mu = np.array([b for _, b in t.mu_curve])
    grid = np.broadcast_to(mu, (2, 2, T.size)).copy()
    return fit_mu_pvT([0.0, 1.0e3], [1.0e-9, 1.0e7], T, grid, degree=1)


def _materials(scene: Scene):
    compounds = []
    for name, path in zip(scene.conditions.compounds, scene.conditions.compound_paths):
        c = load_compound(path)
        if c.thermal is None:
            raise SceneError(f"{scene.source}: [conditions].compounds: compound {name!r} has no "
                             "[thermal] data (rho, c, k), which a thermal scene needs")
        compounds.append((name, c))
    road = load_road(scene.thermal.road)
    if road.thermal is None:
        raise SceneError(f"{scene.source}: [thermal].road = {scene.thermal.road!r} has no "
                         "[thermal] data")
    return compounds, road


def macro_inputs(scene: Scene, compound, road: Road, pressure: float, velocity: float, T0: float,
                 friction) -> tuple[SlidingSpec, MacroSettings]:
    """The macro run's mechanical spec and thermal settings from a thermal scene's tables: a flat
    road, or the macro band of the scene's surface (``road_surface = "macro"``); the road rigid or
    elastic with the road material's E and nu (``road_mechanics``)."""
    t, num = scene.thermal, scene.numerics
    spec = flat_road_spec(compound, pressure=pressure, velocity=velocity, friction=friction,
                          block_length=t.block_length, block_height=t.block_height,
                          slide_distance=t.slide_distance, h_contact=t.h_contact, T0=T0,
                          step_per_element=t.step_per_element, element=num.element,
                          contact=num.contact,
                          grading=num.grading, compression_steps=num.compression_steps,
                          max_cutbacks=num.max_cutbacks, stabilisation=num.stabilisation,
                          min_jacobian=num.min_jacobian,
                          penalty_alpha=num.penalty_alpha,
                          tangential_penalty=num.tangential_penalty,
                          newton_rtol=num.newton_rtol,
                          edge_radius=t.edge_radius)
    if t.road_surface == "macro":
        span = t.slide_distance + t.block_length  # the flat road's extent, [-span, 2 span]
        short = scene.surface.edges[1] if scene.surface.edges else scene.surface.wavelengths[0]
        x, h = macro_road(scene, t.road_start, 3.0 * span, min(0.5 * t.h_contact, short / 16.0))
        spec = replace(spec, surface_x=x - span, surface_h=h)
    settings = MacroSettings(road=road.thermal, T0=T0,
                             interface=ThermalSettings(h0=t.h_c, kappa=t.kappa),
                             road_depth=t.road_depth, road_ahead=t.road_ahead,
                             road_behind=t.road_behind, first_layer=t.first_layer,
                             grading=t.grading, probes=t.probes, bulk_wlf=t.bulk_wlf,
                             road_elastic=road if t.road_mechanics == "elastic" else None)
    return spec, settings


def _T0(scene: Scene, compound) -> float:
    if scene.conditions.T0 is not None:
        return scene.conditions.T0
    return compound.wlf.T_ref if compound.wlf is not None else 293.15


def run_thermal_scene(scene: Scene, *, quiet: bool = False,
                      comm=None) -> list[ThermalRunSummary] | None:
    """Run every (compound, p, v) of a thermal scene; a failed run is reported, never raised.

    Every rank of ``comm`` (default COMM_WORLD) calls this: the runs are dealt out round robin (each
    is serial and deterministic, so the results do not depend on the number of ranks) and rank 0
    gathers the summaries, writes thermal_results.csv and returns them (the others None)."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD if comm is None else comm
    rank, size = comm.Get_rank(), comm.Get_size()
    t = scene.thermal
    if t is None:
        raise SceneError(f"{scene.source}: not a thermal scene ([physics].thermal = false)")
    if t.mode != "given":
        raise SceneError(f"{scene.source}: [thermal] mode = {t.mode!r}: run it with "
                         "thermal_loop_scene.run_coupled_scene (rubberfriction run does)")
    compounds, road = _materials(scene)
    friction = friction_of(scene)
    out = Path(scene.output) / "thermal"
    if rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    if size > 1:
        comm.Barrier()
    num = scene.numerics
    todo = [(n, c, p, v) for n, c in compounds for p in scene.conditions.pressures
            for v in scene.conditions.velocities]
    quiet = quiet or rank != 0  # workers print nothing; rank 0 reports its own runs and the table
    summaries = []
    for i, (name, comp, p, v) in enumerate(todo, 1):
        if (i - 1) % size != rank:
            continue
        T0 = _T0(scene, comp)
        spec, settings = macro_inputs(scene, comp, road, p, v, T0, friction)
        label = f"{name}_p{p:g}_v{v:g}"
        if not quiet:
            print(f"[thermal] run {i}/{len(todo)}: {label} (block {t.block_length} x "
                  f"{t.block_height} mm, slide {t.slide_distance} mm)", flush=True)
        wall = time.perf_counter()
        folder = out / label
        folder.mkdir(exist_ok=True)
        try:
            if t.slides > 1:
                seq = run_thermal_slides(spec, comp.thermal, settings, t.pauses,
                                         wall_limit=num.run_timeout)
                for k, r in enumerate(seq.slides, 1):
                    (folder / f"slide_{k}").mkdir(exist_ok=True)
                    write_run(r, folder / f"slide_{k}", T0)
                _csv(folder / "history.csv", seq.history)
                res = seq.slides[-1]
            else:
                res = run_thermal_macro(spec, comp.thermal, settings, wall_limit=num.run_timeout)
        except Exception as err:  # noqa: BLE001 -- a campaign never dies of one run
            res = None
            reason = f"{type(err).__name__}: {err}"
        wall = time.perf_counter() - wall
        if res is not None:
            summary = _summarise(name, p, v, res, wall, folder)
            if t.slides == 1:
                write_run(res, folder, T0)
        else:
            summary = ThermalRunSummary(name, p, v, "failed", reason, *[math.nan] * 5, wall, folder)
        summaries.append(summary)
        if not quiet:
            print(f"[thermal]   {summary.status} {summary.reason}  mu {summary.mu_force:.4g} "
                  f"(+- {100 * summary.mu_error:.2g} % from the window drift)  T_C "
                  f"{summary.T_contact - T0:+.3g} K  T_R {summary.T_road_behind - T0:+.3g} K  "
                  f"({wall:.1f} s, {summary.steps:.0f} steps, {summary.cutbacks:.0f} cut-backs, "
                  f"{summary.newton_iterations:.0f} Newton iterations, heat "
                  f"{summary.cpu_heat:.1f} s CPU{_stabilised(summary)})",
                  flush=True)
    if size > 1:
        parts = comm.gather(summaries, root=0)
        if rank != 0:
            return None
        order = {(n, p, v): k for k, (n, _, p, v) in enumerate(todo)}
        summaries = sorted((s for part in parts for s in part),
                           key=lambda s: order[(s.compound, s.pressure, s.velocity)])
    write_summary(out / "thermal_results.csv", summaries)
    if not quiet:
        print(f"[thermal] results: {out / 'thermal_results.csv'}")
    return summaries


def _stabilised(s: ThermalRunSummary) -> str:
    """', N stabilised sub-steps (share x % of the friction work)' where there were any."""
    if not s.stabilised_steps > 0:
        return ""
    share = 100 * s.stabilisation_share
    return f", {s.stabilised_steps:.0f} stabilised sub-steps (share {share:.2g} %)"


def _summarise(name, p, v, res: ThermalMacroResult, wall: float, folder: Path) -> ThermalRunSummary:
    s = res.series
    end = (lambda k: float(s[k][-1])) if s and len(s["t"]) else (lambda k: math.nan)
    status = "ok" if res.ok else "failed"
    reason = res.stats.get("thermal_error", "") or res.sliding.reason
    st = res.sliding.stats
    return ThermalRunSummary(name, p, v, status, reason, float(res.sliding.mu_force),
                             end("T_contact"), end("T_max"), end("T_road_behind"),
                             float(res.stats.get("max_step_dT", math.nan)),
                             wall, folder, float(st.get("steps", math.nan)),
                             float(st.get("cutbacks", math.nan)),
                             float(st.get("newton_iterations", math.nan)),
                             float(res.stats.get("cpu_heat", math.nan)),
                             float(st.get("cpu_contact", math.nan)), float(res.sliding.mu_error),
                             float(st.get("stabilised_steps", math.nan)),
                             float(res.sliding.stabilisation_share),
                             float(res.sliding.min_det_F))


def write_summary(path: Path, rows: list[ThermalRunSummary]) -> None:
    cols = ["compound", "pressure", "velocity", "status", "mu_force", "mu_error", "T_contact",
            "T_max", "T_road_behind", "max_step_dT", "wall", "steps", "cutbacks",
            "newton_iterations", "cpu_heat", "cpu_contact",
            "stabilised_steps", "stabilisation_share", "min_det_F", "reason"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([getattr(r, c) for c in cols])


def write_run(res: ThermalMacroResult, folder: Path, T0: float) -> None:
    """series.csv, interface.csv, temperature.xdmf and thermal.png of one run."""
    if res.series:
        _csv(folder / "series.csv", res.series)
    if res.profiles:
        _csv(folder / "interface.csv", {k: np.asarray(v) for k, v in res.profiles.items()})
    heat = res.heat
    if heat is not None:
        from dolfinx.io import XDMFFile

        heat.T.name = "temperature"
        with XDMFFile(heat.mesh.comm, str(folder / "temperature.xdmf"), "w") as x:
            x.write_mesh(heat.mesh)
            x.write_function(heat.T, heat.time)
    if res.series and len(res.series["t"]):
        plot_run(res, folder / "thermal.png", T0)
    if res.surface_history:
        write_surface_history(res, folder, T0)


def write_surface_history(res: ThermalMacroResult, folder: Path, T0: float,
                          max_rows: int = 200) -> None:
    """surface_history.csv (long format: s, body, x, T; at most ``max_rows`` sliding steps, evenly
    picked, the last always) and surface_history.png: the rubber surface along the block and the
    road surface (the track behind the block, x < 0) over the sliding distance."""
    h, s = res.surface_history, res.series["s"]
    rows = np.unique(np.linspace(0, len(s) - 1, min(len(s), max_rows)).round().astype(int))
    with open(folder / "surface_history.csv", "w") as f:
        f.write("s,body,x,T\n")
        for k in rows:
            for body, x, T in (("block", h["x_block"], h["T_block"][k]),
                               ("road", h["x_road"], h["T_road"][k])):
                for xi, Ti in zip(x, T):
                    f.write(f"{s[k]:.8g},{body},{xi:.8g},{Ti:.8g}\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for a, key, xk, title in ((ax[0], "T_block", "x_block", "rubber surface"),
                              (ax[1], "T_road", "x_road",
                               "road surface (track behind the block: x < 0)")):
        m = a.pcolormesh(h[xk], s, h[key] - T0, shading="nearest", cmap="inferno")
        a.set(xlabel="x (mm, block frame, trailing edge 0)", title=title)
        fig.colorbar(m, ax=a, label="T - T0 (K)")
    ax[0].set_ylabel("sliding distance s (mm)")
    fig.tight_layout()
    fig.savefig(folder / "surface_history.png", dpi=110)
    plt.close(fig)


def _csv(path: Path, cols: dict) -> None:
    names = list(cols)
    arr = np.column_stack([np.asarray(cols[n], float) for n in names])
    np.savetxt(path, arr, delimiter=",", header=",".join(names), comments="", fmt="%.10g")


def plot_run(res: ThermalMacroResult, path: Path, T0: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s, p = res.series, res.profiles
    fig, ax = plt.subplots(2, 2, figsize=(10, 7))
    ax[0, 0].plot(s["s"], s["mu"])
    ax[0, 0].set(xlabel="sliding distance s (mm)", ylabel="mu = -F_x / F_z (contact)",
                 title="friction")
    for k, lab in (("T_contact", "contact (pressure-weighted)"), ("T_max", "hottest rubber node"),
                   ("T_road_behind", "road behind the block")):
        ax[0, 1].plot(s["s"], s[k] - T0, label=lab)
    ax[0, 1].set(xlabel="s (mm)", ylabel="T - T0 (K)", title="temperatures")
    ax[0, 1].legend(fontsize=8)
    ax[1, 0].plot(s["s"], s["friction_energy"], label="frictional heat in")
    ax[1, 0].plot(s["s"], s["heat_block"] + s["heat_road"], label="stored (block + road)")
    ax[1, 0].plot(s["s"], s["heat_block"], "--", label="stored in the block")
    ax[1, 0].set(xlabel="s (mm)", ylabel="mJ per mm depth",
                 title="heat balance (rest left through T0 faces)")
    ax[1, 0].legend(fontsize=8)
    if p:
        ax[1, 1].plot(p["x"], p["T_block"] - T0, label="T_block - T0 (K)")
        a2 = ax[1, 1].twinx()
        a2.plot(p["x"], p["pressure"], "k:", label="pressure")
        a2.set_ylabel("contact pressure (MPa)")
        ax[1, 1].set(xlabel="x along the block (mm, trailing edge 0)", ylabel="T - T0 (K)",
                     title="interface at the end")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
