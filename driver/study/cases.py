"""The trend study's cases: settings and the scenes they run (thesis ch. 6.4, 6.5, 8.5.3).

Every campaign of the study is a scene written as TOML (:func:`scene_texts`), on the four-scale
road of ``driver/surfaces/four_scale.py`` (Hurst 0.8, thesis edges 20 / 3 / 0.3 / 0.04 /
0.003 mm) with its lowest scale stated by an explicit ``cutoff``: the study compares cases, and
a fixed cut-off keeps the same scales in every case (the slope rule would drop scales of the
rougher road).  The texts are saved into the study folder, so one case can be rerun alone with
``rubberfriction run <out>/scenes/<case>.toml``.

Conditions follow the thesis: p = 0.3 MPa, T0 = 20 degC (6.5.1); compounds c1..c6 of table 6.1
for the material rows, c3 on two roads (6.5.2) and on the polished road (6.5.3), m2 for the
sawtooth (6.4.1), m1 for the flash temperature (8.5.3, the hot-layer setup), the lowest scale at
3 MPa and 10 mm/s for the sample spread (6.4.2).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from typing import Any

from rubberfriction.driver.scenes import SceneError, load_scene, toml_value
from rubberfriction.driver.surfaces.four_scale import FOUR_SCALE_EDGES
from rubberfriction.driver.surfaces.multiscale import scale_names

#: the material compounds of thesis table 6.1
MATERIALS = ("c1", "c2", "c3", "c4", "c5", "c6")


@dataclass(frozen=True)
class TrendSettings:
    """What the trend study runs; :func:`quick_settings` is the ``--quick`` variant."""

    quick: bool = False
    # mm: the four-scale road kept to meso (two scales).  At 0.04 mm (micro1) the derived
    # compounds c1 and c3 fail their micro1 friction runs at 1 m/s (docs/trends.md)
    cutoff: float = 0.3
    seed: int = 1  # sample positions
    pressure: float = 0.3  # MPa (thesis 6.5.1)
    velocities: tuple[float, ...] = (100.0, 1000.0)  # mm/s: mu(v) with and without flash
    compare_velocity: float = 1000.0  # mm/s: material and surface rows (thesis fig. 6.19 b)
    pressure_samples: int = 1
    friction_samples: int = 3
    rough_scale: float = 1.25  # the rougher road: heights x this (6.5.2)
    polish_fraction: float = 0.1  # polished road: top fraction of each lowest-scale sample cut
    spread_samples: int = 30  # single-scale samples for S(1) / S(10) (6.4.2)
    spread_pressure: float = 3.0  # MPa (thesis 6.4.2)
    spread_velocity: float = 10.0  # mm/s (thesis 6.4.2)
    flash: bool = True  # run the hot-layer flash-temperature case (8.5.3)
    flash_compound: str = "m1"
    flash_rises: tuple[float, ...] = (0.0, 20.0, 40.0, 80.0)  # K: hot-layer T_S - T0
    # mm: the thermal macro block's slide (thesis 8.5.1's 25 mm; at 10 mm the 1 m/s contact
    # still warms by 5 K/mm, docs/trends.md)
    flash_slide: float = 25.0
    flash_road: str = "flat"  # or "macro": the block on the road's macro band (8.17 a)
    # mm: the flash case's lowest wavelength (None: ``cutoff``): the thesis' four scales (8.5.3)
    # (docs/trends.md, "The flash case, cut by cut")
    flash_cutoff: float | None = 0.003
    # the part of mu the cut cascade does not give (the scales below the cut-off, adhesion),
    # thesis 8.4.3's mu_const = 0.6: it sets the frictional heat, hence the flash temperature
    flash_mu_const: float = 0.6
    sawtooth_compound: str = "m2"
    sawtooth_pressure: float = 0.3  # MPa (thesis fig. 6.10)
    sawtooth_velocity: float = 500.0  # mm/s (thesis fig. 6.10)
    elements_per_wavelength: int = 6
    run_timeout: float = 600.0  # s per single-scale run

    def __post_init__(self) -> None:
        """The cut-offs lie on the four-scale road (its finest and coarsest kept edges)."""
        for name in ("cutoff", "flash_cutoff"):
            value = getattr(self, name)
            if value is None and name == "flash_cutoff":
                continue
            if not (isinstance(value, (int, float)) and EDGES[-1] <= value <= EDGES[1]):
                raise SceneError(f"{name} = {value!r} mm: expected a wavelength from "
                                 f"{EDGES[-1]:g} to {EDGES[1]:g} mm (the four-scale road's "
                                 "finest edge and the macro scale's short one)")

    def describe(self) -> str:
        """One line: road, cut-off and samples, as every table of the study states them."""
        cut = ("" if self.flash_cutoff in (None, self.cutoff) else
               f" cut at {self.flash_cutoff:g} mm")
        flash = (f", flash case{cut} on the {self.flash_road} road with mu_const "
                 f"{self.flash_mu_const:g}" if self.flash else
                 ", no flash case")
        return (f"four-scale road cut at {self.cutoff:g} mm, p = {self.pressure:g} MPa, "
                f"{self.pressure_samples} + {self.friction_samples} samples per scale{flash}"
                f"{' (quick)' if self.quick else ''}")

    @property
    def flash_cut(self) -> float:
        """The flash case's lowest wavelength, mm."""
        return self.cutoff if self.flash_cutoff is None else self.flash_cutoff

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def quick_settings() -> TrendSettings:
    """``--quick``: 1 + 2 samples, 20 spread samples, the flash case also cut at 0.3 mm with
    three hot-layer temperatures (up to +160 K, which that contact reaches at 1 m/s: no
    extension of the law) and a shorter thermal slide; every table says so."""
    return replace(TrendSettings(), quick=True, cutoff=0.3, flash_cutoff=None,
                   friction_samples=2, spread_samples=20, flash_rises=(0.0, 40.0, 160.0),
                   flash_slide=6.0)


#: the four-scale road's band edges (mm) and its scales' names, which a cut-off does not change
EDGES = FOUR_SCALE_EDGES
SCALES = tuple(scale_names(len(EDGES) - 1))


def _surface(s: TrendSettings, *, height_scale: float = 1.0, polish: float = 0.0,
             polish_scale: str = "", cutoff: float | None = None) -> str:
    cut = s.cutoff if cutoff is None else cutoff
    lines = ['source = "four_scale"', f"edges = {toml_value(list(EDGES))}",
             f"cutoff = {toml_value(cut)}", f"seed = {s.seed}"]
    if height_scale != 1.0:
        lines.append(f"height_scale = {toml_value(height_scale)}")
    if polish > 0.0:
        lines += [f"polish_fraction = {toml_value(polish)}",
                  f"polish_scales = {toml_value([polish_scale])}"]
    return "\n".join(lines)


def lowest_scale(s: TrendSettings, cutoff: float | None = None) -> str:
    """Name of the lowest scale a cut-off keeps (default the study's; the four-scale road's
    names)."""
    return SCALES[lowest_band(s.cutoff if cutoff is None else cutoff)]


def lowest_band(cutoff: float) -> int:
    """Index into ``SCALES`` of the lowest scale the cut-off (mm) keeps; its band spans
    ``EDGES[i]`` to ``max(EDGES[i + 1], cutoff)``."""
    kept = [i for i, short in enumerate(EDGES[1:]) if short >= cutoff * (1 - 1e-9)]
    if not kept:
        raise ValueError(f"cutoff {cutoff} mm keeps no scale of the four-scale road")
    return kept[-1]


def _scene(name: str, description: str, s: TrendSettings, surface: str, compounds: list[str],
           velocities: list[float], *, pressure_samples: int | None = None,
           friction_samples: int | None = None, thermal: str = "",
           cutoff: float | None = None) -> str:
    physics = "hysteresis = true\nadhesion = false\nthermal = " + ("true" if thermal else "false")
    text = f"""# {description}
# written by `rubberfriction study trends` ({s.describe()})
name = {toml_value(name)}
description = {toml_value(description)}
variant = "rough"

[surface]
{surface}

[samples]
pressure = {pressure_samples or s.pressure_samples}
friction = {friction_samples or s.friction_samples}

[conditions]
compounds = {toml_value(compounds)}
pressures = [{toml_value(s.pressure)}]
velocities = {toml_value([float(v) for v in velocities])}
T0 = 20.0
T0_unit = "degC"

[physics]
{physics}

[numerics]
elements_per_wavelength = {s.elements_per_wavelength}
grading = 1.3
step_per_element = 0.5
run_timeout = {toml_value(s.run_timeout)}
penalty_alpha = 10.0
max_slide_periods = 24
"""
    if lowest_scale(s, cutoff) == "micro2":
        # micro2 kept: the shipped four_scale scene's mesh there (its sharpest tip, docs/scales.md)
        n = load_scene("four_scale").numerics.for_scale("micro2").elements_per_wavelength
        text += f"\n[numerics.micro2]\nelements_per_wavelength = {n}\n"
    return text + (f"\n[thermal]\n{thermal}\n" if thermal else "")


def _hot_layer(s: TrendSettings) -> str:
    """The thesis' reduced flash-temperature setup (8.5.3): hot layer on the lower scales, the
    thermomechanical macro block adapting mu to its surface temperature."""
    return "\n".join([
        'mode = "hot-layer"', "divisions = 4", "partitions = 4", "partition_depth = 0.09",
        f"mu_const = {toml_value(s.flash_mu_const)}",
        f"hot_layer_rises = {toml_value([float(r) for r in s.flash_rises])}",
        "kappa = 0.8", "h_c = 1.6", 'road = "r1"', "block_length = 20.0", "block_height = 8.0",
        "edge_radius = 1.0", f"slide_distance = {toml_value(s.flash_slide)}",
        f"road_surface = {toml_value(s.flash_road)}",
        "h_contact = 0.25", "road_depth = 10.0", "road_ahead = 2.0", "road_behind = 20.0"])


def scene_texts(s: TrendSettings) -> dict[str, str]:
    """The study's campaigns by case name, as scene TOML texts (validated when read)."""
    low = lowest_scale(s)
    base = _surface(s)
    texts = {
        "materials": _scene("trend_materials", "compounds c1..c6 of thesis table 6.1 (6.5.1)", s,
                            base, list(MATERIALS), [s.compare_velocity]),
        "rough": _scene("trend_rough", f"c3 on the four-scale road with heights x "
                        f"{s.rough_scale:g} (the rougher surface, 6.5.2)", s,
                        _surface(s, height_scale=s.rough_scale), ["c3"], [s.compare_velocity]),
        "polished": _scene("trend_polished", f"c3 on the four-scale road, the top "
                           f"{100 * s.polish_fraction:g} % of each {low} sample truncated "
                           "(polishing, 6.5.3)", s,
                           _surface(s, polish=s.polish_fraction, polish_scale=low), ["c3"],
                           [s.compare_velocity]),
        "spread": _scene("trend_spread", f"{s.spread_samples} samples of {low} for the sample "
                         "spread (6.4.2)", s, base, ["c3"], [s.spread_velocity],
                         pressure_samples=1, friction_samples=1),
    }
    if s.flash:
        texts["flash"] = _scene("trend_flash", f"{s.flash_compound} with and without flash "
                                "temperature, hot-layer mode (8.5.3)", s,
                                _surface(s, cutoff=s.flash_cut),
                                [s.flash_compound], list(s.velocities), pressure_samples=1,
                                friction_samples=1, thermal=_hot_layer(s), cutoff=s.flash_cut)
    return texts
