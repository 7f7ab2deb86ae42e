"""Scenes: the user's description of a multiscale friction campaign (TOML), validated early.

This module reads a scene: every table but ``[thermal]`` (``thermal``, its loop modes in
``thermal_loop``), against the keys of ``schema``; :func:`parse_scene` composes one reader per
section.  The campaign code that runs a scene is in ``driver/multiscale``.

A scene says *what* to compute -- surface, scales, samples, compounds, pressures, velocities,
temperature, physics -- and *how finely* (numerical settings).  ``rubberfriction run SCENE``
runs it; ``rubberfriction run`` runs the embedded default scene (``driver/scenes/default.toml``).
Every key, its default and its meaning is in ``schema.SCHEMA`` (the one place defaults are
written down); ``rubberfriction run --schema`` prints it.

Validation fails early with a message that names the file, the key, the value and what is
expected; unknown keys are rejected with a did-you-mean suggestion.  ``[numerics.<scale>]``
tables (``[numerics.micro2]``, a scale's name) change numerical keys for the runs on that scale
only (:meth:`NumericsConfig.for_scale`): model each scale as finely as it needs.  Relative paths
in a scene (``surface.files``, compound files) are relative to the scene file; ``output`` is
relative to the current directory.

Variants (``variant``):

* ``"rough"`` -- rough road surfaces, thesis 6.3.2 (fig. 6.7, 6.8): band-pass scales (eq. 6.10,
  6.14), ``samples.pressure`` (k) frictionless samples per scale to pass the mean contact
  pressure down (eq. 6.11, 6.12), ``samples.friction`` (j) samples per scale to pass the
  coefficient of friction up (eq. 6.13).  Any number of scales.
* ``"separated"`` -- separated scales, thesis 6.2 (fig. 6.1): two scales, micro runs on a
  (p, v) grid, a smooth spline law mu(p, v) (eq. 6.6) fitted to them, the macro run with that
  law in the contact; optionally the single-scale reference on the full profile (fig. 6.4).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from importlib import resources
from pathlib import Path
from typing import Any, Sequence

import tomllib

from rubberfriction import validation as V
from rubberfriction.driver.scenes.schema import (
    SCENE_WIDE_NUMERICS,
    SCHEMA,
    SECTIONS,
    SceneError,
    check_value,
    section_values,
)
from rubberfriction.driver.scenes.thermal import ThermalSceneConfig, parse_thermal
from rubberfriction.driver.surfaces.cutoff import SLOPE_SLACK, CutoffReport, parse_cutoff
from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.multiscale import scale_names
from rubberfriction.driver.surfaces.roads import ROAD_SOURCES, resolve_road
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.forms.material_files import available, resolve_data_path

#: Shipped scenes (``driver/scenes/<name>.toml``); ``load_scene("two_sine")`` finds them by name.
SCENES_PACKAGE = "rubberfriction.driver.scenes"


@dataclass(frozen=True)
class SurfaceConfig:
    source: str
    files: tuple[Path, ...]
    edges: tuple[float, ...]
    names: tuple[str, ...]
    block_lengths: tuple[float, ...]
    top_fraction: float
    seed: int
    amplitudes: tuple[float, ...]
    wavelengths: tuple[float, ...]
    periods_per_block: int
    points_per_wavelength: int
    cutoff: str | float = "slope"
    max_slope: float = 1.3
    #: every height of the road times this (thesis 6.5.2); sines: the amplitudes
    height_scale: float = 1.0
    #: fraction of each polished sample's points the flat tops cover (thesis 6.5.3); 0: none
    polish_fraction: float = 0.0
    #: scales whose samples are polished; empty: every scale below the coarsest two
    polish_scales: tuple[str, ...] = ()
    #: edges as the scene states them; ``edges`` are those the cut-off rule keeps
    stated_edges: tuple[float, ...] = ()
    #: what the rule did, band by band (None for sines)
    cutoff_report: CutoffReport | None = field(default=None, compare=False, repr=False)
    #: the [surface] as the scene states it, before the rule (None: nothing was cut)
    stated: SurfaceConfig | None = field(default=None, compare=False, repr=False)

    @property
    def n_scales(self) -> int:
        return len(self.wavelengths) if self.source == "sines" else len(self.edges) - 1

    @property
    def polished(self) -> tuple[str, ...]:
        """The scales whose samples are polished: ``polish_scales``, or every scale below the
        coarsest two when it is empty; none when ``polish_fraction`` is 0."""
        if self.polish_fraction == 0.0:
            return ()
        return self.polish_scales or tuple(surface_scale_names(self)[2:])


@dataclass(frozen=True)
class SamplesConfig:
    pressure: int
    friction: int
    max_failed_fraction: float


@dataclass(frozen=True)
class ConditionsConfig:
    compounds: tuple[str, ...]  # as written in the scene
    compound_paths: tuple[str, ...]  # names or resolved file paths, for load_compound
    pressures: tuple[float, ...]
    velocities: tuple[float, ...]
    T0: float | None  # kelvin


@dataclass(frozen=True)
class PhysicsConfig:
    hysteresis: bool
    adhesion: bool
    thermal: bool


@dataclass(frozen=True)
class NumericsConfig:
    elements_per_wavelength: int
    grading: float
    window: str
    convergence_tol: float
    window_periods: int
    max_slide_periods: float
    pressure_slide_periods: float
    steady_state: bool
    period_extrapolation: bool
    shortcut: bool
    slide_periods: float
    window_start: float
    step_per_element: float
    compression_steps: int
    contact: str
    element: str
    newton: str
    newton_rtol: float
    max_cutbacks: int
    stabilisation: float
    min_jacobian: float
    penalty_alpha: float
    tangential_penalty: float
    master_points_per_wavelength: int
    run_timeout: float
    #: ``[numerics.<scale>]`` tables: (scale name, ((key, value), ...)) in scene order
    scales: tuple[tuple[str, tuple[tuple[str, Any], ...]], ...] = ()

    def for_scale(self, name: str) -> NumericsConfig:
        """The numerics of the runs on scale ``name``: the scene's, with that scale's
        ``[numerics.<name>]`` values in their place."""
        for scale, values in self.scales:
            if scale == name:
                return replace(self, scales=(), **dict(values))
        return replace(self, scales=())


@dataclass(frozen=True)
class SeparatedConfig:
    pressures: tuple[float, ...]
    pressure_factors: tuple[float, ...]
    velocities: tuple[float, ...]
    velocity_factors: tuple[float, ...]
    micro_window_start: float
    micro_slide_periods: float
    reference: bool
    spline_degree: int
    smoothing: float


@dataclass(frozen=True)
class AdhesionFitConfig:
    """``[adhesion] fit_from``: the measurement files per surface condition (one per compound,
    in the order of ``[conditions].compounds``), the approach, a given alpha (None: fitted)."""

    files: dict[str, tuple[Path, ...]]  # "dry" | "soap" | "water" -> files
    approach: str
    alpha: float | None
    extrapolate: bool


@dataclass(frozen=True)
class Scene:
    """A validated scene (plain typed data; see :data:`SCHEMA`)."""

    name: str
    description: str
    variant: str
    output: Path
    surface: SurfaceConfig
    samples: SamplesConfig
    conditions: ConditionsConfig
    physics: PhysicsConfig
    adhesion: BellLaw | None  # [adhesion] (eq. 7.6-7.8) when [physics].adhesion
    numerics: NumericsConfig
    separated: SeparatedConfig | None
    source: str  # file path or "embedded:<name>"
    text: str = field(repr=False, default="")  # the TOML as given (stored with the results)
    warnings: tuple[str, ...] = ()
    adhesion_fit: AdhesionFitConfig | None = None  # [adhesion] fit_from (thesis 7.3-7.5)
    thermal: ThermalSceneConfig | None = None  # [thermal] when [physics].thermal

    @property
    def n_scales(self) -> int:
        return self.surface.n_scales

    def with_output(self, output: str | Path) -> Scene:
        return replace(self, output=Path(output))

    def with_samples(self, pressure: int | None = None, friction: int | None = None) -> Scene:
        s = self.samples
        return replace(self, samples=replace(s, pressure=pressure or s.pressure,
                                             friction=friction or s.friction))


def _resolve_file(origin: str, base: Path | None, where: str, text: str) -> Path:
    p = Path(text).expanduser()
    if not p.is_absolute() and base is not None:
        p = base / p
    if not p.is_file():
        raise SceneError(f"{origin}: {where} = {text!r}: file not found (looked at {p})")
    return p


def _compound_path(origin: str, base: Path | None, i: int, text: str) -> str:
    where = f"[conditions].compounds[{i}]"
    if text.endswith(".toml") or "/" in text:
        return str(_resolve_file(origin, base, where, text))
    try:
        resolve_data_path(text)
    except ValueError:
        names = available("compound")
        raise SceneError(f"{origin}: {where} = {text!r}: no shipped compound of that name and no "
                         f"such file{V.suggest(text, names)} (shipped: "
                         f"{', '.join(names)})") from None
    return text


def _check_edges(origin: str, edges: tuple[float, ...]) -> None:
    where = f"{origin}: [surface].edges = {list(edges)}"
    if len(edges) < 2:
        raise SceneError(f"{where}: expected at least two wavelengths (lambda_max, lambda_min) in "
                         f"mm")
    if any(e <= 0 for e in edges):
        raise SceneError(f"{where}: expected positive wavelengths in mm")
    for i in range(len(edges) - 1):
        if edges[i + 1] >= edges[i]:
            raise SceneError(f"{where}: expected strictly descending wavelengths (lambda_max "
                             f"first), but edges[{i + 1}] = {edges[i + 1]:g} >= edges[{i}] = "
                             f"{edges[i]:g}")


def _adhesion_fit(origin: str, base: Path | None, given: dict, fit_from: dict, approach: str,
                  extrapolate: bool, conditions: ConditionsConfig) -> AdhesionFitConfig:
    """Validate ``[adhesion] fit_from`` (see :data:`SCHEMA`)."""
    where = f"{origin}: [adhesion].fit_from"
    fitted = sorted(k for k in ("tau0", "c", "v0") if k in given)
    if fitted:
        raise SceneError(f"{where}: {fitted} given as well: expected either fit_from (they are "
                         "fitted) or tau0, c, v0")
    unknown = sorted(set(fit_from) - {"dry", "soap", "water"})
    if unknown:
        raise SceneError(f"{where}: unknown surface condition(s) {unknown}"
                         f"{V.suggest(unknown[0], ['dry', 'soap', 'water'])}; expected dry, "
                         "soap, water")
    if "dry" not in fit_from:
        raise SceneError(f"{where}: expected a dry measurement (dry = \"file.csv\")")
    if approach == "original" and "soap" not in fit_from:
        raise SceneError(f"{where}: approach = \"original\" (dry - soap-water, eq. 7.3, 7.4): "
                         "expected a soap-water measurement (soap = \"file.csv\")")
    if len(conditions.pressures) != 1:
        raise SceneError(f"{where}: [conditions].pressures = {list(conditions.pressures)}: the "
                         "fit is at one pressure (mu_A = tau_A A_r / p); expected one pressure")
    n = len(conditions.compounds)
    files: dict[str, tuple[Path, ...]] = {}
    for cond, value in fit_from.items():
        names = [value] if isinstance(value, str) else value
        if not isinstance(names, list) or not all(isinstance(x, str) for x in names):
            raise SceneError(f"{where}.{cond} = {value!r}: expected a file name or a list of "
                             "file names")
        if len(names) != n:
            raise SceneError(f"{where}.{cond} = {value!r}: expected {n} file(s), one per compound "
                             f"of [conditions].compounds {list(conditions.compounds)}")
        files[cond] = tuple(_resolve_file(origin, base, f"[adhesion].fit_from.{cond}[{i}]", x)
                            for i, x in enumerate(names))
    alpha = float(given["alpha"]) if "alpha" in given else None
    return AdhesionFitConfig(files, approach, alpha, extrapolate)


def parse_scene(text: str, origin: str = "<scene>", base: Path | None = None) -> Scene:
    """Validate a scene given as TOML text; ``base`` is the folder relative paths start from.

    One helper per section, called in the order the checks have always run (the first error a
    scene has is the one reported)."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError(f"{origin}: not valid TOML: {err}") from None
    top = section_values(origin, doc, "")
    doc, scale_tables = _scale_numerics_tables(doc)
    vals = {s: section_values(origin, doc, s) for s in SECTIONS}
    warnings: list[str] = []
    surface, stated_names = _parse_surface(origin, base, doc, vals["surface"], top["name"],
                                           warnings)
    conditions = _parse_conditions(origin, base, vals["conditions"])
    physics, thermal = _parse_physics(origin, doc, vals, warnings)
    adhesion, adhesion_fit = _parse_adhesion(origin, base, doc, vals["adhesion"], physics,
                                             conditions, warnings)
    # the scale count the separated variant checks is the stated one (before any cut-off)
    separated = _parse_separated(origin, doc, top["variant"], vals["separated"],
                                 len(stated_names), physics, warnings)
    numerics = _parse_numerics(origin, vals["numerics"], scale_tables, surface, stated_names,
                               warnings)
    name = top["name"]
    output = Path(top["output"].replace("{name}", name))
    return Scene(name=name, description=top["description"], variant=top["variant"], output=output,
                 surface=surface, samples=SamplesConfig(**vals["samples"]), conditions=conditions,
                 physics=physics, adhesion=adhesion, numerics=numerics,
                 separated=separated, source=origin, text=text, warnings=tuple(warnings),
                 adhesion_fit=adhesion_fit, thermal=thermal)


def _check_sines(origin: str, s: dict[str, Any], given: dict) -> None:
    """[surface] of source = "sines": one amplitude per descending wavelength, edges around
    them (or none: ``s["edges"]`` becomes ``()``)."""
    amps, lams = s["amplitudes"], s["wavelengths"]
    if not lams:
        raise SceneError(f"{origin}: [surface].wavelengths = []: source = \"sines\" needs one "
                         f"wavelength "
                         "(mm) per scale")
    if len(amps) != len(lams):
        raise SceneError(f"{origin}: [surface].amplitudes = {list(amps)}: expected one "
                         f"amplitude per wavelength ({len(lams)} wavelengths given)")
    if any(v <= 0 for v in lams) or any(a < 0 for a in amps):
        raise SceneError(f"{origin}: [surface].wavelengths/amplitudes: expected wavelengths "
                         "> 0 and "
                         "amplitudes >= 0 (mm)")
    if any(lams[i + 1] >= lams[i] for i in range(len(lams) - 1)):
        raise SceneError(f"{origin}: [surface].wavelengths = {list(lams)}: expected strictly "
                         "descending wavelengths (macro scale first)")
    if "edges" not in given:
        s["edges"] = ()
        return
    _check_edges(origin, s["edges"])
    if len(s["edges"]) != len(lams) + 1:
        raise SceneError(f"{origin}: [surface].edges = {list(s['edges'])}: {len(lams)} "
                         f"waves need {len(lams) + 1} edges (or omit edges)")
    for i, lam in enumerate(lams):
        if not s["edges"][i + 1] < lam <= s["edges"][i]:
            raise SceneError(f"{origin}: [surface].edges = {list(s['edges'])}: wavelength "
                             f"{lam:g} mm of scale {i} is outside its band "
                             f"{s['edges'][i]:g}-{s['edges'][i + 1]:g} mm")


def _check_surface_source(origin: str, base: Path | None, s: dict[str, Any], given: dict,
                          warnings: list[str]) -> None:
    """The [surface] keys that belong to one source only (sines: amplitudes and wavelengths;
    files: the profile files, resolved in place against ``base``)."""
    if s["source"] == "sines":
        _check_sines(origin, s, given)
    else:
        _check_edges(origin, s["edges"])
        for k in ("amplitudes", "wavelengths"):
            if k in given:
                raise SceneError(f"{origin}: [surface].{k}: only for source = \"sines\" (source is "
                                 f"{s['source']!r})")
    if s["source"] == "files":
        if not s["files"]:
            raise SceneError(f"{origin}: [surface].files = []: source = \"files\" needs at least "
                             f"one profile file")
        s["files"] = tuple(_resolve_file(origin, base, f"[surface].files[{i}]", f) for i,
                           f in enumerate(s["files"]))
    elif s["files"]:
        raise SceneError(f"{origin}: [surface].files: only for source = \"files\" (source is "
                         f"{s['source']!r})")
    if s["source"] == "sines" and "cutoff" in given:
        warnings.append("[surface].cutoff is ignored: source = \"sines\" has no spectrum to cut")


def _parse_surface(origin: str, base: Path | None, doc: dict, s: dict[str, Any], name: str,
                   warnings: list[str]) -> tuple[SurfaceConfig, list[str]]:
    """[surface]: the surface (cut by its rule for a road source) and the scale names it states
    before the cut (a [numerics.<scale>] table of a dropped scale is then only a warning)."""
    _check_surface_source(origin, base, s, doc.get("surface", {}), warnings)
    surface = SurfaceConfig(**s)
    n = surface.n_scales
    for k in ("names", "block_lengths"):
        if surface.__dict__[k] and len(surface.__dict__[k]) != n:
            raise SceneError(f"{origin}: [surface].{k} = {list(surface.__dict__[k])}: expected {n} "
                             f"entries, one per scale (the edges give {n} scales)")
    if any(b <= 0 for b in surface.block_lengths):
        raise SceneError(f"{origin}: [surface].block_lengths = {list(surface.block_lengths)}: "
                         f"expected "
                         "positive lengths in mm")
    stated_names = surface_scale_names(surface)
    if surface.source in ROAD_SOURCES:
        surface = _cut(origin, surface, name=name)
        warnings.extend(_steep_band_warnings(surface.cutoff_report))
    _check_road_changes(origin, surface, stated_names, warnings)
    return surface, stated_names


def _check_road_changes(origin: str, surface: SurfaceConfig, stated_names: Sequence[str],
                        warnings: list[str]) -> None:
    """``height_scale`` and the polish keys: the factor and the fraction in range, the polished
    scales among those the cut-off keeps."""
    if not surface.height_scale > 0:
        raise SceneError(f"{origin}: [surface].height_scale = {surface.height_scale!r}: expected "
                         "a factor > 0")
    f = surface.polish_fraction
    if not 0.0 <= f < 1.0:
        raise SceneError(f"{origin}: [surface].polish_fraction = {f!r}: expected a fraction "
                         "0 <= f < 1")
    names = surface_scale_names(surface)
    for i, nm in enumerate(surface.polish_scales):
        if nm in names:
            continue
        why = (f"the cut-off rule ({_cutoff_text(surface)}) dropped scale {nm}"
               if nm in stated_names else f"no scale of that name{V.suggest(nm, names)}")
        raise SceneError(f"{origin}: [surface].polish_scales[{i}] = {nm!r}: {why}; expected "
                         f"names of the scene's scales ({', '.join(names)})")
    if len(set(surface.polish_scales)) != len(surface.polish_scales):
        raise SceneError(f"{origin}: [surface].polish_scales = {list(surface.polish_scales)}: "
                         "expected each scale once")
    if f == 0.0 and surface.polish_scales:
        warnings.append("[surface].polish_scales is ignored: polish_fraction = 0")
    elif f > 0.0 and not surface.polished:
        warnings.append(f"[surface].polish_fraction = {f:g} polishes no scale: the scene has "
                        f"{len(names)} scale(s) ({', '.join(names)}) and an empty polish_scales "
                        "means those below the coarsest two; name the scales in polish_scales")


def _parse_conditions(origin: str, base: Path | None, c: dict[str, Any]) -> ConditionsConfig:
    """[conditions]: compound files resolved, T0 in kelvin (given in degC when it says so)."""
    paths = tuple(_compound_path(origin, base, i, t) for i, t in enumerate(c["compounds"]))
    T0 = c["T0"]
    if T0 is not None and c["T0_unit"] == "degC":
        T0 = T0 + 273.15
    if T0 is not None and T0 <= 0:
        raise SceneError(f"{origin}: [conditions].T0 = {c['T0']!r} {c['T0_unit']}: expected a "
                         f"temperature "
                         "above absolute zero")
    return ConditionsConfig(c["compounds"], paths, c["pressures"], c["velocities"], T0)


def _parse_physics(origin: str, doc: dict, vals: dict[str, dict], warnings: list[str]
                   ) -> tuple[PhysicsConfig, ThermalSceneConfig | None]:
    """[physics] and, when it asks for the thermal macro scale, [thermal]."""
    physics = PhysicsConfig(**vals["physics"])
    thermal = parse_thermal(origin, doc, vals["thermal"]) if physics.thermal else None
    if not physics.thermal and "thermal" in doc:
        warnings.append("[thermal] is ignored: [physics].thermal = false")
    if not physics.hysteresis and not physics.adhesion:
        raise SceneError(f"{origin}: [physics]: hysteresis = false and adhesion = false leave "
                         f"nothing to "
                         "compute; expected at least one of them true")
    return physics, thermal


def _parse_adhesion(origin: str, base: Path | None, doc: dict, a: dict[str, Any],
                    physics: PhysicsConfig, conditions: ConditionsConfig, warnings: list[str]
                    ) -> tuple[BellLaw | None, AdhesionFitConfig | None]:
    """[adhesion]: a given bell law (eq. 7.6-7.8), or the measurements to fit it from."""
    if not physics.adhesion:
        if "adhesion" in doc:
            warnings.append("[adhesion] is ignored: [physics].adhesion = false")
        return None, None
    if "adhesion" not in doc:
        raise SceneError(f"{origin}: [physics].adhesion = true: expected an [adhesion] table "
                         f"with tau0 "
                         "(MPa), c, v0 (mm/s) and alpha (eq. 7.6-7.8)")
    a = dict(a)
    fit_from, approach = a.pop("fit_from"), a.pop("approach")
    extrapolate = a.pop("extrapolate")
    if fit_from:
        return None, _adhesion_fit(origin, base, doc["adhesion"], fit_from, approach,
                                   extrapolate, conditions)
    for k in ("approach", "extrapolate"):
        if k in doc["adhesion"]:
            warnings.append(f"[adhesion].{k} is ignored without fit_from")
    return BellLaw(**a), None


def _parse_separated(origin: str, doc: dict, variant: str, t: dict[str, Any], n: int,
                     physics: PhysicsConfig, warnings: list[str]) -> SeparatedConfig | None:
    """[separated] of variant = "separated": two scales, a (p, v) grid of at least 2 x 2."""
    if variant != "separated":
        if "separated" in doc:
            warnings.append("[separated] is ignored: variant = \"rough\"")
        return None
    if n != 2:
        raise SceneError(f"{origin}: variant = \"separated\": expected exactly two scales "
                         f"(macro, micro), "
                         f"the surface gives {n}")
    if physics.adhesion:
        raise SceneError(f"{origin}: variant = \"separated\" with [physics].adhesion = true: "
                         f"adhesion is "
                         "coupled in the rough-surface variant only (thesis 7.3); expected "
                         "variant = \"rough\"")
    separated = SeparatedConfig(**t)
    if not separated.pressures and not separated.pressure_factors:
        raise SceneError(f"{origin}: [separated]: expected pressures or pressure_factors")
    if not separated.velocities and not separated.velocity_factors:
        raise SceneError(f"{origin}: [separated]: expected velocities or velocity_factors")
    for axis, plural in (("pressure", "pressures"), ("velocity", "velocities")):
        grid = getattr(separated, plural) or getattr(separated, axis + "_factors")
        if len(set(grid)) != len(grid) or len(grid) < 2:
            raise SceneError(f"{origin}: [separated].{plural}/{axis}_factors = {list(grid)}: "
                             f"expected at "
                             "least two distinct values (a spline needs two points per axis)")
    return separated


def _parse_numerics(origin: str, t: dict[str, Any], scale_tables: dict[str, Any],
                    surface: SurfaceConfig, stated_names: Sequence[str], warnings: list[str]
                    ) -> NumericsConfig:
    """[numerics] and its [numerics.<scale>] tables, with the element/solver check per scale."""
    numerics = NumericsConfig(**t, scales=_scale_numerics(origin, scale_tables, surface,
                                                          stated_names, warnings))
    for scale in [None, *surface_scale_names(surface)]:
        num = numerics if scale is None else numerics.for_scale(scale)
        if num.newton != "line-search" and num.element == "Q1P0s":
            where = "[numerics]" if scale is None else f"[numerics.{scale}] with [numerics]"
            raise SceneError(f"{origin}: {where}: newton = \"{num.newton}\" with element = "
                             "\"Q1P0s\": the trust region eliminates the cell pressures, which "
                             "the pressure-jump term couples; expected element Q1P0 or Q1")
    return numerics


def _scale_numerics_tables(doc: dict) -> tuple[dict, dict[str, Any]]:
    """``doc`` without the subtables of [numerics] (``[numerics.micro2]``), and those."""
    num = doc.get("numerics")
    if not isinstance(num, dict):
        return doc, {}
    tables = {k: v for k, v in num.items() if isinstance(v, dict)}
    if not tables:
        return doc, {}
    return {**doc, "numerics": {k: v for k, v in num.items() if k not in tables}}, tables


def surface_scale_names(surface: SurfaceConfig) -> list[str]:
    """The scales' names as the campaign labels them: [surface].names or the thesis names."""
    return list(surface.names) or scale_names(surface.n_scales)


def _cut(origin: str, surface: SurfaceConfig, name: str) -> SurfaceConfig:
    """The surface with the edges, names and block lengths its cut-off rule keeps."""
    names = surface_scale_names(surface)
    try:
        rule = parse_cutoff(surface.cutoff, surface.max_slope)
        road, report = resolve_road(surface.source, surface.files, surface.edges, names,
                                    surface.block_lengths, rule, title=name,
                                    height_scale=surface.height_scale)
    except SurfaceError as err:
        raise SceneError(f"{origin}: [surface] (source = {surface.source!r}, edges = "
                         f"{list(surface.edges)}, {_cutoff_text(surface)}): {err}") from None
    n = len(road.scales)
    return replace(surface, edges=tuple(report.edges), names=tuple(names[:n]),
                   block_lengths=tuple(surface.block_lengths[:n]),
                   stated_edges=tuple(surface.edges), cutoff_report=report, stated=surface)


def with_surface(scene: Scene, **changes: Any) -> Scene:
    """The scene with ``[surface]`` keys changed (``edges`` as stated, ``cutoff``, ``max_slope``,
    ``height_scale``, ``polish_fraction``, ``polish_scales`` (a tuple), ...) and its cut-off
    rule applied again (for studies of the lowest scale and of road trends)."""
    base = scene.surface.stated or scene.surface
    bad = set(changes) - {f.name for f in fields(base)}
    if bad:
        raise SceneError(f"with_surface: unknown [surface] key(s) {sorted(bad)}")
    surface = replace(base, **changes)
    if surface.source in ROAD_SOURCES:
        surface = _cut(scene.source, surface, name=scene.name)
    _check_road_changes(scene.source, surface, surface_scale_names(base), [])
    return replace(scene, surface=surface)


def _cutoff_text(surface: SurfaceConfig) -> str:
    c = surface.cutoff
    return f"cutoff = {c!r}" if isinstance(c, str) else f"cutoff = {c:g} mm"


def _steep_band_warnings(report: CutoffReport | None) -> list[str]:
    """A stated cut-off that keeps generated bands beyond the slope limit: say so up front."""
    if report is None or report.rule.kind == "slope":
        return []
    limit = report.rule.max_slope
    steep = [r for r in report.rows if r.status != "dropped" and r.kind == "generated"
             and r.cumulative_slope > limit * (1 + SLOPE_SLACK)]
    return [f"[surface] {report.rule}: the generated band {r.name} ({r.band[0]:g}-"
            f"{r.short_edge:.4g} mm, rms slope {r.rms_slope:.3g}) takes the cumulative 2D rms "
            f"slope to {r.cumulative_slope:.3g} > max_slope {limit:g}: a self-affine continuation "
            "this steep sharpens its tips below any contact element, so its runs may not converge "
            "(the slope rule, cutoff = \"slope\", would stop before it)" for r in steep]


def _scale_numerics(origin: str, tables: dict[str, Any], surface: SurfaceConfig,
                    stated: Sequence[str] = (), warnings: list[str] | None = None
                    ) -> tuple[tuple[str, tuple[tuple[str, Any], ...]], ...]:
    """Validated ``[numerics.<scale>]`` tables: a scale of the scene, [numerics] keys but the
    scene-wide ones, each value checked like the scene's.  A table of a scale the cut-off rule
    dropped (one of ``stated``) is left out with a warning."""
    names = surface_scale_names(surface)
    keys = SCHEMA["numerics"]
    out = []
    for scale, table in tables.items():
        if scale not in names and scale in stated:
            if warnings is not None:
                warnings.append(f"[numerics.{scale}] is ignored: the cut-off rule dropped scale "
                                f"{scale}")
            continue
        if scale not in names:
            raise SceneError(f"{origin}: unknown table [numerics.{scale}]"
                             f"{V.suggest(scale, names)}: a per-scale table is named after a "
                             f"scale of the scene ({', '.join(names)})")
        values = []
        for k, v in table.items():
            if k in SCENE_WIDE_NUMERICS:
                raise SceneError(f"{origin}: [numerics.{scale}].{k}: {k} is scene-wide; set it in "
                                 "[numerics]")
            if k not in keys:
                raise SceneError(f"{origin}: unknown key [numerics.{scale}].{k}"
                                 f"{V.suggest(k, list(keys))} (allowed: the keys of [numerics] but "
                                 f"{', '.join(SCENE_WIDE_NUMERICS)})")
            values.append((k, check_value(origin, f"numerics.{scale}", k, keys[k], v)))
        out.append((scale, tuple(values)))
    return tuple(out)


def shipped_scenes() -> list[str]:
    """Names of the scenes shipped in ``driver/scenes``."""
    files = resources.files(SCENES_PACKAGE).iterdir()
    return sorted(p.name[:-5] for p in files if p.name.endswith(".toml"))


def load_scene(path: str | Path | None = None) -> Scene:
    """Load and validate a scene: a file path, a shipped scene name, or None for the default."""
    if path is None:
        path = "default"
    p = Path(path).expanduser()
    if p.is_file():
        return parse_scene(p.read_text(), str(p), p.resolve().parent)
    name = str(path)
    if "/" not in name and not name.endswith(".toml") and name in shipped_scenes():
        folder = resources.files(SCENES_PACKAGE)
        text = folder.joinpath(f"{name}.toml").read_text()
        # relative paths of a shipped scene (e.g. [adhesion] fit_from) are its package folder's
        return parse_scene(text, f"embedded:{name}", Path(str(folder)))
    hint = V.suggest(name, shipped_scenes())
    raise SceneError(f"scene {name!r}: no such file and no shipped scene of that name{hint} "
                     f"(shipped: {', '.join(shipped_scenes())})")


def override(scene: Scene, **changes: Any) -> Scene:
    """A copy of the scene with top-level or section fields replaced (for tests and studies).

    ``override(scene, samples={"friction": 10}, conditions={"velocities": (100.0,)})``.
    """
    kw: dict[str, Any] = {}
    for name, val in changes.items():
        cur = getattr(scene, name)
        if isinstance(val, dict):
            allowed = {f.name for f in fields(cur)}
            bad = set(val) - allowed
            if bad:
                raise SceneError(f"override: unknown key(s) {sorted(bad)} for {name}")
            kw[name] = replace(cur, **val)
        else:
            kw[name] = val
    return replace(scene, **kw)
