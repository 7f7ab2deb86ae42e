"""Benchmark: speed-accuracy of one micro-cell sliding run, and a stability sweep.

1. Speed-accuracy (the curve users choose settings from): the viscoelastic full-contact sinusoid
   (``verify viscoelastic-sinusoid`` defaults, closed form known) against mesh refinement
   (elements per wavelength) and time step (sliding distance per step / contact element size):
   mu error and wall time per run.
2. Stability: velocities 1e-6 .. 10 m/s x pressures 0.01 .. 10 MPa on a rough periodic sample
   (a band of the default road): status, fallback level, cut-backs, Newton iterations, wall
   time, mu (``--scale``: the first micro1 or micro2 sample).  Nothing may fail silently: a
   failed run prints its reason.  Each run has a wall-time limit (``--wall-limit``); a run that
   hits it is reported as such, not waited for.
3. Iterations (``--part iterations``, not in ``both``): where the CPU time of one Newton iteration
   of a lowest-scale run goes.  The first micro2 sample of the default scene (0.04-0.003 mm band,
   built as the campaign builds it) at ``--pressure`` and ``--velocity``, slid over
   ``--slide-fraction`` of its period: bulk forms, contact, P^T A P, linear solve (numeric
   LU + triangular solves), history update, the rest (Python, set-up); CPU seconds of this
   process (the run's ``cpu_*`` stats: robust to other jobs on the machine) of the attempt that
   gave the result, per Newton iteration.  ``--compare-jit`` repeats the run with the forms
   compiled by dolfinx's default flags (``forms/jit.py``) and prints the ratio per part.
4. Linear solvers (``--part linear-solvers``): the same lowest-scale run, and the first micro1
   sample at a tenth of the pressure (of ``--road``), with each LU package of the Newton solves
   (``driver.fe.newton.LINEAR_SOLVERS``: PETSc's checked pivot-free LU with minimum degree or
   nested dissection ordering, MUMPS) and PETSc's with a factorisation at every iteration
   instead of reused as GMRES's preconditioner (``LINEAR_VARIANTS``), side by side and
   repeated (A B C A B C: the machine is shared): wall time, CPU of the linear solves, Newton
   iterations, factorisations and GMRES iterations, mu_force and the pivot-free solves that fell
   back to MUMPS, and each variant's ratios to the default ("petsc").
5. Newton start (``--part start``): the first sample of every scale of the default road (macro
   0.3, meso 1, micro1 2 MPa and micro2 at ``--pressure``, ``--velocity``, ``--slide-fraction``
   of a period) with the sliding sub-steps started from the best of the last state, the
   translation of the deformation with the surface (or, on whole columns, the column start,
   ``driver.sliding.steps.ColumnShift``) and the extrapolated last increment: unguarded,
   guarded (``--guards``, as shipped ``SlidingRun.EXTRAPOLATION_GUARD``: a start that needs more
   Newton iterations is solved again from the others), the shipped guard with every start's
   residual compared (``unseen_after = 0``, the rule until 0.13.0), as shipped without the
   column start, and without the extrapolation, side by side and repeated (A B C A B C): Newton
   iterations, wall time, mu_force, how often each start won and was rejected, and the ratios
   to the run without it (and shipped against no column).
6. Branches (``--part branches``): the three-wave cell of ``tests/test_shortcut.py`` at 18
   (p, v, amplitude) frictionless and with mu 0.5, two periods, from the last state and the
   translation, with the guarded extrapolation (as shipped) and unguarded: mu_force, its
   difference to the first and the Newton iterations.  Where the equilibrium is unique the
   three agree to round-off; where it is not, the run-in path can differ (README "Start
   iterate").

    rubberfriction bench sliding [--part accuracy|stability|both|iterations|linear-solvers|start
                                         |branches]
                                 [--quick]
                                 [--wall-limit S] [--penalty-alpha A] [--element E] [--json FILE]
                                 [--scale micro1|micro2] [--road default|four_scale]
                                 [--grid quick|standard|full]
                                 [--pressure P] [--velocity V] [--slide-fraction F] [--guards 4,6]
                                 [--compare-jit]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time

import numpy as np

from rubberfriction.driver.fe.solid import ELEMENTS
from rubberfriction.driver.multiscale.results import Point
from rubberfriction.driver.multiscale.scales import build_scales
from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.multiscale.specs import (
    SpecBuilder,
    load_compounds,
    master_points,
    master_polyline,
)
from rubberfriction.driver.multiscale.statistics import STABILISATION_TOL, usable, why_unusable
from rubberfriction.driver.runtime.store import result_outcome
from rubberfriction.driver.fe.newton import FACTOR_REUSE
from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, run_sliding, sliding_contact
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.surfaces import default_road
from rubberfriction.driver.surfaces.four_scale import four_scale_road
from rubberfriction.driver.verification.viscoelastic_sinusoid import simulate
from rubberfriction.forms import jit
from rubberfriction.forms.material_files import load_compound


def accuracy(quick: bool) -> None:
    comp = load_compound("tread_default")
    print("speed-accuracy: viscoelastic full-contact sinusoid "
          "(lambda 1 mm, h0 2 um, p 0.1 MPa, v 10 mm/s)")
    print(f"{'el/lambda':>9} {'step/h':>7} {'mu_force':>11} {'err':>8} {'mu_energy':>11} "
          f"{'err':>8} {'wall [s]':>9}")
    meshes = (8, 16) if quick else (8, 16, 32)
    steps = (1.0, 0.5) if quick else (1.0, 0.5, 0.25)
    for m in meshes:
        for f in steps:
            t0 = time.perf_counter()
            o = simulate(comp, elements_per_wavelength=m, step_fraction=f)
            wall = time.perf_counter() - t0
            ex = o["mu_exact"]
            print(f"{m:>9} {f:>7.2f} {o['mu_force']:>11.4e} {abs(o['mu_force'] / ex - 1):>8.2%} "
                  f"{o['mu_energy']:>11.4e} {abs(o['mu_energy'] / ex - 1):>8.2%} {wall:>9.2f}",
                  flush=True)
    print(f"closed form mu = {ex:.4e}")


#: default-road scales the stability sweep runs on, by their index
STABILITY_SCALES = {"micro1": 2, "micro2": 3}


#: roads the stability sweep takes its samples from
STABILITY_ROADS = {"default": default_road, "four_scale": four_scale_road}
#: (velocities in m/s, pressures in MPa) of the stability grids; "full": 8 x 5 = 40 cases
STABILITY_GRIDS = {
    "quick": ((1e-6, 1e-2, 10.0), (0.01, 10.0)),
    "standard": ((1e-6, 1e-4, 1e-2, 1.0, 10.0), (0.01, 0.1, 1.0, 10.0)),
    "full": ((1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0), (0.01, 0.1, 1.0, 3.0, 10.0)),
}


def rough_sample(scale: str = "micro1", road: str = "default"):
    """First sample of a scale of a road (the default road or the four-scale road): micro1
    (0.3-0.04 mm band, period 0.3 mm) or micro2 (0.04-0.003 mm, period 0.04 mm)."""
    return STABILITY_ROADS[road]().extract_samples(1, seed=1)[STABILITY_SCALES[scale]][0]


def stability(quick: bool, wall_limit: float, penalty_alpha: float, element: str = "Q1P0",
              scale: str = "micro1", road: str = "default", grid: str = "standard"
              ) -> list[dict]:
    """The sweep of part 2 on the first sample of ``scale`` of ``road`` over the velocities and
    pressures of ``grid`` (``quick`` takes the quick grid); the rigid surface refined per
    shortest wavelength of the band as the default scene's campaign does
    (``specs.master_polyline``).  A run is usable when a campaign would average it
    (``statistics.usable``) and its mu is finite; otherwise the row gives the reason."""
    comp = load_compound("tread_default")
    sample = rough_sample(scale, road)
    x, h = np.asarray(sample.x)[:-1], np.asarray(sample.h)[:-1]
    points = master_points(load_scene("default").numerics)
    x, h = master_polyline(x, h, sample.period, float(sample.band[1]), points)
    print(f"scale {scale} of the {road} road", end="; ")
    print(f"stability sweep on a rough sample: period {sample.period:.4g} mm, rms height "
          f"{sample.rms_height:.3g} mm, rms slope {sample.rms_slope:.3g}, {x.size} segments; "
          f"penalty alpha {penalty_alpha:g}, element {element}, "
          f"wall limit {wall_limit:g} s per run")
    print(f"{'v [m/s]':>8} {'p [MPa]':>8} {'status':>7} {'fallback':>8} {'cutbacks':>8} "
          f"{'newton':>7} {'wall [s]':>9} {'mu':>9} {'stab.':>7}  reason")
    vs, ps = STABILITY_GRIDS["quick" if quick else grid]
    rows = []
    for v in vs:
        for p in ps:
            spec = SlidingSpec(surface_x=x, surface_h=h, period=sample.period, pressure=p,
                               velocity=v * 1e3, compound=comp, elements_per_wavelength=8,
                               slide_distance=sample.period, penalty_alpha=penalty_alpha,
                               element=element)
            t0 = time.perf_counter()
            r = run_sliding(spec, wall_limit=wall_limit)
            st, wall = r.stats, time.perf_counter() - t0
            outcome = result_outcome(r)
            good = usable(outcome) and np.isfinite(r.mu_force)
            note = "" if good else why_unusable(outcome) if not usable(outcome) else "mu is NaN"
            print(f"{v:>8.0e} {p:>8.2g} {r.status:>7} {st.get('fallback_level', -1):>8} "
                  f"{st.get('cutbacks', 0):>8} {st.get('newton_iterations', 0):>7} "
                  f"{wall:>9.2f} {r.mu_force:>9.4f} {r.stabilisation_share:>7.2%}  {note}",
                  flush=True)
            rows.append({"velocity_m_s": v, "pressure_MPa": p, "status": r.status,
                         "reason": r.reason, "failure": st.get("failure", ""),
                         "fallback_level": st.get("fallback_level"),
                         "cutbacks": st.get("cutbacks"),
                         "newton_iterations": st.get("newton_iterations"), "wall_time_s": wall,
                         "mu_force": r.mu_force, "mu_energy": r.mu_energy, "usable": bool(good),
                         "stabilisation_share": r.stabilisation_share,
                         "contact_fraction": r.contact_fraction})
    ok = sum(r["status"] == "ok" for r in rows)
    n_usable = sum(r["usable"] for r in rows)
    print(f"{ok} of {len(rows)} runs converged, {n_usable} of them usable (finite mu, "
          f"stabilisation share at most {STABILISATION_TOL:.0%}, as a campaign averages them); "
          f"{sum(r['failure'] == 'wall_limit' for r in rows)} hit the wall-time limit; "
          f"total {sum(r['wall_time_s'] for r in rows):.0f} s")
    return rows


def lowest_scale_spec(pressure: float, velocity: float, slide_fraction: float | None,
                      scale: int = -1, scene_name: str = "default") -> SlidingSpec:
    """The first micro2 (lowest-scale; or ``scale``) sample of the default scene (or the shipped
    ``scene_name``), built as its campaign builds friction runs (``SpecBuilder``: band-limited
    master, element size, quick settings), slid over ``slide_fraction`` of its period (None: the
    campaign's sliding budget)."""
    scene = load_scene(scene_name)
    scales = build_scales(scene, scene.samples.friction)
    compound = scene.conditions.compounds[0]
    k = scale % len(scales.sets)
    spec = SpecBuilder(scene, load_compounds(scene))(
        Point(compound, pressure, velocity), k, scales.sets[k].samples[0], pressure, None, "up")
    if slide_fraction is None:
        return spec
    return dataclasses.replace(spec, slide_distance=slide_fraction * spec.period)


#: the linear-solver variants compared by ``--part linear-solvers``: label -> (LU package,
#: GMRES iterations on a reused factorisation); "petsc" is what sliding runs use
LINEAR_VARIANTS = {"petsc": ("petsc", FACTOR_REUSE), "petsc-fresh": ("petsc", 0),
                   "petsc-nd": ("petsc-nd", FACTOR_REUSE), "mumps": ("mumps", 0)}


def linear_solvers(pressure: float, velocity: float, slide_fraction: float,
                   repeats: int = 2, road: str = "default") -> list[dict]:
    """Each linear-solver variant on the micro2 and micro1 runs, interleaved (module docstring,
    part 4)."""
    cases = [("micro2", lowest_scale_spec(pressure, velocity, slide_fraction, scene_name=road)),
             ("micro1", lowest_scale_spec(0.1 * pressure, velocity, slide_fraction, scale=-2,
                                          scene_name=road))]
    rows = []
    for name, spec in cases:
        print(f"{name}: period {spec.period:g} mm, h_contact {spec.h_contact:g} mm, "
              f"p {spec.pressure:g} MPa, v {velocity:g} mm/s, slide {spec.slide_distance:g} mm")
        for rep in range(repeats):
            for label, (solver, reuse) in LINEAR_VARIANTS.items():
                t0 = time.perf_counter()
                r = SlidingRun(spec, block_mesh, sliding_contact, linear_solver=solver,
                               factor_reuse=reuse).run()
                wall = time.perf_counter() - t0
                st = r.stats
                row = {"case": name, "solver": label, "repeat": rep, "status": r.status,
                       "wall_s": wall, "cpu_linear_s": float(st.get("cpu_linear", np.nan)),
                       "newton_iterations": int(st.get("newton_iterations", 0)),
                       "factorisations": int(st.get("factorisations", 0)),
                       "krylov_iterations": int(st.get("krylov_iterations", 0)),
                       "dofs": float(st.get("dofs", np.nan)), "mu_force": r.mu_force,
                       "lu_fallbacks": int(st.get("lu_fallbacks", 0))}
                rows.append(row)
                its = max(row["newton_iterations"], 1)
                reused = (f", {row['factorisations']} factorisations, "
                          f"{row['krylov_iterations']} GMRES iterations" if reuse else "")
                print(f"  {label:11s} #{rep}: {r.status}, {row['dofs']:.0f} dofs, {its} Newton "
                      f"iterations{reused}, linear {1e3 * row['cpu_linear_s'] / its:.2f} ms/it, "
                      f"wall {wall:.1f} s, mu_force {r.mu_force:.10g}, "
                      f"fallbacks {row['lu_fallbacks']}", flush=True)
        mine = [r for r in rows if r["case"] == name]
        new = [r for r in mine if r["solver"] == "petsc"]
        for other in (s for s in LINEAR_VARIANTS if s != "petsc"):
            ref = [r for r in mine if r["solver"] == other]
            lin = (sum(r["cpu_linear_s"] for r in ref)
                   / max(sum(r["cpu_linear_s"] for r in new), 1e-300))
            wall = sum(r["wall_s"] for r in ref) / max(sum(r["wall_s"] for r in new), 1e-300)
            dmu = max(abs(a["mu_force"] - b["mu_force"]) for a, b in zip(ref, new))
            print(f"  {name}: {other} / petsc: linear solves x{lin:.2f}, wall x{wall:.2f}; "
                  f"|mu_force difference| {dmu:.2e}")
    return rows


#: scale of the default road (first sample) -> its pressure in ``--part start`` (micro2: --pressure)
START_SCALES = {"macro": 0.3, "meso": 1.0, "micro1": 2.0, "micro2": None}


#: the three-wave cell of ``tests/test_shortcut.py``: (harmonic, amplitude mm, phase) on 1 mm
THREE_WAVES = ((1, 0.004, 0.0), (2, 0.002, 1.0), (3, 0.0012, 2.5))


def start_branches(friction: float | None, guard: int = SlidingRun.EXTRAPOLATION_GUARD
                   ) -> list[dict]:
    """The three-wave cell (p 0.02 / 0.1 / 1 MPa, v 1 / 100 / 1e4 mm/s, amplitudes x1 / x10; 24
    contact elements, two periods) from the last state and the translation, from all three
    starts with the extrapolation guarded, and unguarded: mu_force and the relative difference
    to the first (module docstring, part 6)."""
    x = np.arange(192) / 192.0
    variants = {"other starts": (("last", "translation"), 0),
                f"guard {guard}": (SlidingRun.START_CANDIDATES, guard),
                "unguarded": (SlidingRun.START_CANDIDATES, 0)}
    rows = []
    for p in (0.02, 0.1, 1.0):
        for v in (1.0, 100.0, 1e4):
            for amp in (1.0, 10.0):
                h = sum(a * amp * np.cos(2 * np.pi * k * x + ph) for k, a, ph in THREE_WAVES)
                spec = SlidingSpec(surface_x=x, surface_h=h, period=1.0, pressure=p, velocity=v,
                                   compound=load_compound("tread_default"), h_contact=1.0 / 24,
                                   slide_distance=2.0, steady_state=True, friction=friction)
                row = {"pressure": p, "velocity": v, "amplitude": amp}
                for name, (candidates, g) in variants.items():
                    run = SlidingRun(spec, block_mesh, sliding_contact)
                    run.start_candidates, run.extrapolation_guard = candidates, g
                    t0 = time.perf_counter()
                    r = run.run()
                    row[name] = {"status": r.status, "mu_force": r.mu_force,
                                 "newton_iterations": run.newton_iterations,
                                 "wall_s": time.perf_counter() - t0}
                ref = row["other starts"]["mu_force"]
                text = f"p {p:4g} v {v:6g} x{amp:<3g}: other starts mu {ref:.6g}"
                for name in list(variants)[1:]:
                    mu = row[name]["mu_force"]
                    row[name]["difference"] = abs(mu - ref) / abs(ref) if ref else float("nan")
                    text += (f" | {name} {mu:.6g} ({row[name]['difference']:.1e}, Newton "
                             f"{row[name]['newton_iterations']} / "
                             f"{row['other starts']['newton_iterations']})")
                print(text, flush=True)
                rows.append(row)
    return rows


def _guards(text: str) -> tuple[int, ...]:
    try:
        guards = tuple(int(g) for g in text.split(",") if g.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected whole numbers, e.g. 4,6,10") from None
    if not guards or min(guards) < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: expected guards >= 1")
    return guards


def start_candidates(pressure: float, velocity: float, slide_fraction: float,
                     repeats: int = 2,
                     guards: tuple[int, ...] = (SlidingRun.EXTRAPOLATION_GUARD,),
                     scales: tuple[str, ...] = tuple(START_SCALES)) -> list[dict]:
    """Each scale with and without the extrapolated Newton start (module docstring, part 5)."""
    both = SlidingRun.START_CANDIDATES
    plain = tuple(c for c in both if c != "extrapolation")
    shipped = SlidingRun.EXTRAPOLATION_GUARD
    variants = {"unguarded": (both, 0, 0),
                **{f"guard {g}": (both, g, SlidingRun.UNSEEN_AFTER) for g in guards},
                f"guard {shipped}, compared": (both, shipped, 0),
                # as shipped without the column start (0.28.0): what it saves
                "no column": (tuple(c for c in both if c != "column"), shipped,
                              SlidingRun.UNSEEN_AFTER),
                "no extrapolation": (plain, 0, 0)}
    rows = []
    for k, (name, p) in enumerate(START_SCALES.items()):
        if name not in scales:
            continue
        spec = lowest_scale_spec(pressure if p is None else p, velocity, slide_fraction, scale=k)
        print(f"{name}: period {spec.period:g} mm, h_contact {spec.h_contact:g} mm, "
              f"p {spec.pressure:g} MPa, v {velocity:g} mm/s, slide {spec.slide_distance:g} mm",
              flush=True)
        for rep in range(repeats):
            for label, (candidates, guard, unseen) in variants.items():
                run = SlidingRun(spec, block_mesh, sliding_contact)
                run.start_candidates = candidates
                run.extrapolation_guard = guard
                run.unseen_after = unseen
                t0 = time.perf_counter()
                r = run.run()
                wall = time.perf_counter() - t0
                st = r.stats
                row = {"scale": name, "variant": label, "repeat": rep, "status": r.status,
                       "wall_s": wall, "newton_iterations": int(st.get("newton_iterations", 0)),
                       "steps": int(st.get("steps", 0)), "mu_force": r.mu_force,
                       "translation": int(st.get("predictor_used", 0)),
                       "extrapolation": int(st.get("extrapolation_used", 0)),
                       "column": int(st.get("column_used", 0)),
                       "rejected": run.guard_rejections}
                rows.append(row)
                print(f"  {label:16s} #{rep}: {r.status}, {row['newton_iterations']} Newton "
                      f"iterations, starts: translation {row['translation']}, extrapolation "
                      f"{row['extrapolation']} ({row['rejected']} redone), column "
                      f"{row['column']}; wall {wall:.1f} s, "
                      f"mu_force {r.mu_force:.6g}",
                      flush=True)
        mine = [r for r in rows if r["scale"] == name]
        old = [r for r in mine if r["variant"] == "no extrapolation"]
        for v in variants:
            if v == "no extrapolation":
                continue
            new = [r for r in mine if r["variant"] == v]
            its = sum(r["newton_iterations"] for r in old) / max(
                sum(r["newton_iterations"] for r in new), 1)
            wall = sum(r["wall_s"] for r in old) / max(sum(r["wall_s"] for r in new), 1e-300)
            dmu = max(abs(a["mu_force"] - b["mu_force"]) / abs(b["mu_force"])
                      for a, b in zip(new, old))
            print(f"  {name}: no extrapolation / {v}: Newton iterations x{its:.2f}, "
                  f"wall x{wall:.2f}; relative mu_force difference {dmu:.2e}", flush=True)
        for variant, label in (("no column", "no column"),
                               (f"guard {shipped}, compared",
                                f"compared (unseen after {SlidingRun.UNSEEN_AFTER})")):
            _against_shipped(name, label, [r for r in mine if r["variant"] == variant],
                             [r for r in mine if r["variant"] == f"guard {shipped}"])
    return rows


def _against_shipped(scale: str, label: str, a: list[dict], shipped: list[dict]) -> None:
    """Print the wall ratio and Newton iterations of variant rows ``a`` against the shipped."""
    if a and shipped:
        print(f"  {scale}: {label} / shipped: wall "
              f"x{sum(r['wall_s'] for r in a) / sum(r['wall_s'] for r in shipped):.3f}, Newton "
              f"iterations {sum(r['newton_iterations'] for r in a)} / "
              f"{sum(r['newton_iterations'] for r in shipped)}", flush=True)


#: (label, stats key) of the CPU split of one attempt; the rest is cpu_attempt minus their sum
CPU_PARTS = (("bulk forms (tangent + residual)", "cpu_bulk"),
             ("contact (C++ evaluate + assembly)", "cpu_contact"),
             ("condensation P^T A P (+ PETSc assembly)", "cpu_condense"),
             ("linear solve (numeric LU + solves)", "cpu_linear"),
             ("history update (prepare + commit)", "cpu_history"))


def cpu_split(stats: dict) -> dict[str, float]:
    """CPU seconds by part (CPU_PARTS labels, plus the rest and the total) from a run's stats."""
    parts = {label: float(stats[key]) for label, key in CPU_PARTS}
    parts["rest (Python, set-up, predictor)"] = float(stats["cpu_attempt"]) - sum(parts.values())
    parts["total (the attempt)"] = float(stats["cpu_attempt"])
    return parts


def iterations(pressure: float, velocity: float, slide_fraction: float, compare_jit: bool,
               element: str = "Q1P0") -> dict:
    """Per-iteration CPU split of one lowest-scale run (module docstring, part 3)."""
    spec = dataclasses.replace(lowest_scale_spec(pressure, velocity, slide_fraction),
                               element=element)
    print(f"lowest-scale run: micro2 sample 1 of the default scene, period {spec.period:g} mm, "
          f"h_contact {spec.h_contact:g} mm, p {pressure:g} MPa, v {velocity:g} mm/s, slide "
          f"{spec.slide_distance:g} mm, element {element}")
    variants = [("project flags", jit.COMPILE_ARGS)]
    if compare_jit:
        variants.append(("dolfinx flags", jit.DOLFINX_DEFAULT_ARGS))
    splits, out = [], {}
    for name, args in variants:
        with jit.compile_args(args):
            t0 = time.perf_counter()
            r = run_sliding(spec)
            wall = time.perf_counter() - t0
        its = max(int(r.stats.get("newton_iterations", 0)), 1)
        print(f"{name} ({' '.join(args)}): {r.status} ({r.stats.get('attempt', '')}), "
              f"{its} Newton iterations, {r.stats.get('dofs', 0):.0f} dofs, "
              f"mu_force {r.mu_force:.10g}, wall {wall:.1f} s", flush=True)
        if "cpu_attempt" not in r.stats:
            print(f"  no CPU split: {r.reason}")
            return out
        splits.append((cpu_split(r.stats), its))
        out[name] = {"status": r.status, "mu_force": r.mu_force, "iterations": its, "wall_s": wall,
                     "cpu_s": splits[-1][0]}
    head = f"{'part':42} {'CPU [s]':>8} {'share':>6} {'ms/it':>7}"
    print(head + ("" if len(splits) == 1 else f" {'ms/it':>7} {'ratio':>6}  (dolfinx flags)"))
    (first, n1), rest = splits[0], splits[1:]
    for label, v in first.items():
        line = f"{label:42} {v:>8.2f} {v / first['total (the attempt)']:>6.1%} {1e3 * v / n1:>7.2f}"
        for other, n2 in rest:  # per-iteration ratio, dolfinx flags / project flags
            w = other[label]
            line += f" {1e3 * w / n2:>7.2f} {(w / n2) / (v / n1) if v > 0 else float('nan'):>6.2f}"
        print(line)
    return out


def _number(minimum: float, strict: bool):
    """argparse type: a finite float >= minimum (> minimum if strict), else a clear error."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not np.isfinite(value) or value < minimum or (strict and value == minimum):
            raise argparse.ArgumentTypeError(
                f"expected a finite number {'>' if strict else '>='} {minimum:g}, got {text}")
        return value

    return parse


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench sliding", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--part", choices=["accuracy", "stability", "both", "iterations",
                                       "linear-solvers", "start", "branches"],
                    default="both")
    ap.add_argument("--quick", action="store_true", help="fewer levels (a smoke run)")
    ap.add_argument("--wall-limit", type=_number(0.0, strict=False), default=300.0,
                    help="seconds per stability run before it is stopped and reported "
                         "(300; 0: no limit)")
    ap.add_argument("--penalty-alpha", type=_number(0.0, strict=True), default=100.0,
                    help="contact penalty factor of the stability runs (SlidingSpec.penalty_alpha)")
    ap.add_argument("--scale", choices=tuple(STABILITY_SCALES), default="micro1",
                    help="stability: the road's scale whose first sample is swept (micro1)")
    ap.add_argument("--road", choices=tuple(STABILITY_ROADS), default="default",
                    help="stability, linear-solvers: the road the sample comes from (default)")
    ap.add_argument("--grid", choices=tuple(STABILITY_GRIDS), default="standard",
                    help="stability: velocities x pressures (standard 5 x 4; full 8 x 5: 1e-6 to "
                         "10 m/s, 0.01 to 10 MPa)")
    ap.add_argument("--element", choices=ELEMENTS, default="Q1P0",
                    help="rubber element of the stability and iteration runs (SlidingSpec.element)")
    ap.add_argument("--json", metavar="FILE",
                    help="write the stability rows (or the iteration split) as JSON")
    ap.add_argument("--pressure", type=_number(0.0, strict=True), default=10.0,
                    help="iterations: mean pressure of the micro2 run [MPa] "
                         "(10; the default scene's micro2 runs see 6-31)")
    ap.add_argument("--velocity", type=_number(0.0, strict=True), default=100.0,
                    help="iterations: sliding velocity [mm/s] (100)")
    ap.add_argument("--slide-fraction", type=_number(0.0, strict=True), default=0.1,
                    help="iterations: sliding distance in periods of the sample (0.1; a "
                         "campaign slides 1.5)")
    ap.add_argument("--guards", type=_guards, default=(SlidingRun.EXTRAPOLATION_GUARD,),
                    help="start: the guards compared, branches: the first (Newton iterations "
                         "allowed from the extrapolated start), comma-separated")
    ap.add_argument("--compare-jit", action="store_true",
                    help="iterations: repeat with dolfinx's default compiler flags, print ratios")
    a = ap.parse_args(argv)
    if a.part == "linear-solvers":
        rows = linear_solvers(a.pressure, a.velocity, a.slide_fraction,
                              repeats=1 if a.quick else 2, road=a.road)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"linear_solvers": rows}, f, indent=1, default=float)
        return 0
    if a.part == "branches":
        rows = [dict(r, friction=f) for f in (None, 0.5)
                for r in start_branches(f, guard=a.guards[0])]
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"branches": rows}, f, indent=1, default=float)
        return 0
    if a.part == "start":
        rows = start_candidates(a.pressure, a.velocity, a.slide_fraction,
                                repeats=1 if a.quick else 2, guards=a.guards)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"start": rows}, f, indent=1, default=float)
        return 0
    if a.part == "iterations":
        out = iterations(a.pressure, a.velocity, a.slide_fraction, a.compare_jit, a.element)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"iterations": out}, f, indent=1, default=float)
        return 0
    if a.part in ("accuracy", "both"):
        accuracy(a.quick)
    if a.part in ("stability", "both"):
        rows = stability(a.quick, a.wall_limit, a.penalty_alpha, a.element, a.scale, a.road,
                         a.grid)
        if a.json:
            with open(a.json, "w") as f:
                json.dump({"stability": rows}, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
