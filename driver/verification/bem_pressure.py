"""``rubberfriction verify bem-pressure``: the frictionless pressure branch against a periodic BEM.

An elastic periodic block (plane strain) pressed frictionlessly onto a rigid small-slope
self-affine profile (``driver.surfaces.generators.self_affine_profile``), the set-up of a
pressure-branch run (``driver.multiscale.cascade``: a frictionless run whose contact fraction A
gives the pressure p / A handed down, eq. 6.11).  The reference is an independent boundary-element
solution of the same profile: the periodic elastic half-plane, whose surface displacement under a
pressure mode p_k cos(q x) is

    u_k = 2 p_k / (E* |q|),    E* = E / (1 - nu^2)   (plane strain, Johnson 1985 eq. 2.25a),

solved on an FFT grid with the constrained conjugate gradient of Polonsky & Keer (Wear 231, 1999)
at a fixed mean pressure.  The FE block has a finite height H with a held top; for H >= the period
L its compliance differs from the half-plane's by a factor 1 - O(exp(-2 q H)) <= 1 - 1e-5 at the
longest wave q = 2 pi / L, so the comparison is exact up to discretisation and the small-slope
(linear) approximation.

Compared: the contact fraction (contact length / L, 7.4) and the mean contact pressure
(eq. 6.11) of the FE run's window against the BEM's, at the BEM's pressure for each requested
contact fraction.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rubberfriction.driver.verification import check

#: BEM grid points per FE master segment (the profile is linear between its vertices)
BEM_REFINE = 8


def bem_contact(h: np.ndarray, period: float, e_star: float, p_mean: float,
                tol: float = 1e-10, max_iterations: int = 5000) -> tuple[np.ndarray, float]:
    """Pressure on a uniform grid of one period (h: heights of the rigid profile on it) of a
    periodic elastic half-plane (plane-strain modulus ``e_star``) pressed onto the profile at mean
    pressure ``p_mean`` (Polonsky-Keer constrained conjugate gradient; the approach is the
    Lagrange multiplier of the mean-pressure constraint).  Returns (pressure, contact fraction).
    """
    n = h.size
    q = 2.0 * np.pi * np.fft.rfftfreq(n, d=period / n)
    compliance = np.zeros_like(q)
    compliance[1:] = 2.0 / (e_star * q[1:])

    def displacement(p: np.ndarray) -> np.ndarray:  # of the body's surface, mean-free
        return np.fft.irfft(compliance * np.fft.rfft(p), n=n)

    p = np.full(n, float(p_mean))
    t = np.zeros(n)
    g_norm_old, delta = 1.0, 0.0
    for _ in range(max_iterations):
        gap = displacement(p) - h
        inside = p > 0.0
        gap -= gap[inside].mean()
        g_norm = float(np.sum(gap[inside] ** 2))
        t = np.where(inside, gap + delta * (g_norm / g_norm_old) * t, 0.0)
        g_norm_old = g_norm
        r = displacement(t)
        r -= r[inside].mean()
        denom = float(np.sum(r[inside] * t[inside]))
        if denom == 0.0:
            break
        tau = float(np.sum(gap[inside] * t[inside])) / denom
        p_old = p.copy()
        p = np.where(inside, p - tau * t, 0.0)
        p[p < 0.0] = 0.0
        overlap = (p == 0.0) & (gap < 0.0)
        delta = 0.0 if np.any(overlap) else 1.0
        p[overlap] -= tau * gap[overlap]
        p *= p_mean / p.mean()
        if np.sum(np.abs(p - p_old)) <= tol * np.sum(np.abs(p)):
            break
    return p, float(np.mean(p > 0.0))


def refine_profile(x: np.ndarray, h: np.ndarray, period: float, factor: int) -> np.ndarray:
    """Heights of the periodic polyline (x, h) on a uniform grid `factor` times finer."""
    n = x.size * factor
    xf = np.arange(n) * period / n
    return np.interp(xf, np.append(x, x[0] + period), np.append(h, h[0]))


def pressure_for_fraction(h_fine: np.ndarray, period: float, e_star: float, fraction: float,
                          slope: float) -> float:
    """Mean pressure at which the BEM's contact fraction is ``fraction`` (bisection in log p)."""
    lo, hi = 1e-6 * e_star * slope, e_star * slope
    for _ in range(50):
        mid = float(np.sqrt(lo * hi))
        if bem_contact(h_fine, period, e_star, mid)[1] < fraction:
            lo = mid
        else:
            hi = mid
    return float(np.sqrt(lo * hi))


def case_profile(n: int = 64, rms_slope: float = 0.03, hurst: float = 0.8, seed: int = 1,
                 period: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The case's self-affine profile (n vertices over one period), scaled to ``rms_slope``."""
    from rubberfriction.driver.surfaces.generators import self_affine_profile

    prof = self_affine_profile(period, period / n, H=hurst, rms_height=1.0, seed=seed)
    x, h = np.asarray(prof.x, float), np.asarray(prof.h, float)
    s = np.sqrt(np.mean((np.diff(np.append(h, h[0])) / (period / n)) ** 2))
    return x, h * (rms_slope / s)


def elastic_compound(name: str = "m1"):
    """The equilibrium (long-time) part of a compound file: elastic, no Prony series."""
    from rubberfriction.forms.compound import Compound
    from rubberfriction.forms.material_files import load_compound

    c = load_compound(name)
    return Compound(name=f"{c.name}-elastic", hyperelastic=c.hyperelastic, prony=None, wlf=None,
                    thermal=None)


def compare(fractions=(0.07, 0.2, 0.3), n: int = 64, rms_slope: float = 0.03, seed: int = 1,
            compound: str = "m1", contact: str = "mortar", slide_periods: float = 1.0,
            refine: int = 1) -> dict:
    """FE pressure-branch runs (frictionless, elastic, periodic, block height = period) at the
    BEM's pressure for each contact fraction, ``refine`` contact elements per profile segment.
    The window is the whole slide (``window_start`` 0: an elastic frictionless run has no
    run-in), by default one period, so the FE measure is averaged over the road's offsets
    against the mesh: at one offset a patch edge counts up to a node more or less, a sizeable
    share of the contact at the lowest fraction (docs/verification.md).
    Returns per fraction the BEM's and the FE's contact fraction and mean contact pressure, and
    the FE's contact fraction after compression."""
    from rubberfriction.driver.sliding.run import run_sliding
    from rubberfriction.driver.sliding.spec import SlidingSpec

    period = 1.0
    x, h = case_profile(n, rms_slope, seed=seed, period=period)
    mat = elastic_compound(compound)
    he = mat.hyperelastic
    e_star = he.E / (1.0 - he.nu**2)
    h_fine = refine_profile(x, h, period, BEM_REFINE)
    rows = []
    for a in fractions:
        p = pressure_for_fraction(h_fine, period, e_star, float(a), rms_slope)
        pb, ab = bem_contact(h_fine, period, e_star, p)
        spec = SlidingSpec(surface_x=x, surface_h=h, period=period, pressure=p, velocity=10.0,
                           compound=mat, friction=None, h_contact=period / (n * refine),
                           block_height=period, slide_distance=slide_periods * period,
                           window_start=0.0,
                           contact=contact)
        res = run_sliding(spec)
        rows.append({"pressure": p, "bem_fraction": ab, "bem_contact_pressure": p / ab,
                     "status": res.status, "reason": res.reason,
                     "fe_fraction": res.contact_fraction,
                     "fe_compression_fraction": res.stats.get("compression_contact_fraction",
                                                              float("nan")),
                     "fe_contact_pressure": res.mean_pressure})
    return {"e_star": e_star, "rows": rows}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--fractions", type=float, nargs="+", default=[0.07, 0.2, 0.3],
                   help="BEM contact fractions to compare at (default 0.07 0.2 0.3)")
    p.add_argument("--n", type=int, default=64, help="profile vertices = contact elements")
    p.add_argument("--rms-slope", type=float, default=0.03, help="rms slope of the profile")
    p.add_argument("--seed", type=int, default=1, help="seed of the self-affine profile")
    p.add_argument("--refine", type=int, default=1,
                   help="contact elements per profile segment (default 1)")
    p.add_argument("--contact", default="mortar", help="contact formulation (mortar, nts, surface)")
    p.add_argument("--tolerance", type=float, default=0.03, help="relative tolerance")


def run(args: argparse.Namespace) -> dict:
    t0 = time.perf_counter()
    out = compare(tuple(args.fractions), args.n, args.rms_slope, args.seed,
                  contact=args.contact, refine=args.refine)
    checks = []
    for row in out["rows"]:
        a = row["bem_fraction"]
        checks.append(check(f"contact fraction @ {a:.3f}", row["fe_fraction"], a, args.tolerance))
        checks.append(check(f"contact pressure @ {a:.3f}", row["fe_contact_pressure"],
                            row["bem_contact_pressure"], args.tolerance))
    return {"case": "bem-pressure",
            "parameters": {"n": args.n, "rms_slope": args.rms_slope, "seed": args.seed,
                           "contact": args.contact, "refine": args.refine,
                           "E*": out["e_star"]},
            "checks": checks,
            "notes": [f"p = {r['pressure']:.5g} MPa: FE compression fraction "
                      f"{r['fe_compression_fraction']:.4f} ({r['status']} {r['reason']})"
                      for r in out["rows"]] + [f"{time.perf_counter() - t0:.0f} s"]}
