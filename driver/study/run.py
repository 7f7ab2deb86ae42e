"""``rubberfriction study trends``: run the trend cases, collect the evidence, write the table.

The campaigns (``driver/study/cases.py``) run one after the other, each farmed over all ranks
like ``rubberfriction run``, with their reports in ``<out>/<case>/`` and one store,
``<out>/store``: a run two cases share (the polished road's unpolished scales are the base
road's) is computed once, and a second call resumes, reusing every finished run.  The flash
case keeps its own store in ``<out>/flash/``.  A case that fails (a
failed point, a failed thermal loop) leaves its rows "missing" with the reason; the study goes
on.  The sawtooth pair (two single-scale runs) runs on rank 0 and is kept in
``<out>/sawtooth.json``.  Everything the table reads is saved in ``<out>/evidence.json``;
``<out>/trends.txt``, ``trends.json`` and ``trends.png`` are the table.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from mpi4py import MPI

from rubberfriction.driver.multiscale.campaign import run_sample_study, run_scene
from rubberfriction.driver.multiscale.thermal_loop_scene import run_coupled_scene
from rubberfriction.driver.scenes import Scene, SceneError, parse_scene
from rubberfriction.driver.study.cases import (
    EDGES,
    MATERIALS,
    SCALES,
    TrendSettings,
    lowest_band,
    lowest_scale,
    scene_texts,
)
from rubberfriction.driver.study.evidence import (
    Evidence,
    SawtoothValue,
    SpreadValue,
    flash_values,
    point_key,
    point_value,
    strict_json,
)
from rubberfriction.driver.study.plots import plot_trends
from rubberfriction.driver.study.trends import TrendRow, build_rows, table_text, trends
from rubberfriction.driver.verification.sawtooth import sawtooth_mu
from rubberfriction.forms.material_files import load_compound


#: the cases that are multiscale campaigns (``rubberfriction run`` scenes), in run order
CAMPAIGNS = ("materials", "rough", "polished")


@dataclass
class StudyResult:
    """What ``study trends`` returns on rank 0."""

    rows: list[TrendRow]
    evidence: Evidence
    output: Path
    files: list[Path]
    wall_time: float
    case_times: dict[str, float]


def study_scenes(settings: TrendSettings, out: Path) -> dict[str, Scene]:
    """The cases' scenes, read from the TOML texts saved in ``<out>/scenes`` (rank 0 writes)."""
    folder = out / "scenes"
    scenes = {}
    for case, text in scene_texts(settings).items():
        path = folder / f"{case}.toml"
        if MPI.COMM_WORLD.Get_rank() == 0:
            folder.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        scene = parse_scene(text, str(path), folder)
        scenes[case] = scene.with_output(out / case)
    return scenes


def _log(quiet: bool) -> Callable[[str], None]:
    def log(msg: str) -> None:
        if not quiet and MPI.COMM_WORLD.Get_rank() == 0:
            print(f"[study trends] {msg}", flush=True)
    return log


def run_trends(settings: TrendSettings, out: str | Path, *, quiet: bool = False,
               fresh: bool = False, comm: Any = None) -> StudyResult | None:
    """Run (or resume) the trend study; every rank calls this, rank 0 returns the result."""
    comm = MPI.COMM_WORLD if comm is None else comm
    rank = comm.Get_rank()
    out = Path(out)
    log = _log(quiet)
    t0 = time.perf_counter()
    scenes = study_scenes(settings, out)
    if rank == 0:
        (out / "settings.json").write_text(json.dumps(settings.to_dict(), indent=1) + "\n")
    ev = Evidence(settings.to_dict())
    times: dict[str, float] = {}
    low = lowest_scale(settings)
    n_cases = len(scenes) + 1
    for i, case in enumerate(CAMPAIGNS, 1):
        log(f"case {i}/{n_cases}: {case}: {scenes[case].description}")
        t = time.perf_counter()
        res = run_scene(scenes[case], quiet=quiet, fresh=fresh and i == 1, comm=comm,
                        store_folder=out / "store")
        times[case] = time.perf_counter() - t
        if res is not None:
            for pt in res.points:
                ev.points[point_key(case, pt.point.compound, pt.point.velocity)] = point_value(pt)
    log(f"case 4/{n_cases}: spread: {settings.spread_samples} samples of {low} at "
        f"{settings.spread_pressure:g} MPa, {settings.spread_velocity:g} mm/s")
    t = time.perf_counter()
    try:
        sp = run_sample_study(scenes["spread"], scale=low, n=settings.spread_samples,
                              pressure=settings.spread_pressure,
                              velocity=settings.spread_velocity, compound="c3", quiet=quiet,
                              comm=comm, output=out)
    except ValueError as err:  # fewer than two samples succeeded: the row says so
        sp = None
        ev.notes.append(f"samples: the spread study failed: {err}")
    times["spread"] = time.perf_counter() - t
    if sp is not None:
        st = sp["study"]
        if st.values.size > 10:
            ev.spread = SpreadValue(low, int(st.values.size), float(st.S[0]), float(st.S[9]),
                                    float(st.S_exact[9]), float(st.mean_ref))
            ev.notes.append(f"samples: {st.values.size} samples; for independent samples "
                            f"S(1) / S(10) = sqrt(10 (N - 1) / (N - 10)) = "
                            f"{math.sqrt(10 * (st.values.size - 1) / (st.values.size - 10)):.2f}"
                            " (the thesis' N = 287: 3.21)")
        else:
            ev.notes.append(f"samples: only {st.values.size} samples succeeded (> 10 needed)")
    if "flash" in scenes:
        log(f"case 5/{n_cases}: flash: {scenes['flash'].description}")
        t = time.perf_counter()
        try:
            results = run_coupled_scene(scenes["flash"], quiet=quiet, comm=comm, fresh=fresh)
        except SceneError as err:
            results = None
            ev.notes.append(f"speed: the flash case was refused: {err}")
        times["flash"] = time.perf_counter() - t
        for r in results or []:
            iso, hot, notes = flash_values(r)
            ev.points[point_key("flash", r.point.compound, r.point.velocity)] = iso
            ev.points[point_key("flash_hot", r.point.compound, r.point.velocity)] = hot
            ev.notes += [f"speed: {r.point.compound} at {r.point.velocity:g} mm/s: {n}"
                         for n in notes]
    if rank != 0:
        return None
    log(f"case {n_cases}/{n_cases}: sawtooth: {settings.sawtooth_compound}, "
        f"{settings.sawtooth_pressure:g} MPa, {settings.sawtooth_velocity:g} mm/s (2 runs)")
    t = time.perf_counter()
    ev.sawtooth = sawtooth_value(settings, out / "sawtooth.json")
    times["sawtooth"] = time.perf_counter() - t
    ev.notes += material_notes(settings) + speed_notes(settings)
    return write_table(ev, out, settings, time.perf_counter() - t0, times)


def sawtooth_value(settings: TrendSettings, path: Path) -> SawtoothValue:
    """The sawtooth pair of ``verify sawtooth`` (thesis 6.4.1), kept in ``path`` for a rerun."""
    key = {"compound": settings.sawtooth_compound, "pressure": settings.sawtooth_pressure,
           "velocity": settings.sawtooth_velocity}
    if path.is_file():
        stored = json.loads(path.read_text())
        if stored.get("key") == key:
            return SawtoothValue(**stored["value"])
    try:
        res = sawtooth_mu(load_compound(settings.sawtooth_compound),
                          pressure=settings.sawtooth_pressure,
                          velocity=settings.sawtooth_velocity)
        sharp, smooth = res["sharp"], res["smooth"]
        ok = sharp.status == "ok" and smooth.status == "ok"
        value = SawtoothValue(float(sharp.mu_force), float(smooth.mu_force), ok,
                              "" if ok else f"sharp {sharp.status}, smooth {smooth.status}")
    except Exception as err:  # noqa: BLE001 -- one failed case never ends the study
        value = SawtoothValue(math.nan, math.nan, False, f"{type(err).__name__}: {err}")
    path.write_text(json.dumps(strict_json({"key": key, "value": value.__dict__})) + "\n")
    return value


def material_notes(settings: TrendSettings) -> list[str]:
    """Evidence for the material rows: each compound's E' and tan delta at the excitation
    frequency of the lowest scale, omega = 2 pi v / lambda_cut, and of the macro band's long
    edge, 2 pi v / 20 mm (20 degC, eq. 3.34)."""
    v = settings.compare_velocity
    w_low, w_macro = 2 * math.pi * v / settings.cutoff, 2 * math.pi * v / 20.0
    parts = []
    for name in MATERIALS:
        c = load_compound(name)
        lo, ma = c.complex_modulus(w_low), c.complex_modulus(w_macro)
        parts.append(f"{name} E' {lo.real:.3g} / {ma.real:.3g} MPa, tan d "
                     f"{lo.imag / lo.real:.3f} / {ma.imag / ma.real:.3f}")
    return [f"materials: at omega = {w_low:.3g} / {w_macro:.3g} rad/s (2 pi v over "
            f"{settings.cutoff:g} / 20 mm, v = {v:g} mm/s): " + "; ".join(parts)]


#: the study's T0 (20 degC, thesis 6.5.1 and 8.5.3), K
STUDY_T0 = 293.15


def tan_delta_peak(compound: Any, T: float = STUDY_T0) -> tuple[float, float]:
    """(omega, tan delta) of the loss tangent's maximum at temperature T (K), rad/s, on a grid
    of 100 points per decade from 1e-6 to 1e14 rad/s (eq. 3.34)."""
    w = np.logspace(-6.0, 14.0, 2001)
    E = compound.complex_modulus(w, T)
    td = E.imag / E.real
    k = int(np.argmax(td))
    return float(w[k]), float(td[k])


def speed_notes(settings: TrendSettings) -> list[str]:
    """Evidence for the speed row: where the flash case's lowest scale is excited,
    omega = 2 pi v / lambda over its band, against the flash compound's loss-tangent peak at T0.
    Below the peak (the rubbery side) that scale's mu rises with v and falls with temperature,
    the thesis' trend; above it (the glassy side) both turn round.  A rise of T by 20 K divides
    the reduced frequency by 1 / a_T (WLF, eq. 3.37)."""
    if not settings.flash:
        return []
    c = load_compound(settings.flash_compound)
    w_peak, td_peak = tan_delta_peak(c)
    i = lowest_band(settings.flash_cut)
    long, short = EDGES[i], max(EDGES[i + 1], settings.flash_cut)
    parts = []
    for v in settings.velocities:
        lo, hi = 2 * math.pi * v / long, 2 * math.pi * v / short
        side = ("below the peak" if hi < w_peak else "above the peak, glassy side"
                if lo > w_peak else "across the peak")
        parts.append(f"{lo:.3g}-{hi:.3g} rad/s at {v:g} mm/s ({side})")
    shift = (f"; +20 K divides the reduced frequency by {1 / c.wlf.aT(STUDY_T0 + 20.0):.3g}"
             if c.wlf is not None else "")
    if settings.flash_mu_const > 0.0:
        shift += (f"; the macro contact's constant part mu_const = {settings.flash_mu_const:g} "
                  "does not change with temperature")
    return [f"speed: {c.name}'s loss tangent at 20 degC peaks at omega = {w_peak:.3g} rad/s "
            f"(tan d {td_peak:.3f}); the flash case's lowest scale, {SCALES[i]} ({long:g}-"
            f"{short:g} mm), is excited at {', '.join(parts)}.  Below the peak its mu rises with "
            f"v and falls with temperature (the thesis' trend), above it both turn round{shift}"]


def write_table(ev: Evidence, out: Path, settings: TrendSettings, wall: float,
                times: dict[str, float]) -> StudyResult:
    """``evidence.json``, ``trends.txt``, ``trends.json`` and ``trends.png`` from the evidence."""
    table = trends(min(settings.velocities), max(settings.velocities),
                   settings.compare_velocity, settings.flash_compound)
    rows = build_rows(ev, table)
    header = (f"thesis trend table, {settings.describe()}; wall time {wall:.0f} s ("
              + ", ".join(f"{k} {v:.0f} s" for k, v in times.items()) + ")")
    files = [ev.save(out / "evidence.json")]
    text = table_text(rows, header)
    (out / "trends.txt").write_text(text + "\n")
    (out / "trends.json").write_text(json.dumps(strict_json(
        {"settings": settings.to_dict(), "wall_time_s": wall, "case_times_s": times,
         "agree_in_sign": sum(r.verdict == "agrees" for r in rows),
         "rows": [r.to_dict() for r in rows]}), indent=1) + "\n")
    files += [out / "trends.txt", out / "trends.json", plot_trends(rows, out / "trends.png",
                                                                   settings.describe())]
    return StudyResult(rows, ev, out, files, wall, times)
