"""The result of one sliding attempt: its series, window averages, stationarity and stats.

mu(t) = F_x/F_z (eq. 6.2) and mu from dissipated energy (eq. 2.8: viscous (+ frictional) energy
per sliding distance over F_z), their averages over the homogenisation window
(``driver.sliding.window``), the mean contact pressure over contact nodes and steps (eq. 6.11),
the contact length (area per unit depth) and its average (7.4), the stabilisation share, and the
counters and CPU split of the attempt.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec
from rubberfriction.driver.sliding.window import (
    error_estimate,
    period_means,
    step_lengths,
    window_drift,
)

#: columns of a sliding step's row, the series of the result
COLUMNS = ("t", "s", "Fx", "Fz", "contact_length", "viscous_energy", "friction_energy",
           "mean_pressure", "stabilisation_energy", "stabilisation_impulse", "interface_energy")


def solvers(model: Any) -> list:
    """The Newton solvers of an attempt's model (two in the hybrid)."""
    extra = model.trust not in (None, model.newton)
    return [model.newton] + ([model.trust] if extra else [])


def cpu_split(model: Any, cpu_start: float) -> dict[str, float]:
    """CPU seconds of an attempt (its ``model``) by part (stats ``cpu_*``): bulk forms, contact,
    P^T A P (with PETSc's assembly calls), linear solves (numeric LU + triangular solves),
    history update (eq. 3.76), and the whole attempt since ``cpu_start`` (set-up and Python
    included)."""
    asm = model.problem.cpu
    return {"cpu_bulk": asm["bulk"], "cpu_contact": asm["hooks"],
            "cpu_condense": asm["condense"],
            "cpu_linear": sum(n.cpu_linear for n in solvers(model)),
            "cpu_history": model.sp.cpu_history,
            "cpu_attempt": time.process_time() - cpu_start}


def window(spec: SlidingSpec, s_done: np.ndarray, distance: float,
           window_used: int) -> tuple[float, float]:
    """(start, end) sliding distance of the averaging window (driver.sliding.window): the last
    ``window_used`` (or ``spec.window_periods``) whole periods under the converged rule, else
    the fixed fraction of the distance."""
    if spec.converge_tol > 0 and spec.period > 0:
        end = spec.period * math.floor(float(np.max(s_done, initial=0.0)) / spec.period + 1e-9)
        w = window_used or spec.window_periods
        return max(0.0, end - w * spec.period), end
    return spec.window_start * distance, distance


def slow_mode_stats(periods) -> dict[str, float]:
    """The contact face's creep over the last period in contact elements (``face_creep``) and
    the extrapolations of the block's creep (``driver.sliding.slowmode``): how many, how many
    were left out, and their total factor (0 where none)."""
    creep = getattr(periods, "face_creep", math.nan) if periods is not None else math.nan
    out = {} if math.isnan(creep) else {"face_creep": float(creep)}
    slow = getattr(periods, "slow_mode", None) if periods is not None else None
    if slow is None:
        return out
    return {**out, "extrapolated_creep": float(slow.count),
            "extrapolation_left_out": float(slow.rejected),
            "extrapolation_factor": float(sum(slow.omegas))}


def assemble(run: Any, rows: list, distance: float, status: str, reason: str,
             t: float) -> SlidingResult:
    """The result of the run's attempt from its sliding rows (COLUMNS): series, window
    averages and the stats of its model (``run.model``), step control (``run.steps``) and
    periods (``run.periods``)."""
    model, steps, periods, spec = run.model, run.steps, run.periods, run.spec
    L = model.L
    arr = np.array(rows, dtype=float).reshape(-1, len(COLUMNS))
    series = {c: arr[:, i] for i, c in enumerate(COLUMNS)}
    res = SlidingResult(status, reason=reason, t_reached=t, series=series,
                        min_det_F=steps.min_det_F if math.isfinite(steps.min_det_F) else math.nan,
                        road_intrusion=(run.intrusion / model.hc if run.intrusion >= 0.0
                                        else math.nan))
    lo, hi = window(spec, series["s"], distance, periods.window_used)
    res.stats = {"cutbacks": steps.cutbacks, "newton_iterations": steps.newton_iterations,
                 "predictor_used": steps.predictor_used,
                 "extrapolation_used": steps.extrapolation_used,
                 "period_used": steps.period_used,
                 "column_used": steps.column_used,
                 # extrapolated starts the guard rejected (solved again from the others)
                 "extrapolation_rejected": steps.guard_rejections,
                 "extrapolation_unseen": steps.extrapolation_unseen,
                 "steps": len(rows), "h_contact": model.hc,
                 "dofs": float(model.sp.w.x.array.size),
                 "stabilised_steps": steps.stabilised_steps,
                 "lu_fallbacks": sum(n.lu_fallbacks for n in solvers(model)),
                 "factorisations": sum(n.factorisations for n in solvers(model)),
                 "krylov_iterations": sum(n.krylov_iterations for n in solvers(model)),
                 # trial steps the trust region refused (newton = "trust-region" or "hybrid")
                 "rejected_steps": float(model.trust.rejected if model.trust else 0),
                 "trust_region_solves": float(steps.trust_solves),
                 "window_start": lo, "window_end": hi,
                 "compression_contact_fraction": run.compression_contact,
                 "warm_start": float(run.warm_started), **slow_mode_stats(periods),
                 **cpu_split(model, run._cpu_start)}
    if len(rows) == 0:
        return res
    Fz = series["Fz"]
    with np.errstate(divide="ignore", invalid="ignore"):
        # friction force on the block opposes +x sliding
        series["mu_force"] = -series["Fx"] / Fz
    win = series["s"] > lo + 1e-9 * max(hi, 1.0)
    if status == "ok" and np.count_nonzero(win) >= 2:
        ds = step_lengths(series["s"])[win]
        res.mu_force = float(np.sum(series["mu_force"][win] * ds) / ds.sum())
        energy = (series["viscous_energy"] + series["friction_energy"])[win].sum()
        work_scale = np.mean(Fz[win]) * ds.sum()
        res.mu_energy = float(energy / work_scale)
        # what the contact takes up, in the same measure (docs/notes-energy.md)
        res.mu_interface = float(series["interface_energy"][win].sum() / work_scale)
        res.mean_pressure = pooled_contact_pressure(series["mean_pressure"][win],
                                                    series["contact_length"][win])
        res.contact_fraction = float(np.mean(series["contact_length"][win]) / L)
        res.contact_elements = float(np.min(series["contact_length"][win]) / model.hc)
        cell = spec.period if spec.converge_tol > 0 else 0.0  # whole periods: one-period drift
        res.window_drift = window_drift(series["s"], series["mu_force"], lo, hi, cell)
        res.contact_drift = window_drift(series["s"], series["contact_length"] / L, lo, hi, cell)
        res.stabilisation_share = stabilisation_share(series, win, ds, spec.velocity,
                                                      spec.pressure * L)
        stationarity(res, series, spec, L, periods.converged, periods.window_used)
    return res


def stationarity(res: SlidingResult, series: dict[str, np.ndarray], spec: SlidingSpec,
                 L: float, converged: float, window_used: int) -> None:
    """Converged rule: whether the run got there, the period means and the error estimate;
    fixed rule: half the window drift as the error estimate."""
    if spec.converge_tol > 0 and spec.period > 0:
        w = window_used or spec.window_periods
        means = period_means(series["s"], series["mu_force"], spec.period)
        contact = period_means(series["s"], series["contact_length"] / L, spec.period)
        res.converged = 1.0 if converged == 1.0 else 0.0
        res.mu_error = error_estimate(means, w)
        res.contact_error = error_estimate(contact, w)
        res.stats["period_mu"] = [float(m) for m in means]
        res.stats["period_contact"] = [float(c) for c in contact]
    else:
        res.mu_error = 0.5 * abs(res.window_drift)
        res.contact_error = 0.5 * abs(res.contact_drift)
    if spec.period > 0:
        res.stats["periods"] = round(float(series["s"][-1] / spec.period), 6)


def pooled_contact_pressure(step_pressure: np.ndarray, contact_length: np.ndarray) -> float:
    """Eq. (6.11): the contact pressures of all contact nodes of all time steps, each weighted by
    its contact area, averaged: sum_t p_t A_t / sum_t A_t with a step's area-weighted mean
    pressure p_t over its contact length A_t.  (The mean of the p_t would weigh a step with a
    small contact patch, whose pressure is high, as much as one with a large patch.)  NaN
    without contact."""
    area = float(np.sum(contact_length))
    return float(np.sum(step_pressure * contact_length) / area) if area > 0.0 else math.nan


def stabilisation_share(series: dict[str, np.ndarray], win: np.ndarray, ds: np.ndarray,
                        velocity: float, load: float = 0.0) -> float:
    """What the stabilising dashpots carry of a window (driver.fe.stabilisation): the largest of
    their work and of the work equivalent of their net x-force (impulse sum F_x,d dt times v) over
    the friction work sum |F_x| ds, and of the part of the normal ``load`` (p l, held on the top
    edge) that the contact does not carry in the stabilised steps, sum |p l - F_z| ds over
    p l sum ds (quasi-static: the dashpots carry it; a stabilised step can hold the block with the
    contact carrying nothing).  0 without stabilised sub-steps."""
    work = float(np.sum(np.abs(series["Fx"][win]) * ds))
    if not work > 0.0:
        return math.nan
    energy = float(np.sum(series["stabilisation_energy"][win]))
    impulse = abs(float(np.sum(series["stabilisation_impulse"][win]))) * velocity
    normal = 0.0
    if load > 0.0:
        stab = ((series["stabilisation_energy"][win] != 0.0)
                | (series["stabilisation_impulse"][win] != 0.0))
        missing = np.abs(load - np.abs(series["Fz"][win][stab]))
        normal = float(np.sum(missing * ds[stab])) / (load * ds.sum())
    return max(energy / work, impulse / work, normal)
