"""``rubberfriction theory [SCENE]``: mu(v) and A/A0(v) from the analytical theories.

Persson (line roughness = plane strain, and isotropic eq. 2.10), Klüppel-Heinrich (eq. 2.9) and,
with a bell law, the adhesion term (eqs. 2.11, 7.6, 7.7), all fed with the same surface PSD and
compound as the FE.  Examples::

    rubberfriction theory --surface default --compound tread_default --pressure 0.3 \\
        --vmin 1e-3 --vmax 1e4 --n 50 --temperature 293.15 --plot mu.png --csv mu.csv
    rubberfriction theory scene.toml --flash --json

Units: speeds mm/s, pressure MPa, temperature K, wavelengths mm.

Scene file (TOML): only the keys below are read, every other key or table is ignored.  Two
spellings are understood: the multiscale driver's scene (``driver/scenes/*.toml``, see
``rubberfriction run --schema``) and a minimal one::

    [surface]
    source = "default_road"  # multiscale scene: default_road | files (files = [...]) | sines
    edges = [20.0, 3.0, 0.3, 0.04, 0.003]   # mm: analysis range edges[0] .. edges[-1]
    # minimal form instead: profile = "road.dat" (or file/path; "default" = default road),
    # optional lambda_max, lambda_min (mm).  Relative paths are relative to the scene file.
    amplitudes = [0.075, 0.01]              # source = "sines": one sine per entry (mm) ...
    wavelengths = [5.0, 0.5]                # ... with these wavelengths (mm): line spectrum
    [compound]
    name = "tread_default"   # minimal form (or file/path); multiscale scene: [conditions] compounds
    [conditions]
    compounds = ["tread_default"]  # the first is used (--compound picks another)
    pressures = [0.3]        # MPa, the first is used (also: p, pressure; --pressure)
    velocities = [1.0, 10.0] # mm/s (also: v, velocity)
    T0 = 20.0                # with T0_unit = "degC" or "K" (default K); also T0_C in degC
    [physics]
    adhesion = true          # multiscale scene: use the [adhesion] table only when true
    [adhesion]               # bell law eq. (7.6): tau0 (MPa), c, v0 (mm/s), alpha (eq. 7.3)
    tau0 = 3.0
    c = 0.15
    v0 = 20.0
    alpha = 1.0

Command-line options override the scene.  Surface: a profile file is read with
``driver.surfaces.load_profile`` (cleaned), its PSD is ``psd_1d`` (Hann window); the default
range is wavelengths from a quarter of the record length down to the Nyquist wavelength.
``default``/``default_road`` is the four-scale default road (CAPTIF + generated fine extension),
several ``files`` are combined like the multiscale driver does
(``driver.surfaces.multiscale_from_measurements``): the PSD of each band profile within its
band.  ``sines`` give a line spectrum: only the line-roughness Persson model applies (in full
contact it is the exact viscoelastic result).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.theory.curves import (
    MODELS,
    TheoryCurve,
    persson_curve,
    plot_curves,
    theory_curves,
)
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.persson import PerssonOptions
from rubberfriction.driver.theory.rubber import Rubber, rubber_from_compound
from rubberfriction.driver.theory.spectrum import line_spectrum

if TYPE_CHECKING:
    from rubberfriction.driver.multiscale.scene import Scene

DEFAULT_COMPOUND = "tread_default"
DEFAULT_N = 50
DEFAULT_VRANGE = (1e-3, 1e4)   # mm/s


@dataclass
class SceneInputs:
    """The keys of a scene file that the theories need (see module docstring)."""

    surface: str | None = None                 #: "default" or a profile path
    files: list[str] = field(default_factory=list)
    sines: list[tuple[float, float]] = field(default_factory=list)   #: (amplitude, wavelength) mm
    edges: tuple[float, ...] | None = None
    lambda_max: float | None = None
    lambda_min: float | None = None
    compound: str | None = None
    pressure: float | None = None
    velocities: list[float] | None = None
    T0: float | None = None
    adhesion: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def _pick(table: dict[str, Any], keys: tuple[str, ...], where: str) -> Any:
    found = [k for k in keys if k in table]
    if len(found) > 1:
        raise TheoryInputError(f"{where}: give only one of {found}")
    return table[found[0]] if found else None


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TheoryInputError(f"{where} = {value!r}: expected a number")
    return float(value)


def _numbers(value: Any, where: str) -> list[float]:
    vals = value if isinstance(value, list) else [value]
    if not vals:
        raise TheoryInputError(f"{where} is empty: expected at least one number")
    return [_number(x, where) for x in vals]


def _path(base: Path, text: Any, where: str) -> str:
    if not isinstance(text, str) or not text:
        raise TheoryInputError(f"{where} = {text!r}: expected a file name")
    return text if Path(text).is_absolute() else str(base / text)


def read_scene(path: str | Path) -> SceneInputs:
    """Read the theory keys from a scene TOML (see module docstring; other keys are ignored)."""
    path = Path(path)
    if not path.is_file():
        raise TheoryInputError(f"scene file not found: {path}")
    try:
        doc = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as err:
        raise TheoryInputError(f"{path}: not valid TOML: {err}") from None
    out = SceneInputs()
    base = path.resolve().parent
    surf = doc.get("surface", {})
    if isinstance(surf, str):
        surf = {"profile": surf}
    if not isinstance(surf, dict):
        raise TheoryInputError(f"{path} [surface]: expected a table")
    src = _pick(surf, ("profile", "file", "path"), f"{path} [surface]")
    source = surf.get("source")
    if src is not None and source is not None:
        raise TheoryInputError(f"{path} [surface]: give either profile or source, not both")
    if src is not None:
        out.surface = ("default" if src in ("default", "default_road")
                       else _path(base, src, f"{path} [surface].profile"))
    elif source is not None:
        if source == "default_road":
            out.surface = "default"
        elif source == "files":
            files = surf.get("files", [])
            if not isinstance(files, list) or not files:
                raise TheoryInputError(f"{path} [surface].files: expected a non-empty list of "
                                       "profile files")
            out.files = [_path(base, f, f"{path} [surface].files") for f in files]
        elif source == "sines":
            amps = _numbers(surf.get("amplitudes", []), f"{path} [surface].amplitudes")
            lams = _numbers(surf.get("wavelengths", []), f"{path} [surface].wavelengths")
            if len(amps) != len(lams):
                raise TheoryInputError(f"{path} [surface]: {len(amps)} amplitudes but {len(lams)} "
                                       "wavelengths")
            out.sines = list(zip(amps, lams))
        else:
            raise TheoryInputError(f"{path} [surface].source = {source!r}: expected default_road, "
                                   "files or sines")
    if "edges" in surf:
        out.edges = tuple(_numbers(surf["edges"], f"{path} [surface].edges"))
        out.lambda_max, out.lambda_min = out.edges[0], out.edges[-1]
    for key in ("lambda_max", "lambda_min"):
        if key in surf:
            setattr(out, key, _number(surf[key], f"{path} [surface].{key}"))
    comp = doc.get("compound", {})
    if isinstance(comp, str):
        comp = {"name": comp}
    if isinstance(comp, dict):
        name = _pick(comp, ("name", "file", "path"), f"{path} [compound]")
        if name is not None:
            name = str(name)
            out.compound = (_path(base, name, f"{path} [compound]") if name.endswith(".toml")
                            else name)
    cond = doc.get("conditions", {})
    if not isinstance(cond, dict):
        raise TheoryInputError(f"{path} [conditions]: expected a table")
    comps = cond.get("compounds")
    if comps is not None:
        if not isinstance(comps, list) or not comps or not all(isinstance(c, str) for c in comps):
            raise TheoryInputError(f"{path} [conditions].compounds: expected a non-empty list of "
                                   "names")
        if out.compound is None:
            c0 = comps[0]
            out.compound = (_path(base, c0, f"{path} [conditions].compounds")
                            if c0.endswith(".toml") else c0)
        if len(comps) > 1:
            out.notes.append(f"scene lists {len(comps)} compounds; using {comps[0]!r} (--compound "
                             "picks another)")
    p = _pick(cond, ("p", "pressure", "pressures"), f"{path} [conditions]")
    if p is not None:
        ps = _numbers(p, f"{path} [conditions].pressures")
        out.pressure = ps[0]
        if len(ps) > 1:
            out.notes.append(f"scene lists {len(ps)} pressures; using {ps[0]:g} MPa (--pressure "
                             "picks another)")
    v = _pick(cond, ("v", "velocities", "velocity"), f"{path} [conditions]")
    if v is not None:
        out.velocities = _numbers(v, f"{path} [conditions].velocities")
    T = _pick(cond, ("T0", "T", "temperature", "T0_C"), f"{path} [conditions]")
    if T is not None:
        unit = "degC" if "T0_C" in cond else cond.get("T0_unit", "K")
        if unit not in ("K", "degC"):
            raise TheoryInputError(f"{path} [conditions].T0_unit = {unit!r}: expected 'K' or "
                                   "'degC'")
        out.T0 = _number(T, f"{path} [conditions].T0") + (273.15 if unit == "degC" else 0.0)
    adh = doc.get("adhesion", {})
    phys = doc.get("physics", {})
    # multiscale scene: [adhesion] counts only with [physics] adhesion = true (its default is
    # false); minimal form (no [physics] table): an [adhesion] table switches it on
    if "physics" in doc and isinstance(phys, dict):
        use_adhesion = bool(phys.get("adhesion", False))
    else:
        use_adhesion = True
    if isinstance(adh, dict) and use_adhesion:
        for key in ("tau0", "c", "v0", "alpha"):
            if key in adh:
                out.adhesion[key] = _number(adh[key], f"{path} [adhesion].{key}")
    return out


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
    from rubberfriction.driver.surfaces import psd_1d

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


def surface_psd(surface: str | None = "default", lambda_max: float | None = None,
                lambda_min: float | None = None, *, files: list[str] | None = None,
                edges: tuple[float, ...] | None = None) -> SurfacePSD:
    """Profile PSD (Persson convention) of a profile file, several files or the default road.

    ``surface="default"``: the default road (with ``edges`` if given); ``files``: profiles of one
    road at several resolutions, decomposed at ``edges`` like the multiscale driver; otherwise
    ``surface`` is one profile file.
    """
    from rubberfriction.driver.surfaces import (
        default_road,
        load_profile,
        multiscale_from_measurements,
        psd_1d,
    )

    if files:
        profiles = [load_profile(f) for f in files]
        if edges is None:
            raise TheoryInputError("several profile files need the scale edges ([surface] edges)")
        road = multiscale_from_measurements(profiles, edges, name="scene profiles")
        q, C = _band_psd(road)
        lam_hi, lam_lo = road.edges[0], road.edges[-1]
        source = ", ".join(Path(f).name for f in files)
    elif surface in (None, "default", "default_road"):
        road = default_road() if edges is None else default_road(edges=edges)
        q, C = _band_psd(road)
        lam_hi, lam_lo = road.edges[0], road.edges[-1]
        source = road.name or "default road"
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
    """Rubber for the theories from a compound name or TOML file (forms.materials)."""
    from rubberfriction.forms.materials import load_compound

    comp = load_compound(compound)
    rubber = rubber_from_compound(comp)
    if nu is not None:
        rubber = Rubber(rubber.modulus, nu=nu, log10_aT=rubber.log10_aT, rho=rubber.rho, c=rubber.c,
                        k=rubber.k, name=rubber.name, T_ref=rubber.T_ref)
    return rubber, comp.name


def scene_inputs(scene: Scene) -> SceneInputs:
    """The theory keys of an already-loaded multiscale scene (``driver.multiscale.scene.Scene``).

    Same meaning as :func:`read_scene` on the scene's file, but from the validated object, so
    the report of a finished campaign needs neither the file nor its folder: surface source,
    edges (analysis range edges[0] .. edges[-1]) and files (already resolved), the first compound
    (as resolved for ``load_compound``) and pressure, the velocities, T0 (kelvin) and the
    adhesion table when ``[physics] adhesion`` is on.
    """
    surf, cond = scene.surface, scene.conditions
    out = SceneInputs()
    edges = tuple(float(e) for e in surf.edges)
    if surf.source == "default_road":
        out.surface = "default"
    elif surf.source == "files":
        out.files = [str(f) for f in surf.files]
    elif surf.source == "sines":
        out.sines = [(float(a), float(lam)) for a, lam in zip(surf.amplitudes, surf.wavelengths)]
    else:
        raise TheoryInputError(f"scene {scene.name!r}: surface source {surf.source!r}: expected "
                               "default_road, files or sines")
    if edges:
        out.edges = edges
        out.lambda_max, out.lambda_min = edges[0], edges[-1]
    out.compound = str(cond.compound_paths[0])
    if len(cond.compounds) > 1:
        out.notes.append(f"scene lists {len(cond.compounds)} compounds; using "
                         f"{cond.compounds[0]!r} (--compound picks another)")
    out.pressure = float(cond.pressures[0])
    if len(cond.pressures) > 1:
        out.notes.append(f"scene lists {len(cond.pressures)} pressures; using "
                         f"{cond.pressures[0]:g} MPa (--pressure picks another)")
    out.velocities = [float(v) for v in cond.velocities]
    out.T0 = None if cond.T0 is None else float(cond.T0)
    if scene.adhesion is not None:
        a = scene.adhesion
        out.adhesion = {"tau0": a.tau0, "c": a.c, "v0": a.v0, "alpha": a.alpha}
    if not scene.physics.hysteresis:
        out.notes.append("scene has [physics] hysteresis = false (elastic FE rubber); the "
                         "theory curves are viscoelastic")
    return out


def _scene_of(scene: str | Path | Scene | SceneInputs | None) -> SceneInputs:
    """Theory inputs of a scene given as a path, a loaded ``Scene``, ``SceneInputs`` or None."""
    if scene is None:
        return SceneInputs()
    if isinstance(scene, SceneInputs):
        return scene
    if isinstance(scene, (str, Path)):
        return read_scene(scene)
    if hasattr(scene, "surface") and hasattr(scene, "conditions"):
        return scene_inputs(scene)
    raise TheoryInputError(f"scene {scene!r}: expected a file path, a loaded Scene or "
                           "SceneInputs")


def _velocities(args: argparse.Namespace, scene: SceneInputs) -> np.ndarray:
    if args.velocities:
        return np.asarray(args.velocities, dtype=float)
    if args.vmin is not None or args.vmax is not None or args.n is not None:
        lo = args.vmin if args.vmin is not None else DEFAULT_VRANGE[0]
        hi = args.vmax if args.vmax is not None else DEFAULT_VRANGE[1]
        n = args.n if args.n is not None else DEFAULT_N
        if not (lo > 0 and hi > lo and n >= 1):
            raise TheoryInputError(f"speed range --vmin {lo} --vmax {hi} --n {n}: expected 0 < "
                                   "vmin < vmax, n >= 1")
        return np.geomspace(lo, hi, int(n))
    if scene.velocities:
        return np.asarray(scene.velocities, dtype=float)
    return np.geomspace(*DEFAULT_VRANGE, DEFAULT_N)


def run_theory(args: argparse.Namespace) -> dict[str, Any]:
    """Evaluate the theories for parsed arguments; returns the JSON-ready result."""
    scene = _scene_of(args.scene or None)
    compound = args.compound or scene.compound or DEFAULT_COMPOUND
    pressure = args.pressure if args.pressure is not None else scene.pressure
    if pressure is None:
        pressure = 0.3
    T0 = args.temperature if args.temperature is not None else scene.T0
    v = _velocities(args, scene)
    lam_max = args.lambda_max if args.lambda_max is not None else scene.lambda_max
    lam_min = args.lambda_min if args.lambda_min is not None else scene.lambda_min
    # validate the cheap inputs before building the surface
    if not (math.isfinite(pressure) and pressure > 0):
        raise TheoryInputError(f"pressure = {pressure} MPa: expected > 0")
    if np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise TheoryInputError(f"sliding speeds must be > 0 mm/s; got {v.tolist()}")
    adhesion = None
    alpha = 1.0
    adh = dict(scene.adhesion)
    if args.adhesion is not None:
        adh.update(dict(zip(("tau0", "c", "v0"), args.adhesion)))
    if args.alpha is not None:
        adh["alpha"] = args.alpha
    if {"tau0", "c", "v0"} <= set(adh):
        adhesion = BellLaw(tau0=adh["tau0"], c=adh["c"], v0=adh["v0"])
        alpha = adh.get("alpha", 1.0)
    elif adh.keys() - {"alpha"}:
        raise TheoryInputError(f"adhesion needs tau0, c and v0; got {sorted(adh)}")
    rubber, comp_name = load_rubber(compound, args.nu)
    options = PerssonOptions(gamma=args.gamma)
    # "scene lists N ...; using the first (--X picks another)" is moot when --X was given
    given = {"--compound": bool(args.compound), "--pressure": args.pressure is not None}
    notes = [n for n in scene.notes if not any(on and f"({opt} picks another)" in n
                                               for opt, on in given.items())]
    if not args.surface and scene.sines:
        k = np.array([2 * math.pi / lam for _, lam in scene.sines])
        amp = np.array([abs(a) for a, _ in scene.sines])
        spec = line_spectrum(k, amp / math.sqrt(2.0), dim=1)
        skipped = [m for m in args.models if m != "persson-1d"]
        if skipped:
            notes.append("sine surface: line spectrum, only persson-1d applies (skipped "
                         f"{skipped})")
        curves = [persson_curve(spec, rubber, float(pressure), v, T0=T0, options=options,
                                flash=args.flash, adhesion=adhesion, alpha=alpha)]
        waves = ", ".join(f"{a:g} mm x {lam:g} mm" for a, lam in scene.sines)
        surf_info = {"source": "sines " + waves,
                     "lambda_max_mm": max(lam for _, lam in scene.sines),
                     "lambda_min_mm": min(lam for _, lam in scene.sines)}
    else:
        if args.surface:
            edges = scene.edges if args.surface == "default" else None
            psd = surface_psd(args.surface, lam_max, lam_min, edges=edges)
        else:
            psd = surface_psd(scene.surface, lam_max, lam_min, files=scene.files, edges=scene.edges)
        curves = theory_curves(psd.q, psd.C1D, rubber, float(pressure), v, T0=T0,
                               models=args.models,
                               qmin=psd.qmin, qmax=psd.qmax, flash=args.flash, adhesion=adhesion,
                               alpha=alpha, options=options)
        surf_info = {"source": psd.source, "lambda_max_mm": 2 * math.pi / psd.qmin,
                     "lambda_min_mm": 2 * math.pi / psd.qmax}
    return {
        "conditions": {"pressure_MPa": float(pressure), "T0_K": T0, "v_mm_s": [float(x) for x in v],
                       "flash_temperature": bool(args.flash)},
        "surface": surf_info,
        "notes": notes,
        "compound": {"name": comp_name, "nu": rubber.nu, "T_ref_K": rubber.T_ref},
        "adhesion": None if adhesion is None else {"tau0_MPa": adhesion.tau0, "c": adhesion.c,
                                                   "v0_mm_s": adhesion.v0, "alpha": alpha},
        "curves": [c.to_dict() for c in curves],
        "_curves": curves,
    }


def theory_args(scene: str | Path | Scene | SceneInputs | None = None,
                **options: Any) -> argparse.Namespace:
    """Arguments of ``rubberfriction theory`` as a namespace, for calling :func:`run_theory`
    from Python (e.g. the multiscale report): keyword names are the option names with ``_``.

    ``scene`` is a scene file, an already-loaded multiscale ``driver.multiscale.scene.Scene`` (read with
    :func:`scene_inputs`), a :class:`SceneInputs` or None."""
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    register(sub)
    by_path = scene is None or isinstance(scene, (str, Path))
    args = parser.parse_args(["theory"] + ([str(scene)] if by_path and scene is not None else []))
    if not by_path:
        args.scene = scene
    for key, val in options.items():
        if not hasattr(args, key):
            raise TheoryInputError(f"unknown theory option {key!r}")
        setattr(args, key, val)
    return args


def scene_theory_curves(scene: str | Path | Scene | SceneInputs | None = None,
                        **options: Any) -> tuple[list[TheoryCurve], dict]:
    """Theory curves for a scene (the multiscale report draws them beside the FE curve with
    :func:`rubberfriction.driver.theory.curves.add_to_axes`).  Returns the curves and the
    JSON-ready description (conditions, surface, compound, notes)."""
    result = run_theory(theory_args(scene, **options))
    curves = result.pop("_curves")
    return curves, result


def draw_beside_fe(ax_mu: Any, scene: str | Path | Scene | SceneInputs | None, *, v_fe: Any,
                   compound: str | None = None,
                   pressure: float | None = None, T0: float | None = None,
                   models: tuple[str, ...] = ("persson-1d", "persson-2d"),
                   ax_area: Any | None = None, n: int = 40) -> tuple[list[TheoryCurve], list[str]]:
    """Draw the theory curves of a scene on the multiscale report's mu(v) axes (and A/A0 axes).

    The curves span the FE speeds ``v_fe`` (mm/s) with a factor 3 margin on a log grid of ``n``
    speeds, for the FE's compound, pressure and temperature.  ``scene`` is anything
    :func:`theory_args` accepts (a file or the loaded ``Scene`` of the campaign).  A failure
    (e.g. a surface the theories cannot read) never breaks the report: it is returned as a note
    and nothing is drawn.  Returns (curves, notes).
    """
    from rubberfriction.driver.theory.curves import add_to_axes

    v = np.asarray(v_fe, dtype=float).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    if v.size == 0:
        return [], ["theory: no FE speeds > 0 to compare with"]
    grid = list(np.geomspace(v.min() / 3.0, v.max() * 3.0, n))
    try:
        curves, info = scene_theory_curves(scene, velocities=grid, compound=compound,
                                           pressure=pressure, temperature=T0, models=list(models))
    except (TheoryInputError, ValueError, OSError) as err:
        return [], [f"theory curves not drawn: {err}"]
    add_to_axes(curves, ax_mu, ax_area)
    return curves, list(info.get("notes", [])) + [n_ for c in curves for n_ in c.notes]


def _print_table(result: dict[str, Any]) -> None:
    curves: list[TheoryCurve] = result["_curves"]
    cond, surf, comp = result["conditions"], result["surface"], result["compound"]
    T = "reference" if cond["T0_K"] is None else f"{cond['T0_K']:g} K"
    print(f"analytical friction theories: p = {cond['pressure_MPa']:g} MPa, T0 = {T}, "
          f"compound {comp['name']} (nu = {comp['nu']:.4g}), flash temperature "
          f"{'on' if cond['flash_temperature'] else 'off'}")
    print(f"surface: {surf['source']}, wavelengths {surf['lambda_max_mm']:.4g} .. "
          f"{surf['lambda_min_mm']:.4g} mm")
    for note in result.get("notes", []):
        print(f"note: {note}")
    for c in curves:
        info = ", ".join(f"{k} = {v:.4g}" for k, v in c.extra.items() if isinstance(v, float))
        print(f"  {c.model}: {c.label}" + (f" ({info})" if info else ""))
        for note in c.notes:
            print(f"    note: {note}")
    head = ["v (mm/s)"]
    for c in curves:
        head.append(f"mu {c.model}")
        if c.area is not None:
            head.append("A/A0")
        if c.flash_dT is not None:
            head.append("dT (K)")
    print("  ".join(f"{h:>18}" for h in head))
    for i, vi in enumerate(curves[0].v):
        row = [f"{vi:18.5g}"]
        for c in curves:
            row.append(f"{c.mu[i]:18.5g}")
            if c.area is not None:
                row.append(f"{c.area[i]:18.5g}")
            if c.flash_dT is not None:
                row.append(f"{c.flash_dT[i]:18.4g}")
        print("  ".join(row))


def _write_csv(result: dict[str, Any], path: Path) -> None:
    curves: list[TheoryCurve] = result["_curves"]
    cols = {"v_mm_s": curves[0].v}
    for c in curves:
        cols[f"{c.model}_mu"] = c.mu
        cols[f"{c.model}_mu_hysteresis"] = c.mu_hysteresis
        if c.mu_adhesion is not None:
            cols[f"{c.model}_mu_adhesion"] = c.mu_adhesion
        if c.area is not None:
            cols[f"{c.model}_area_ratio"] = c.area
        if c.flash_dT is not None:
            cols[f"{c.model}_flash_dT_K"] = c.flash_dT
    data = np.column_stack(list(cols.values()))
    np.savetxt(path, data, delimiter=",", header=",".join(cols), comments="", fmt="%.10g")


def _run(args: argparse.Namespace) -> int:
    try:
        result = run_theory(args)
        if args.csv:
            _write_csv(result, Path(args.csv))
        if args.plot:
            cond = result["conditions"]
            plot_curves(result["_curves"], args.plot,
                        title=f"{result['surface']['source']} | {result['compound']['name']} | "
                              f"p = {cond['pressure_MPa']:g} MPa"
                              + ("" if cond["T0_K"] is None else f" | T0 = {cond['T0_K']:g} K"))
    except (TheoryInputError, ValueError, OSError) as err:
        print(f"rubberfriction theory: error: {err}", file=sys.stderr)
        return 2
    if args.json:
        out = {k: v for k, v in result.items() if not k.startswith("_")}
        print(json.dumps(out, indent=1))
    else:
        _print_table(result)
        for what, path in (("csv", args.csv), ("plot", args.plot)):
            if path:
                print(f"{what}: {path}")
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``theory`` to the ``rubberfriction`` command."""
    doc = __doc__ or ""
    p = subparsers.add_parser(
        "theory", help="mu(v) and contact area from the Persson / Klüppel-Heinrich theories",
        description=doc.split("\n\n")[0] + " Speeds mm/s, pressure MPa, temperature K.",
        epilog=doc[doc.find("Scene file (TOML)"):] if "Scene file (TOML)" in doc else None,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", nargs="?", help="scene TOML; keys read: [surface], [compound], "
                   "[conditions], [physics] adhesion, [adhesion] (schema below)")
    p.add_argument("--surface", help="profile file or 'default' (embedded default road)")
    p.add_argument("--compound", help=f"compound name or TOML file (default {DEFAULT_COMPOUND})")
    p.add_argument("--pressure", type=float, help="nominal pressure, MPa (default 0.3)")
    p.add_argument("--velocities", type=float, nargs="+", metavar="V", help="sliding speeds, mm/s")
    p.add_argument("--vmin", type=float,
                   help=f"log-spaced speeds from (mm/s, default {DEFAULT_VRANGE[0]:g})")
    p.add_argument("--vmax", type=float, help=f"... to (mm/s, default {DEFAULT_VRANGE[1]:g})")
    p.add_argument("--n", type=int, help=f"... number of speeds (default {DEFAULT_N})")
    p.add_argument("--temperature", type=float,
                   help="background temperature T0, K (default: WLF reference)")
    p.add_argument("--models", nargs="+", choices=MODELS, default=list(MODELS),
                   help="models to evaluate")
    p.add_argument("--lambda-max", type=float, help="longest wavelength included, mm")
    p.add_argument("--lambda-min", type=float,
                   help="shortest wavelength included (q1 = 2 pi/lambda_min), mm")
    p.add_argument("--gamma", type=float, default=0.5,
                   help="S(q) = gamma + (1-gamma) P^2 (default 0.5)")
    p.add_argument("--nu", type=float,
                   help="Poisson ratio (default: the compound's long-term value)")
    p.add_argument("--flash", action="store_true", help="flash temperature (Persson 2006)")
    p.add_argument("--adhesion", type=float, nargs=3, metavar=("TAU0", "C", "V0"),
                   help="bell law eq. (7.6): tau0 MPa, c, v0 mm/s")
    p.add_argument("--alpha", type=float, help="adhesion share alpha of eq. (7.3) (default 1)")
    p.add_argument("--plot", help="write mu(v) and A/A0(v) to this PNG")
    p.add_argument("--csv", help="write the curves to this CSV")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=_run)
