"""``rubberfriction theory [SCENE]``: mu(v) and A/A0(v) from the analytical theories.

Persson (line roughness = plane strain, and isotropic eq. 2.10), Klüppel-Heinrich (eq. 2.9) and,
with a bell law, the adhesion term (eqs. 2.11, 7.6, 7.7), all fed with the same surface PSD and
compound as the FE.  Examples::

    rubberfriction theory --surface default --compound tread_default --pressure 0.3 \\
        --vmin 1e-3 --vmax 1e4 --n 50 --temperature 293.15 --plot mu.png --csv mu.csv
    rubberfriction theory scene.toml --flash --json

Units: speeds mm/s, pressure MPa, temperature K, wavelengths mm.

Scene file (TOML): only these keys are read, every other key or table is ignored, so the
multiscale driver's scene files can be passed as they are::

    [surface]
    profile = "road.dat"     # or file/path; "default" = the embedded default road; relative to the scene
    lambda_max = 20.0        # optional analysis range, mm
    lambda_min = 0.003
    [compound]
    name = "tread_default"   # or file/path: a compound TOML (forms/data format)
    [conditions]
    p = 0.3                  # nominal pressure, MPa (also: pressure)
    v = [1.0, 10.0, 100.0]   # sliding speeds, mm/s (also: velocities, velocity)
    T0 = 293.15              # background temperature, K (also: T; T0_C in degC)
    [adhesion]               # optional bell law, eq. (7.6)
    tau0 = 3.0               # MPa
    c = 0.18
    v0 = 20.0                # mm/s
    alpha = 1.0              # share of eq. (7.3)

Command-line options override the scene.  Surface: a profile file is read with
``driver.surfaces.load_profile`` (cleaned), its PSD is ``psd_1d`` (Hann window); the default
range is wavelengths from a quarter of the record length down to the Nyquist wavelength.
``default`` is the four-scale default road (CAPTIF + generated fine extension): the PSD of each
band profile within its band, 20 mm down to 0.003 mm.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.theory.curves import MODELS, TheoryCurve, plot_curves, theory_curves
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.persson import PerssonOptions
from rubberfriction.driver.theory.rubber import Rubber, rubber_from_compound

DEFAULT_COMPOUND = "tread_default"
DEFAULT_N = 50
DEFAULT_VRANGE = (1e-3, 1e4)   # mm/s


@dataclass
class SceneInputs:
    """The keys of a scene file that the theories need (see module docstring)."""

    surface: str | None = None
    lambda_max: float | None = None
    lambda_min: float | None = None
    compound: str | None = None
    pressure: float | None = None
    velocities: list[float] | None = None
    T0: float | None = None
    adhesion: dict[str, float] = field(default_factory=dict)


def _pick(table: dict[str, Any], keys: tuple[str, ...], where: str) -> Any:
    found = [k for k in keys if k in table]
    if len(found) > 1:
        raise TheoryInputError(f"{where}: give only one of {found}")
    return table[found[0]] if found else None


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TheoryInputError(f"{where} = {value!r}: expected a number")
    return float(value)


def read_scene(path: str | Path) -> SceneInputs:
    """Read the minimal theory schema from a scene TOML (other keys are tolerated)."""
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
    if isinstance(surf, dict):
        src = _pick(surf, ("profile", "file", "path"), f"{path} [surface]")
        if src is not None:
            src = str(src)
            out.surface = src if src == "default" else str((base / src) if not Path(src).is_absolute() else src)
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
            cand = base / name
            out.compound = str(cand) if (name.endswith(".toml") and not Path(name).is_absolute()) else name
    cond = doc.get("conditions", {})
    if isinstance(cond, dict):
        p = _pick(cond, ("p", "pressure"), f"{path} [conditions]")
        if p is not None:
            out.pressure = _number(p, f"{path} [conditions].p")
        v = _pick(cond, ("v", "velocities", "velocity"), f"{path} [conditions]")
        if v is not None:
            vals = v if isinstance(v, list) else [v]
            out.velocities = [_number(x, f"{path} [conditions].v") for x in vals]
        T = _pick(cond, ("T0", "T", "temperature"), f"{path} [conditions]")
        if T is not None:
            out.T0 = _number(T, f"{path} [conditions].T0")
        if "T0_C" in cond:
            if out.T0 is not None:
                raise TheoryInputError(f"{path} [conditions]: give T0 (K) or T0_C (degC), not both")
            out.T0 = _number(cond["T0_C"], f"{path} [conditions].T0_C") + 273.15
    adh = doc.get("adhesion", {})
    if isinstance(adh, dict):
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


def surface_psd(surface: str, lambda_max: float | None = None, lambda_min: float | None = None) -> SurfacePSD:
    """Profile PSD (Persson convention) of a profile file or of the default road."""
    from rubberfriction.driver.surfaces import default_road, load_profile, psd_1d

    if surface == "default":
        road = default_road()
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
        q, C = q[keep], C[keep]
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
        raise TheoryInputError(f"wavelength range {lam_hi:g}..{lam_lo:g} mm: expected lambda_max > lambda_min > 0")
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


def _velocities(args: argparse.Namespace, scene: SceneInputs) -> np.ndarray:
    if args.velocities:
        return np.asarray(args.velocities, dtype=float)
    if args.vmin is not None or args.vmax is not None or args.n is not None:
        lo = args.vmin if args.vmin is not None else DEFAULT_VRANGE[0]
        hi = args.vmax if args.vmax is not None else DEFAULT_VRANGE[1]
        n = args.n if args.n is not None else DEFAULT_N
        if not (lo > 0 and hi > lo and n >= 1):
            raise TheoryInputError(f"speed range --vmin {lo} --vmax {hi} --n {n}: expected 0 < vmin < vmax, n >= 1")
        return np.geomspace(lo, hi, int(n))
    if scene.velocities:
        return np.asarray(scene.velocities, dtype=float)
    return np.geomspace(*DEFAULT_VRANGE, DEFAULT_N)


def run_theory(args: argparse.Namespace) -> dict[str, Any]:
    """Evaluate the theories for parsed arguments; returns the JSON-ready result."""
    scene = read_scene(args.scene) if args.scene else SceneInputs()
    surface = args.surface or scene.surface or "default"
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
    psd = surface_psd(surface, lam_max, lam_min)
    curves = theory_curves(psd.q, psd.C1D, rubber, float(pressure), v, T0=T0, models=args.models,
                           qmin=psd.qmin, qmax=psd.qmax, flash=args.flash, adhesion=adhesion,
                           alpha=alpha, options=PerssonOptions(gamma=args.gamma))
    return {
        "conditions": {"pressure_MPa": float(pressure), "T0_K": T0, "v_mm_s": [float(x) for x in v],
                       "flash_temperature": bool(args.flash)},
        "surface": {"source": psd.source, "lambda_max_mm": 2 * math.pi / psd.qmin,
                    "lambda_min_mm": 2 * math.pi / psd.qmax},
        "compound": {"name": comp_name, "nu": rubber.nu, "T_ref_K": rubber.T_ref},
        "adhesion": None if adhesion is None else {"tau0_MPa": adhesion.tau0, "c": adhesion.c,
                                                   "v0_mm_s": adhesion.v0, "alpha": alpha},
        "curves": [c.to_dict() for c in curves],
        "_curves": curves,
    }


def _print_table(result: dict[str, Any]) -> None:
    curves: list[TheoryCurve] = result["_curves"]
    cond, surf, comp = result["conditions"], result["surface"], result["compound"]
    T = "reference" if cond["T0_K"] is None else f"{cond['T0_K']:g} K"
    print(f"analytical friction theories: p = {cond['pressure_MPa']:g} MPa, T0 = {T}, "
          f"compound {comp['name']} (nu = {comp['nu']:.4g}), flash temperature "
          f"{'on' if cond['flash_temperature'] else 'off'}")
    print(f"surface: {surf['source']}, wavelengths {surf['lambda_max_mm']:.4g} .. {surf['lambda_min_mm']:.4g} mm")
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
    p = subparsers.add_parser(
        "theory", help="mu(v) and contact area from the Persson / Klüppel-Heinrich theories",
        description=__doc__.split("\n\n")[0] + " Speeds mm/s, pressure MPa, temperature K.",
    )
    p.add_argument("scene", nargs="?", help="scene TOML; keys read: [surface], [compound], "
                   "[conditions] p, v, T0, optional [adhesion] (see module docstring)")
    p.add_argument("--surface", help="profile file or 'default' (embedded default road)")
    p.add_argument("--compound", help=f"compound name or TOML file (default {DEFAULT_COMPOUND})")
    p.add_argument("--pressure", type=float, help="nominal pressure, MPa (default 0.3)")
    p.add_argument("--velocities", type=float, nargs="+", metavar="V", help="sliding speeds, mm/s")
    p.add_argument("--vmin", type=float, help=f"log-spaced speeds from (mm/s, default {DEFAULT_VRANGE[0]:g})")
    p.add_argument("--vmax", type=float, help=f"... to (mm/s, default {DEFAULT_VRANGE[1]:g})")
    p.add_argument("--n", type=int, help=f"... number of speeds (default {DEFAULT_N})")
    p.add_argument("--temperature", type=float, help="background temperature T0, K (default: WLF reference)")
    p.add_argument("--models", nargs="+", choices=MODELS, default=list(MODELS), help="models to evaluate")
    p.add_argument("--lambda-max", type=float, help="longest wavelength included, mm")
    p.add_argument("--lambda-min", type=float, help="shortest wavelength included (q1 = 2 pi/lambda_min), mm")
    p.add_argument("--gamma", type=float, default=0.5, help="S(q) = gamma + (1-gamma) P^2 (default 0.5)")
    p.add_argument("--nu", type=float, help="Poisson ratio (default: the compound's long-term value)")
    p.add_argument("--flash", action="store_true", help="flash temperature (Persson 2006)")
    p.add_argument("--adhesion", type=float, nargs=3, metavar=("TAU0", "C", "V0"),
                   help="bell law eq. (7.6): tau0 MPa, c, v0 mm/s")
    p.add_argument("--alpha", type=float, help="adhesion share alpha of eq. (7.3) (default 1)")
    p.add_argument("--plot", help="write mu(v) and A/A0(v) to this PNG")
    p.add_argument("--csv", help="write the curves to this CSV")
    p.add_argument("--json", action="store_true", help="print JSON instead of a table")
    p.set_defaults(func=_run)
