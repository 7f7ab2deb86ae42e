"""The analytical baselines of a scene: Persson and Klüppel-Heinrich mu(v) from the FE's inputs.

The theories of :mod:`rubberfriction.driver.theory` take a profile PSD, a rubber and conditions;
this module gets those from what a user hands the FE (a loaded :class:`Scene`, or the
``rubberfriction theory`` options): the surface PSD of a profile file, of several files banded
like the multiscale driver, of the default road, or the line spectrum of sine waves; the compound
as :class:`~rubberfriction.driver.theory.rubber.Rubber`; pressure, speeds, T0 and the bell law.
Used by ``rubberfriction theory`` and by the multiscale report (theory curves beside the FE).

Surface: a profile file is read with ``driver.surfaces.load_profile`` (cleaned), its PSD is
``psd_1d`` (Hann window); the default range is wavelengths from a quarter of the record length
down to the Nyquist wavelength.  ``"default"`` is the default road (CAPTIF + generated
fine extension) at the scene's edges as its cut-off rule keeps them (without a scene: the thesis
edges down to 0.003 mm, no rule; the label says which); several ``files`` are combined like
the multiscale driver does (``driver.surfaces.multiscale_from_measurements``): the PSD of each
band profile within its band.  Sines give a line spectrum: only the line-roughness Persson
model applies (in full contact it is the exact viscoelastic result).  Units: speeds mm/s,
pressure MPa, temperature K, wavelengths mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.scenes import Scene
from rubberfriction.driver.surfaces import (
    DEFAULT_EDGES,
    default_road,
    load_profile,
    multiscale_from_measurements,
    psd_1d,
)
from rubberfriction.driver.surfaces.cutoff import DEFAULT_MAX_SLOPE, apply_cutoff, parse_cutoff
from rubberfriction.driver.surfaces.four_scale import FOUR_SCALE_EDGES, four_scale_road
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.theory.curves import (
    MODELS,
    TheoryCurve,
    add_to_axes,
    persson_curve,
    theory_curves,
)
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.persson import PerssonOptions
from rubberfriction.driver.theory.rubber import Rubber, rubber_from_compound
from rubberfriction.driver.theory.spectrum import line_spectrum
from rubberfriction.forms.material_files import DEFAULT_COMPOUND, load_compound

DEFAULT_N = 50
DEFAULT_VRANGE = (1e-3, 1e4)  # mm/s
DEFAULT_PRESSURE = 0.3  # MPa


@dataclass(frozen=True)
class TheoryRequest:
    """What the baselines are evaluated for (plain data; see the module docstring).

    The surface is the first that applies of ``sines`` (amplitude, wavelength in mm), ``files``
    (banded at ``edges``) and ``surface`` (``"default"`` or one profile file).
    """

    compound: str = DEFAULT_COMPOUND  # name or TOML file, for load_compound
    pressure: float = DEFAULT_PRESSURE
    velocities: tuple[float, ...] = tuple(np.geomspace(*DEFAULT_VRANGE, DEFAULT_N))
    T0: float | None = None  # K; None: the WLF reference temperature
    surface: str = "default"
    files: tuple[str, ...] = ()
    sines: tuple[tuple[float, float], ...] = ()
    edges: tuple[float, ...] | None = None
    lambda_max: float | None = None
    lambda_min: float | None = None
    models: tuple[str, ...] = MODELS
    gamma: float = 0.5
    nu: float | None = None
    flash: bool = False
    adhesion: BellLaw | None = None
    notes: tuple[str, ...] = ()
    #: how the shipped road's lowest scale was chosen (a scene's cut-off rule), for the label
    cutoff: str | None = None


def request_from_scene(scene: Scene, **overrides: Any) -> TheoryRequest:
    """The request of a loaded scene: its surface (edges give the analysis range edges[0] ..
    edges[-1]), first compound and pressure, speeds, T0 and bell law; ``overrides`` replace
    fields (a given compound or pressure drops the "scene lists N ..." note)."""
    surf, cond = scene.surface, scene.conditions
    notes = []
    if len(cond.compounds) > 1 and overrides.get("compound") is None:
        notes.append(f"scene lists {len(cond.compounds)} compounds; using {cond.compounds[0]!r} "
                     "(--compound picks another)")
    if len(cond.pressures) > 1 and overrides.get("pressure") is None:
        notes.append(f"scene lists {len(cond.pressures)} pressures; using "
                     f"{cond.pressures[0]:g} MPa (--pressure picks another)")
    if not scene.physics.hysteresis:
        notes.append("scene has [physics] hysteresis = false (elastic FE rubber); the theory "
                     "curves are viscoelastic")
    edges = tuple(float(e) for e in surf.edges) or None
    req = TheoryRequest(
        compound=str(cond.compound_paths[0]), pressure=float(cond.pressures[0]),
        velocities=tuple(float(v) for v in cond.velocities), T0=cond.T0,
        surface="four_scale" if surf.source == "four_scale" else "default",
        files=tuple(str(f) for f in surf.files) if surf.source == "files" else (),
        sines=tuple(zip(surf.amplitudes, surf.wavelengths)) if surf.source == "sines" else (),
        edges=edges, lambda_max=edges[0] if edges else None,
        lambda_min=edges[-1] if edges else None, adhesion=scene.adhesion, notes=tuple(notes),
        cutoff=str(surf.cutoff_report.rule) if surf.cutoff_report is not None else None)
    return replace(req, **{k: v for k, v in overrides.items() if v is not None})


@dataclass
class SurfacePSD:
    """A profile PSD with its analysis range and provenance."""

    q: np.ndarray
    C1D: np.ndarray
    qmin: float
    qmax: float
    source: str


def _band_psd(road: Any) -> tuple[np.ndarray, np.ndarray]:
    """PSD of a multiscale surface: each band profile's psd_1d within its band, concatenated."""
    qs, cs = [], []
    for sc in road.scales:
        q, C = psd_1d(sc.profile)
        lo, hi = 2 * math.pi / sc.band[0], 2 * math.pi / sc.band[1]
        m = (q >= lo) & (q <= hi)
        qs.append(q[m])
        cs.append(C[m])
    q = np.concatenate(qs)
    C = np.concatenate(cs)
    order = np.argsort(q)
    q, C = q[order], C[order]
    keep = np.concatenate(([True], np.diff(q) > 0))
    return q[keep], C[keep]


def road_label(road: Any, cutoff: str | None = None) -> str:
    """What a shipped road is and where it stops: its name without the builder's description,
    which part is measured and which generated, the shortest wavelength and the rule that chose
    it (``cutoff``, a scene's ``CutoffRule`` as text; None: the edges as given)."""
    base = (road.name or "road").split(" (")[0]
    kinds = []
    for kind in ("measured", "generated"):
        bands = [s.band for s in road.scales if s.kind == kind]
        if bands:
            what = "CAPTIF chipseal, measured" if kind == "measured" and "CAPTIF" in road.name \
                else kind
            what = "self-affine extension" if kind == "generated" and "default" in base else what
            kinds.append(f"{what} {bands[0][0]:g}-{bands[-1][1]:g} mm")
    rule = f"by {cutoff}" if cutoff else "(the edges as given, no cut-off rule)"
    return f"{base} ({'; '.join(kinds)}), cut at {road.edges[-1]:g} mm {rule}"


def surface_psd(surface: str | None = "default", lambda_max: float | None = None,
                lambda_min: float | None = None, *, files: Sequence[str] = (),
                edges: tuple[float, ...] | None = None, cutoff: str | None = None) -> SurfacePSD:
    """Profile PSD (Persson convention) of a profile file, several files or a shipped road.

    ``surface="default"``: the default road with ``edges`` if given, else cut by the default
    lowest-scale rule (``cutoff = "slope"``, as the default scene and ``surface default``);
    ``"four_scale"``: the four-scale road (driver.surfaces.four_scale), likewise; ``files``:
    profiles of one road at several resolutions, decomposed at ``edges`` like the multiscale
    driver; otherwise ``surface`` is one profile file.  ``cutoff`` (a scene's cut-off rule as
    text) goes into the shipped road's label (:func:`road_label`), which states the road and
    where it stops.
    """
    if files:
        profiles = [load_profile(f) for f in files]
        if edges is None:
            raise TheoryInputError("several profile files need the scale edges ([surface] edges)")
        road = multiscale_from_measurements(profiles, edges, name="scene profiles")
        q, C = _band_psd(road)
        lam_hi, lam_lo = road.edges[0], road.edges[-1]
        source = ", ".join(Path(f).name for f in files)
    elif surface in (None, "default", "default_road", "four_scale"):
        make = four_scale_road if surface == "four_scale" else default_road
        if edges is None:  # the shipped road as every command takes it: the slope cut-off rule
            edges_all = FOUR_SCALE_EDGES if surface == "four_scale" else DEFAULT_EDGES
            road, _ = apply_cutoff(lambda e: make(edges=e), edges_all, parse_cutoff("slope"))
            cutoff = cutoff or f'cutoff = "slope" (max_slope = {DEFAULT_MAX_SLOPE:g})'
        else:
            road = make(edges=edges)
        q, C = _band_psd(road)
        lam_hi, lam_lo = road.edges[0], road.edges[-1]
        source = road_label(road, cutoff)
    else:
        prof = load_profile(surface)
        q, C = psd_1d(prof)
        lam_hi = prof.length / 4.0
        lam_lo = 2 * math.pi / q[-1]
        source = str(surface)
    lam_hi = lam_hi if lambda_max is None else float(lambda_max)
    lam_lo = lam_lo if lambda_min is None else float(lambda_min)
    if not (lam_hi > lam_lo > 0):
        raise TheoryInputError(f"wavelength range {lam_hi:g}..{lam_lo:g} mm: expected lambda_max > "
                               "lambda_min > 0")
    qmin = max(2 * math.pi / lam_hi, float(q[0]))
    qmax = min(2 * math.pi / lam_lo, float(q[-1]))
    if not qmin < qmax:
        raise TheoryInputError(
            f"wavelengths {lam_hi:g}..{lam_lo:g} mm are outside the profile's spectrum "
            f"{2 * math.pi / q[-1]:g}..{2 * math.pi / q[0]:g} mm"
        )
    return SurfacePSD(q=q, C1D=C, qmin=qmin, qmax=qmax, source=source)


def load_rubber(compound: str, nu: float | None = None) -> tuple[Rubber, str]:
    """Rubber for the theories from a compound name or TOML file (forms.material_files)."""
    comp = load_compound(compound)
    rubber = rubber_from_compound(comp)
    if nu is not None:
        rubber = Rubber(rubber.modulus, nu=nu, log10_aT=rubber.log10_aT, rho=rubber.rho, c=rubber.c,
                        k=rubber.k, name=rubber.name, T_ref=rubber.T_ref)
    return rubber, comp.name


@dataclass
class TheoryResult:
    """Curves and their JSON-ready description (conditions, surface, compound, adhesion, notes)."""

    curves: list[TheoryCurve]
    info: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {**self.info, "curves": [c.to_dict() for c in self.curves]}


def evaluate(req: TheoryRequest) -> TheoryResult:
    """The requested theories' mu(v) (and A/A0) for one request."""
    p, v = float(req.pressure), np.asarray(req.velocities, dtype=float)
    # validate the cheap inputs before building the surface
    if not (math.isfinite(p) and p > 0):
        raise TheoryInputError(f"pressure = {p} MPa: expected > 0")
    if v.size == 0 or np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise TheoryInputError(f"sliding speeds must be > 0 mm/s; got {v.tolist()}")
    rubber, comp_name = load_rubber(req.compound, req.nu)
    options = PerssonOptions(gamma=req.gamma)
    law = req.adhesion
    alpha = law.alpha if law is not None else 1.0
    notes = list(req.notes)
    if req.sines:
        k = np.array([2 * math.pi / lam for _, lam in req.sines])
        amp = np.array([abs(a) for a, _ in req.sines])
        spec = line_spectrum(k, amp / math.sqrt(2.0), dim=1)
        skipped = [m for m in req.models if m != "persson-1d"]
        if skipped:
            notes.append("sine surface: line spectrum, only persson-1d applies "
                         f"(skipped {skipped})")
        curves = [persson_curve(spec, rubber, p, v, T0=req.T0, options=options, flash=req.flash,
                                adhesion=law, alpha=alpha)]
        waves = ", ".join(f"{a:g} mm x {lam:g} mm" for a, lam in req.sines)
        surf_info = {"source": "sines " + waves,
                     "lambda_max_mm": max(lam for _, lam in req.sines),
                     "lambda_min_mm": min(lam for _, lam in req.sines)}
    else:
        psd = surface_psd(req.surface, req.lambda_max, req.lambda_min, files=req.files,
                          edges=req.edges, cutoff=req.cutoff)
        curves = theory_curves(psd.q, psd.C1D, rubber, p, v, T0=req.T0, models=req.models,
                               qmin=psd.qmin, qmax=psd.qmax, flash=req.flash, adhesion=law,
                               alpha=alpha, options=options)
        surf_info = {"source": psd.source, "lambda_max_mm": 2 * math.pi / psd.qmin,
                     "lambda_min_mm": 2 * math.pi / psd.qmax}
    info = {
        "conditions": {"pressure_MPa": p, "T0_K": req.T0, "v_mm_s": [float(x) for x in v],
                       "flash_temperature": bool(req.flash)},
        "surface": surf_info,
        "notes": notes,
        "compound": {"name": comp_name, "nu": rubber.nu, "T_ref_K": rubber.T_ref},
        "adhesion": None if law is None else {"tau0_MPa": law.tau0, "c": law.c,
                                              "v0_mm_s": law.v0, "alpha": alpha},
    }
    return TheoryResult(curves, info)


def draw_beside_fe(ax_mu: Any, scene: Scene, *, v_fe: Any, compound: str | None = None,
                   pressure: float | None = None, T0: float | None = None,
                   models: tuple[str, ...] = ("persson-1d", "persson-2d", "kluppel-heinrich"),
                   ax_area: Any | None = None, n: int = 40) -> tuple[list[TheoryCurve], list[str]]:
    """Draw the theory curves of a scene on the multiscale report's mu(v) axes (and A/A0 axes).

    The curves span the FE speeds ``v_fe`` (mm/s) with a factor 3 margin on a log grid of ``n``
    speeds, for the FE's compound, pressure and temperature.  A failure (e.g. a profile file gone
    since the scene was loaded) never breaks the report: it is returned as a note and nothing is
    drawn.  Returns (curves, notes); the notes end with the curves' validity flags
    ("persson-2d outside validity: ..."), which the report writes into summary.txt.
    """
    v = np.asarray(v_fe, dtype=float).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    if v.size == 0:
        return [], ["theory: no FE speeds > 0 to compare with"]
    grid = tuple(np.geomspace(v.min() / 3.0, v.max() * 3.0, n))
    try:
        req = request_from_scene(scene, velocities=grid, compound=compound, pressure=pressure,
                                 T0=T0, models=tuple(models))
        result = evaluate(req)
    except (TheoryInputError, ValueError, OSError) as err:
        return [], [f"theory curves not drawn: {err}"]
    add_to_axes(result.curves, ax_mu, ax_area)
    flags = [f"{c.model} outside validity: {f.message}" for c in result.curves for f in c.flags]
    return (result.curves,
            list(result.info["notes"]) + [m for c in result.curves for m in c.notes] + flags)
