"""Viscoelastic block sliding frictionless in full contact over a small-amplitude sinusoid.

The closed form, mu = (k h0)^2 Im E*_eff(k v) / (4 p0) for plane strain, steady sliding and a
linear viscoelastic half-space, and its derivation are in :mod:`rubberfriction.driver.sliding.
sinusoid` (which also computes it); the block height is one wavelength (thesis 6.2.2), so the
finite-height correction ~exp(-2 pi) is below 0.2 %.

Temperature layers (``--layer THICKNESS:T``, thesis 8.3.3): the block's relaxation times are
WLF-shifted layer by layer from the contact face up, the rest of the block at ``--temperature``.
The reference is then the linear viscoelastic solution of the layered strip of the block's height
(``sinusoid.layered_strip_mu``: transfer matrices of the plane-strain equations per layer), and
the notes give the uniform closed forms at the coldest and hottest temperature present, between
which a layered block's mu lies where the loss modulus is monotone in T.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from rubberfriction.driver.fe.solid import ELEMENTS
from rubberfriction.driver.sliding.outputs import DissipationByDepth, FieldWriter, write_run_outputs
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.sinusoid import (closed_form_mu, full_contact_pressure,
                                                    layered_strip_mu)
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.verification import check
from rubberfriction.forms.compound import Compound
from rubberfriction.forms.material_files import load_compound


def simulate(compound: Compound, *, wavelength: float = 1.0, amplitude: float = 0.002,
             pressure: float = 0.1, velocity: float = 10.0, temperature: float | None = None,
             elements_per_wavelength: int = 16, segments: int = 128, periods: float = 3.0,
             step_fraction: float = 0.5, contact: str = "mortar", element: str = "Q1P0",
             observers=(),
             converge_tol: float = 0.0, steady_state: bool = False,
             layers: tuple[tuple[float, float], ...] = (), wall_limit: float = 0.0) -> dict:
    """FE run and closed form; returns both mu estimates and the analytical value.

    layers: (thickness mm, T K) from the contact face up (``SlidingSpec.temperature_layers``);
    then mu_exact is the layered strip's (block height = wavelength) and ``mu_bounds`` the
    uniform closed forms at the coldest and hottest temperature present.

    observers: passed to ``run_sliding`` (outputs such as ``driver.sliding.outputs.FieldWriter``).
    ``converge_tol`` > 0: the converged time homogenisation with ``periods`` as the budget
    (``driver.sliding.window``); ``steady_state``: periodic extrapolation of the histories.
    ``wall_limit``: passed to ``run_sliding`` (seconds, 0: none).
    """
    x = np.linspace(0.0, wavelength, segments + 1)[:-1]
    h = amplitude * np.cos(2.0 * np.pi * x / wavelength)
    hc = wavelength / elements_per_wavelength
    spec = SlidingSpec(surface_x=x, surface_h=h, period=wavelength, pressure=pressure,
                       velocity=velocity, compound=compound, temperature=temperature, h_contact=hc,
                       contact=contact, element=element, slide_distance=periods * wavelength,
                       step_length=step_fraction * hc,
                       converge_tol=converge_tol, steady_state=steady_state,
                       temperature_layers=tuple((float(d), float(T)) for d, T in layers))
    res = run_sliding(spec, observers=observers, wall_limit=wall_limit)
    out = {"result": res, "spec": spec, "mu_force": res.mu_force, "mu_energy": res.mu_energy,
           "mu_exact": closed_form_mu(compound, wavelength, amplitude, pressure, velocity,
                                      temperature),
           "p_full_contact": full_contact_pressure(compound, wavelength, amplitude, velocity)}
    if spec.temperature_layers:
        background = temperature if temperature is not None else compound.wlf.T_ref
        out["mu_exact"] = layered_strip_mu(compound, wavelength, amplitude, pressure, velocity,
                                           wavelength, spec.temperature_layers, background)
        uniform = [closed_form_mu(compound, wavelength, amplitude, pressure, velocity, T)
                   for T in {background, *(T for _, T in spec.temperature_layers)}]
        out["mu_bounds"] = (min(uniform), max(uniform))
    return out


def parse_layer(text: str) -> tuple[float, float]:
    """'THICKNESS:T' (mm, K) -> (thickness, T); argparse type of ``--layer``."""
    try:
        d, T = text.split(":")
        return float(d), float(T)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--layer: expected THICKNESS:T (mm:K), got {text!r}") from None


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--compound", default="tread_default", help="compound name or TOML file")
    p.add_argument("--wavelength", type=float, default=1.0, help="mm")
    p.add_argument("--amplitude", type=float, default=0.002, help="h0, mm")
    p.add_argument("--pressure", type=float, default=0.1, help="MPa (must exceed full-contact p*)")
    p.add_argument("--velocity", type=float, default=10.0, help="mm/s")
    p.add_argument("--temperature", type=float, default=None, help="K (default: WLF reference)")
    p.add_argument("--mesh", type=int, default=16,
                   help="elements per wavelength on the contact face")
    p.add_argument("--periods", type=float, default=3.0, help="sliding distance in wavelengths")
    p.add_argument("--contact", default="mortar", choices=["mortar", "nts", "surface"])
    p.add_argument("--element", default="Q1P0", choices=ELEMENTS, help="rubber element")
    p.add_argument("--layer", type=parse_layer, action="append", default=[], metavar="THICKNESS:T",
                   help="temperature layer from the contact face up (mm:K, repeatable; the block "
                        "above the layers is at --temperature); checked against the layered strip")
    p.add_argument("--out", metavar="DIR", default=None,
                   help="write the run's outputs to DIR: fields/ (XDMF for ParaView, contact "
                        "pressure CSV), series.csv, mu.png, dissipation_by_depth.csv, summary.json")


def run(args: argparse.Namespace) -> dict:
    comp = load_compound(args.compound)
    folder = getattr(args, "out", None)
    observers = []
    if folder:

        observers = [FieldWriter(Path(folder) / "fields"), DissipationByDepth()]
    out = simulate(comp, wavelength=args.wavelength, amplitude=args.amplitude,
                   pressure=args.pressure, velocity=args.velocity, temperature=args.temperature,
                   elements_per_wavelength=args.mesh, periods=args.periods, contact=args.contact,
                   element=args.element,
                   observers=observers, layers=tuple(getattr(args, "layer", []) or ()))
    res = out["result"]
    notes = [f"run status: {res.status} {res.reason}",
             f"wall time {res.stats.get('wall_time', 0):.2f} s",
             f"full contact needs p > {out['p_full_contact']:.4g} MPa"]
    if "mu_bounds" in out:
        lo, hi = out["mu_bounds"]
        notes.append(f"layered strip mu {out['mu_exact']:.5g}; uniform closed forms over the "
                     f"temperatures present: {lo:.5g} .. {hi:.5g}")
    if folder:

        written = write_run_outputs(res, out["spec"], folder)
        notes.append(f"outputs in {folder}: fields/{observers[0].xdmf_path.name}, "
                     + ", ".join(p.name for p in written.values()))
    reference = "layered strip" if "mu_bounds" in out else "closed form"
    checks = [check(f"mu (force, eq. 6.2) vs {reference}", out["mu_force"], out["mu_exact"], 0.03),
              check(f"mu (energy, eq. 2.8) vs {reference}", out["mu_energy"], out["mu_exact"],
                    0.03),
              check("mu force vs energy", out["mu_force"], out["mu_energy"], 0.02)]
    params = {k: getattr(args, k) for k in ("compound", "wavelength", "amplitude", "pressure",
                                            "velocity", "temperature", "mesh", "periods", "contact",
                                            "element")}
    params["layers"] = [list(x) for x in getattr(args, "layer", []) or []]
    if folder:
        params["out"] = str(folder)
    return {"case": "viscoelastic-sinusoid", "parameters": params, "checks": checks, "notes": notes}
