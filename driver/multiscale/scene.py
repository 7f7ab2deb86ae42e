"""Scenes: the user's description of a multiscale friction campaign (TOML), validated early.

A scene says *what* to compute -- surface, scales, samples, compounds, pressures, velocities,
temperature, physics -- and *how finely* (numerical settings).  ``rubberfriction run SCENE``
runs it; ``rubberfriction run`` runs the embedded default scene (``driver/scenes/default.toml``).
Every key, its default and its meaning is in :data:`SCHEMA` below (the one place defaults are
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
from rubberfriction.driver.multiscale.roads import ROAD_SOURCES, resolve_road
from rubberfriction.driver.surfaces.cutoff import SLOPE_SLACK, CutoffReport, parse_cutoff
from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.multiscale import scale_names
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.forms.material_files import available, resolve_data_path

#: Shipped scenes (``driver/scenes/<name>.toml``); ``load_scene("two_sine")`` finds them by name.
SCENES_PACKAGE = "rubberfriction.driver.scenes"


class SceneError(V.InputError):
    """A scene that cannot be run; the message names the key, the value and what is expected."""


# ----------------------------------------------------------------------------------------------
# the schema: one place for keys, types, defaults and meaning
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Key:
    """One scene key: its type, default, admissible values and meaning."""

    kind: str  # "str" "int" "float" "bool" "floats" "strs" "ints" "opt_float"
    default: Any
    doc: str
    choices: tuple = ()
    minimum: float | None = None  # value >= minimum
    above: float | None = None  # value > above
    maximum: float | None = None  # value <= maximum
    nonempty: bool = False
    unit: str = ""  # of a number or its list elements, "1": dimensionless (from UNITS below)


SCHEMA: dict[str, dict[str, Key]] = {
    "": {
        "name": Key("str", "scene", "name of the scene (labels the runs and the report)"),
        "description": Key("str", "", "free text"),
        "variant": Key("str", "rough", "rough: rough-surface cascade (thesis 6.3.2); separated: "
                                       "two separated scales with a spline law mu(p, v) (thesis "
                                       "6.2)",
                       choices=("rough", "separated")),
        "output": Key("str", "rf-results/{name}",
                      "output folder (relative to the current directory); "
                      "{name} is replaced by the scene name; the command line --out wins"),
    },
    "surface": {
        "source": Key("str", "default_road",
                      "default_road: CAPTIF chipseal + self-affine fine extension "
                      "(driver.surfaces.default_road); four_scale: synthetic self-affine road "
                      "whose four scales reach a cumulative 2D rms slope of 1.3 at 3 um "
                      "(driver.surfaces.four_scale); files: measured profiles listed in 'files'; "
                      "sines: one sine wave per scale (amplitudes, wavelengths)",
                      choices=("default_road", "four_scale", "files", "sines")),
        "cutoff": Key("cutoff", "slope",
                      "the lowest scale (not for sines): \"slope\": measured bands down to the "
                      "measurement's resolution, generated bands while the cumulative 2D rms slope "
                      "stays <= max_slope (the crossing band shortened, lower ones dropped); "
                      "\"resolution\": measured bands only; a wavelength in mm: the bands down "
                      "to it"),
        "max_slope": Key("float", 1.3, "cutoff = \"slope\": the largest cumulative 2D rms slope "
                         "(Lorenz et al., J. Chem. Phys. 142, 194701, 2015)", above=0.0),
        "files": Key("strs", [], "source = files: profile files (relative to the scene file), one "
                                 "or more resolutions of one road; each band is cut from the "
                                 "coarsest file resolving it"),
        "edges": Key("floats", [20.0, 3.0, 0.3, 0.04, 0.003],
                     "scale edges in mm, descending: scale i is the band edges[i]..edges[i+1] (eq. "
                     "6.10, 6.14); source = sines: optional, each wavelength must lie in its band"),
        "names": Key("strs", [], "scale names (default: macro, meso, micro1, micro2 / scale0..)"),
        "block_lengths": Key("floats", [],
                             "rubber block length per scale in mm (default: the long edge "
                             "of each band, thesis 6.5.1; sines: periods_per_block x wavelength)"),
        "top_fraction": Key("float", 0.2, "sample centres lie on the top fraction of the carrier "
                            "(thesis 6.5.1: contact happens on the top asperities)", above=0.0,
                            maximum=1.0),
        "seed": Key("int", 1, "seed of the sample positions (same seed, same samples)", minimum=0),
        "amplitudes": Key("floats", [], "source = sines: amplitude of each wave in mm (scale "
                                        "order)"),
        "wavelengths": Key("floats", [], "source = sines: wavelength of each wave in mm, "
                                         "descending"),
        "periods_per_block": Key("int", 1, "source = sines: block length in wavelengths",
                                 minimum=1),
        "points_per_wavelength": Key("int", 64,
                                     "source = sines: vertices of the rigid polyline "
                                     "per wavelength", minimum=8),
    },
    "samples": {
        "pressure": Key("int", 2, "k: surface samples per scale on the frictionless pressure "
                                  "branch (eq. 6.11, 6.12); the thesis argues k < j "
                                  "suffices", minimum=1),
        "friction": Key("int", 2, "j: surface samples per scale on the friction branch (eq. 6.13); "
                        "the thesis uses 10 (6.4.2: S(10) ~ S(1)/3)", minimum=1),
        "max_failed_fraction": Key("float", 0.25, "a scale on which more than this fraction of the "
                                   "samples failed is flagged in the report", minimum=0.0,
                                   maximum=1.0),
    },
    "conditions": {
        "compounds": Key("strs", ["tread_default"], "compound names (forms/data) or TOML files "
                         "(relative to the scene file)", nonempty=True),
        "pressures": Key("floats", [0.3], "global nominal pressures p in MPa (at most 1000 MPa: "
                         "a tyre presses the road with about 0.2-1 MPa, rubber's moduli are a few "
                         "MPa)", nonempty=True, above=0.0, maximum=1000.0),
        "velocities": Key("floats", [1.0, 10.0, 100.0],
                          "global sliding velocities v in mm/s (full slip: "
                          "the same v on every scale, thesis 6.3.2; at most 1e5 mm/s = 100 m/s, "
                          "beyond any sliding tyre)", nonempty=True, above=0.0, maximum=1e5),
        "T0": Key("opt_float", None, "temperature T0 (unit: T0_unit); omitted: the compound's WLF "
                  "reference temperature"),
        "T0_unit": Key("str", "K", "unit of T0", choices=("K", "degC")),
    },
    "physics": {
        "hysteresis": Key("bool", True, "viscoelastic rubber (Prony series, history variables); "
                                        "false: long-term elastic rubber, no history variables are "
                                        "built"),
        "adhesion": Key("bool", False, "bell-law adhesion on the macro scale with the multiscale "
                                       "real contact area (thesis 7.3, eq. 7.5-7.8); needs the "
                                       "[adhesion] table"),
        "thermal": Key("bool", False, "thermomechanical macro scale (thesis ch. 8): a block "
                                      "sliding over the road with frictional heating, with the "
                                      "friction of [thermal].mu or mu_curve, or from the lower "
                                      "scales ([thermal].mode = coupled or hot-layer: the thermal "
                                      "multiscale loop, thesis 8.4)"),
    },
    "adhesion": {
        "tau0": Key("float", 3.0, "peak adhesive shear stress in MPa (eq. 7.6)", minimum=0.0),
        "c": Key("float", 0.15, "width of the bell (eq. 7.6, decadic log)", above=0.0),
        "v0": Key("float", 20.0, "velocity of the peak in mm/s (eq. 7.6)", above=0.0),
        "alpha": Key("float", 1.0, "share of adhesion, 1 dry .. 0 lubricated (eq. 7.8); with "
                     "fit_from: given (not fitted) when written", minimum=0.0, maximum=1.0),
        "fit_from": Key("table", {}, "fit tau0, c, v0 to friction measurements instead of giving "
                        "them (thesis 7.3-7.5): { dry = ..., soap = ..., water = ... }, each a "
                        "file or a list of files, one per compound in [conditions].compounds "
                        "(relative to the scene file; format: driver/adhesion/measurements.py); "
                        "the campaign runs the hysteresis cascade, fits, then the macro scale "
                        "with alpha = 1 and with each fitted alpha (lower scales reused)"),
        "approach": Key("str", "original", "with fit_from: original = dry - soap-water (eq. 7.3, "
                        "7.4); modified = dry - the campaign's mu_H (thesis 7.5)",
                        choices=("original", "modified")),
        "extrapolate": Key("bool", False, "with fit_from: allow measurement speeds outside the "
                           "campaign's velocities (A_r, mu_H extended linearly in log v)"),
    },
    "numerics": {
        "elements_per_wavelength": Key("int", 8,
                                       "contact-face elements per shortest wavelength of a "
                                       "sample (the run's element size rule)", minimum=2),
        "master_points_per_wavelength": Key("int", 32, "vertices of the rigid surface per "
                                            "shortest wavelength of a sample's band: coarser "
                                            "samples are refined by band-limited "
                                            "interpolation (0: as sampled)", minimum=0),
        "grading": Key("float", 1.2, "growth ratio of element height away from the contact face",
                       minimum=1.0, maximum=3.0),
        "window": Key("str", "converged",
                      "time homogenisation of every run (eq. 6.2; driver.sliding.window): "
                      "converged = slide whole block lengths until the mean mu (pressure "
                      "branch: the contact fraction, whose reciprocal is the pressure passed "
                      "down) of the last w >= 2 "
                      "and of the w before agree within convergence_tol and average the last w "
                      "(a run that cannot "
                      "within max_slide_periods is marked unconverged and not averaged); fixed = "
                      "slide slide_periods block lengths and average after window_start "
                      "(thesis 6.2.3)", choices=("converged", "fixed")),
        "convergence_tol": Key("float", 0.01, "window = converged: largest relative change of "
                               "the mean mu (pressure branch: contact fraction) of the last w "
                               "periods against the w before", above=0.0,
                               maximum=0.5),
        "max_slide_periods": Key("float", 12.0, "window = converged: sliding budget in block "
                                 "lengths (at least a run-in period and two blocks of two)",
                                 minimum=5.0),
        "pressure_slide_periods": Key("float", 24.0, "window = converged: sliding budget of the "
                                      "pressure-branch runs in block lengths (frictionless, "
                                      "cheaper; their contact fraction settles more slowly than "
                                      "mu)", minimum=5.0),
        "steady_state": Key("bool", True, "periodic extrapolation of the Prony histories at the "
                            "end of every period of a cell (forms.viscoelastic."
                            "ViscoelasticHistory.extrapolate_periodic): the static part of the "
                            "load relaxes at once instead of creeping for tau_max / T periods"),
        "shortcut": Key("bool", True, "a frictionless run in full contact over small slopes is "
                        "the linear viscoelastic closed form instead of an FE run (criterion and "
                        "guard: driver.sliding.shortcut; the report counts them)"),
        "slide_periods": Key("float", 2.0, "window = fixed: sliding distance in block lengths",
                             above=0.0),
        "window_start": Key("float", 1.0 / 3.0, "window = fixed: fraction of the sliding distance "
                            "before the time average of eq. (6.2) starts (run-in)", minimum=0.0,
                            maximum=0.9),
        "step_per_element": Key("float", 0.5, "sliding step / contact element size", above=0.0,
                                maximum=4.0),
        "compression_steps": Key("int", 10, "steps of the compression phase", minimum=1),
        "contact": Key("str", "mortar", "contact formulation (a failing run falls back to a "
                       "softer c_T (frictional runs), nts, smaller steps, then contact elements "
                       "twice as short)",
                       choices=("mortar", "nts", "surface")),
        "element": Key("str", "Q1P0", "rubber element (Q1P0s: Q1P0 with pressure-jump "
                       "stabilisation, no checkerboard mode in confined cells)",
                       choices=("Q1P0", "Q1P0s", "Q1")),
        "newton": Key("str", "line-search", "globalisation of the Newton solves: line-search "
                      "(residual backtracking), trust-region (minimises the step's incremental "
                      "potential, driver.fe.trust_region: converges where the tangent is "
                      "indefinite; Q1P0 or Q1) or hybrid (line-search, and the trust region for a "
                      "sub-step where it fails)",
                      choices=("line-search", "trust-region", "hybrid")),
        "max_cutbacks": Key("int", 8, "step halvings before a step counts as failed", minimum=0),
        "stabilisation": Key("float", 0.1, "viscous stabilisation beta of a sub-step that still "
                             "fails after a cut-back (thesis 6.3.3; tried x1, x10, x100; its "
                             "share of mu is in samples.csv); 0: off", minimum=0.0),
        "min_jacobian": Key("float", 1e-3, "a converged state with det F at most this at a "
                            "quadrature point (a collapsed element) is refused like an inverted "
                            "one: cut back, stabilise, fall back; 0: inversion only",
                            minimum=0.0, maximum=0.5),
        "penalty_alpha": Key("float", 100.0, "normal penalty c_N = alpha |E*(omega)| / h_contact: "
                             "contact compliance ~1/alpha of an element's; lower is faster on "
                             "steep surfaces and softer (more contact area)", above=0.0),
        "tangential_penalty": Key("float", 0.1, "tangential penalty c_T = this x c_N (the stick "
                                  "compliance; full slip does not depend on it); a frictional run "
                                  "that fails tries it 10 times softer next", above=0.0),
        "run_timeout": Key("float", 0.0, "seconds after which a single run stops with a stored "
                                         "failure ('timeout': reported, recomputed on the next "
                                         "run of the scene) and the campaign goes on; a run stuck "
                                         "where it cannot stop itself is killed 10 % + 60 s "
                                         "later and the campaign exits (rerun to resume); 0: no "
                                         "limit",
                           minimum=0.0),
    },
    "thermal": {
        "mu": Key("opt_float", None, "constant friction coefficient of the macro run (or mu_curve)",
                  minimum=0.0),
        "mu_curve_T": Key("floats", [], "mu(T_s) curve (thesis fig. 8.5 a): temperatures in K, "
                                        "increasing; the contact temperature of each node "
                                        "selects mu",
                          above=0.0),
        "mu_curve_mu": Key("floats", [], "mu(T_s) curve: friction coefficients at mu_curve_T",
                           minimum=0.0),
        "kappa": Key("float", 1.0, "share of the frictional heat going into the rubber (thesis "
                                   "8.3.1: 1; 0.8-0.9 elsewhere)", minimum=0.0, maximum=1.0),
        "h_c": Key("float", 1.0e6, "interface conductance in mW/(mm^2 K) where in contact (thesis "
                                   "8.3.1: 1e6, i.e. perfect contact)", minimum=0.0),
        "road": Key("str", "r1", "road material with [thermal] data (forms/data or a TOML file)"),
        "block_length": Key("float", 20.0, "rubber block length in mm (thesis 8.5.1: 20)",
                            above=0.0),
        "block_height": Key("float", 8.0, "rubber block height in mm", above=0.0),
        "edge_radius": Key("float", 0.0, "rounded leading (front) edge in mm: 0 square, else a "
                                         "multiple of h_contact, at least 3 h_contact",
                           minimum=0.0),
        "slide_distance": Key("float", 10.0, "sliding distance in mm", above=0.0),
        "h_contact": Key("float", 0.25, "contact element length of block and road along x, mm",
                         above=0.0),
        "step_per_element": Key("float", 0.5, "sliding step / h_contact", above=0.0),
        "road_depth": Key("float", 10.0, "depth of the road body in mm", above=0.0),
        "road_mechanics": Key("str", "rigid", "rigid (thesis 8.4.1) or elastic: the road's "
                                              "surface deflection under the contact forces (E, "
                                              "nu of the road material) moves the road each step "
                                              "(driver/thermal/road_deflection.py)",
                              choices=("rigid", "elastic")),
        "road_surface": Key("str", "flat", "flat, or macro: the block slides over the macro band "
                                           "(the first scale) of the scene's [surface], from "
                                           "road_start on (mode = given only: the lower scales' "
                                           "mu is the given one)",
                            choices=("flat", "macro")),
        "road_start": Key("float", 0.0, "macro road: where along the band profile the road "
                                        "starts, mm",
                          minimum=0.0),
        "road_ahead": Key("float", 2.0, "road ahead of the block (block frame, inflow at T0), mm",
                          minimum=0.0),
        "road_behind": Key("float", 20.0, "road behind the block (the heated track, outflow), mm",
                           minimum=0.0),
        "first_layer": Key("float", 0.01, "first element height at the interface in mm (thesis "
                                          "8.4.1: 0.01)", above=0.0),
        "grading": Key("float", 1.2, "growth ratio of element heights away from the interface",
                       minimum=1.0),
        "probes_x": Key("floats", [], "thermocouple positions x in mm (block frame, 0 = trailing "
                                      "edge)"),
        "probes_z": Key("floats", [], "thermocouple positions z in mm (> 0 rubber, < 0 road)"),
        "slides": Key("int", 1, "repeated slides of slide_distance (thesis 8.5.2: the block keeps "
                                "its temperature field, the road is fresh each slide)", minimum=1),
        "pauses": Key("floats", [], "pause in s after each slide but the last (block lifted, "
                                    "conduction only): slides - 1 values", minimum=0.0),
        "coupling": Key("str", "staggered", "heat step after each converged sliding step (see "
                                            "driver/thermal/macro.py)", choices=("staggered",)),
        "mode": Key("str", "given", "given: mu or mu_curve on the macro run, no lower scales; "
                                    "coupled: the thermal multiscale loop (mu from the scene's "
                                    "rough cascade, redone with the flash-temperature profile at "
                                    "each homogenisation point, driver/multiscale/thermal_loop.py)",
                    choices=("given", "coupled", "hot-layer")),
        "divisions": Key("int", 4, "coupled: homogenisation points at n_d equal parts of the slide "
                                   "(thesis 8.4.3)", minimum=1),
        "points": Key("floats", [], "coupled: homogenisation points as sliding distances in mm "
                                    "(increasing; the slide's end is added); overrides divisions",
                      above=0.0),
        "auto_dT": Key("float", 0.0, "coupled: automatic homogenisation points (thesis 8.4.3) "
                                     "whenever the mean contact surface temperature moved by this "
                                     "many K; 0: divisions / points", minimum=0.0),
        "max_points": Key("int", 16, "coupled: at most this many automatic points", minimum=1),
        "warm_start": Key("bool", True, "coupled: each homogenisation point's lower-scale runs "
                                        "slide on from the previous point's final states (the "
                                        "rubber keeps its deformation and history); false: "
                                        "every run from rest, as the thesis did (hot-layer mode "
                                        "always)"),
        "warm_window_periods": Key("int", 1, "coupled, warm_start: periods per block of a warm "
                                             "run's converged window (driver/sliding/window.py): "
                                             "1 stops a warm run after 2 periods where they "
                                             "agree; 2, the rule of the runs from rest, after 4 "
                                             "at the least (on the default road 1.3-1.5x slower "
                                             "than 1, the points' mu within 0.6 %; README)",
                                   minimum=1),
        "partitions": Key("int", 4, "coupled: temperature partitions n_p over partition_depth "
                                    "(thesis 8.3.3, 8.4.2)", minimum=1),
        "partition_depth": Key("float", 0.09, "coupled: depth below the contact face the "
                                              "partitions cover, mm (thesis 8.4.2: 0.09)",
                               above=0.0),
        "mu_const": Key("float", 0.0, "coupled: constant friction added on the macro scale to the "
                                      "lower scales' mu (thesis 8.3.2 adhesive part, 8.4.3: 0.6)",
                        minimum=0.0),
        "bulk_wlf": Key("bool", True, "the macro block's relaxation times follow its temperature "
                                      "cell by cell (WLF)"),
        "hot_layer_rises": Key("floats", [0.0, 5.0, 10.0, 20.0, 40.0, 80.0],
                               "hot-layer mode (thesis 8.5.3): surface temperatures T_S - T0 in "
                               "K of the precomputed lower scales (increasing, from 0)",
                               minimum=0.0),
        "hot_layer": Key("float", 0.005, "hot-layer mode: thickness of the layer at T_S, mm "
                                         "(thesis: 5 um)", above=0.0),
        "hot_transition": Key("float", 0.020, "hot-layer mode: depth of the second partition at "
                                              "(T_S + T0) / 2, mm (thesis: 20 um)", above=0.0),
    },
    "separated": {
        "pressures": Key("floats", [], "micro grid pressures in MPa; empty: pressure_factors x the "
                                       "mean contact pressure of the frictionless macro run "
                                       "(thesis 6.2.1 step C)",
                         above=0.0),
        "pressure_factors": Key("floats", [0.25, 0.5, 1.0, 2.0, 4.0], "see pressures", above=0.0),
        "velocities": Key("floats", [], "micro grid velocities in mm/s; empty: velocity_factors x "
                                        "v",
                          above=0.0),
        "velocity_factors": Key("floats", [0.5, 1.0, 2.0], "see velocities", above=0.0),
        "micro_window_start": Key("float", 0.0,
                                  "window start of the micro time average; 0 includes the "
                                  "micro run-in, which the thesis finds necessary (6.2.3)",
                                  minimum=0.0,
                                  maximum=0.9),
        "micro_slide_periods": Key("float", 1.5,
                                   "micro sliding distance in block lengths (thesis 6.2.3: "
                                   "1.5 wavelengths)", above=0.0),
        "reference": Key("bool", True, "also run the single-scale reference on the full profile "
                                       "and compare mu and wall time (thesis fig. 6.4)"),
        "spline_degree": Key("int", 3, "highest spline degree per axis (eq. 6.6); lowered to the "
                                       "grid",
                             minimum=1, maximum=5),
        "smoothing": Key("float", 0.0, "FITPACK smoothing factor of the spline fit (0: "
                                       "interpolate)",
                         minimum=0.0),
    },
}

#: Units of the real-valued keys, "[section].key" -> unit ("1": dimensionless); every key of kind
#: float, floats, opt_float or cutoff has one (tests/test_docs_reference.py), and they go into
#: the keys' ``unit`` here, so ``docs/scene-reference.md`` (generated from SCHEMA) shows them.
UNITS: dict[str, str] = {
    "[surface].cutoff": "mm", "[surface].max_slope": "1", "[surface].edges": "mm",
    "[surface].block_lengths": "mm", "[surface].top_fraction": "1", "[surface].amplitudes": "mm",
    "[surface].wavelengths": "mm",
    "[samples].max_failed_fraction": "1",
    "[conditions].pressures": "MPa", "[conditions].velocities": "mm/s",
    "[conditions].T0": "K or degC (T0_unit)",
    "[adhesion].tau0": "MPa", "[adhesion].c": "decades of v", "[adhesion].v0": "mm/s",
    "[adhesion].alpha": "1",
    "[numerics].grading": "1", "[numerics].convergence_tol": "1",
    "[numerics].max_slide_periods": "block lengths",
    "[numerics].pressure_slide_periods": "block lengths",
    "[numerics].slide_periods": "block lengths", "[numerics].window_start": "1",
    "[numerics].step_per_element": "contact elements", "[numerics].stabilisation": "1",
    "[numerics].min_jacobian": "1", "[numerics].penalty_alpha": "1",
    "[numerics].tangential_penalty": "1", "[numerics].run_timeout": "s",
    "[thermal].mu": "1", "[thermal].mu_curve_T": "K", "[thermal].mu_curve_mu": "1",
    "[thermal].kappa": "1", "[thermal].h_c": "mW/(mm^2 K)", "[thermal].block_length": "mm",
    "[thermal].block_height": "mm", "[thermal].edge_radius": "mm",
    "[thermal].slide_distance": "mm", "[thermal].h_contact": "mm",
    "[thermal].step_per_element": "h_contact", "[thermal].road_depth": "mm",
    "[thermal].road_start": "mm", "[thermal].road_ahead": "mm", "[thermal].road_behind": "mm",
    "[thermal].first_layer": "mm", "[thermal].grading": "1", "[thermal].probes_x": "mm",
    "[thermal].probes_z": "mm", "[thermal].pauses": "s", "[thermal].points": "mm",
    "[thermal].auto_dT": "K", "[thermal].partition_depth": "mm", "[thermal].mu_const": "1",
    "[thermal].hot_layer_rises": "K", "[thermal].hot_layer": "mm",
    "[thermal].hot_transition": "mm",
    "[separated].pressures": "MPa", "[separated].pressure_factors": "1",
    "[separated].velocities": "mm/s", "[separated].velocity_factors": "1",
    "[separated].micro_window_start": "1", "[separated].micro_slide_periods": "block lengths",
    "[separated].smoothing": "1",
}


def _attach_units() -> None:
    """Write :data:`UNITS` into the keys of :data:`SCHEMA` (a unit of no key fails here)."""
    for where, unit in UNITS.items():
        section, name = where[1:].split("].")
        SCHEMA[section][name] = replace(SCHEMA[section][name], unit=unit)


_attach_units()

SECTIONS = tuple(k for k in SCHEMA if k)


def schema_text() -> str:
    """All keys with defaults and meaning, as TOML comments (``rubberfriction run --schema``)."""
    lines = []
    for section, keys in SCHEMA.items():
        if section:
            lines.append(f"\n[{section}]")
        for name, key in keys.items():
            default = _toml_value(key.default)
            extra = f" (one of {', '.join(map(str, key.choices))})" if key.choices else ""
            lines.append(f"{name} = {default}  # {key.doc}{extra}")
        if section == "numerics":
            lines.append("\n# [numerics.<scale>]  (e.g. [numerics.micro2]): any key of [numerics] "
                         f"but {', '.join(SCENE_WIDE_NUMERICS)}, for the runs on that scale only")
    return "\n".join(lines).lstrip() + "\n"


def _toml_value(v: Any) -> str:
    if v is None:
        return "<unset>"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


# ----------------------------------------------------------------------------------------------
# typed scene
# ----------------------------------------------------------------------------------------------


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
    #: edges as the scene states them; ``edges`` are those the cut-off rule keeps
    stated_edges: tuple[float, ...] = ()
    #: what the rule did, band by band (None for sines)
    cutoff_report: CutoffReport | None = field(default=None, compare=False, repr=False)
    #: the [surface] as the scene states it, before the rule (None: nothing was cut)
    stated: SurfaceConfig | None = field(default=None, compare=False, repr=False)

    @property
    def n_scales(self) -> int:
        return len(self.wavelengths) if self.source == "sines" else len(self.edges) - 1


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
    max_slide_periods: float
    pressure_slide_periods: float
    steady_state: bool
    shortcut: bool
    slide_periods: float
    window_start: float
    step_per_element: float
    compression_steps: int
    contact: str
    element: str
    newton: str
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


#: [numerics] keys that a [numerics.<scale>] table may not change: the window rule is the
#: scene's (one convergence statement per campaign), the wall clock is the executor's
SCENE_WIDE_NUMERICS = ("window", "run_timeout")


@dataclass(frozen=True)
class ThermalSceneConfig:
    """``[thermal]`` of a thermal scene (see SCHEMA): friction (constant mu or a mu(T) curve),
    heat split and conductance, road material, block and road geometry, probes."""

    mu: float | None
    mu_curve: tuple[tuple[float, float], ...]
    kappa: float
    h_c: float
    road: str
    block_length: float
    block_height: float
    slide_distance: float
    h_contact: float
    step_per_element: float
    road_depth: float
    road_ahead: float
    road_behind: float
    first_layer: float
    grading: float
    probes: tuple[tuple[float, float], ...]
    slides: int = 1
    pauses: tuple[float, ...] = ()
    edge_radius: float = 0.0
    mode: str = "given"  # or "coupled": the thermal multiscale loop
    divisions: int = 4
    points: tuple[float, ...] = ()
    partitions: int = 4
    partition_depth: float = 0.09
    mu_const: float = 0.0
    bulk_wlf: bool = True
    hot_layer_rises: tuple[float, ...] = (0.0, 5.0, 10.0, 20.0, 40.0, 80.0)
    auto_dT: float = 0.0
    max_points: int = 16
    warm_start: bool = True
    warm_window_periods: int = 1
    hot_layer: float = 0.005
    hot_transition: float = 0.020
    road_mechanics: str = "rigid"  # or "elastic"
    road_surface: str = "flat"  # or "macro": the first band of [surface]
    road_start: float = 0.0


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


# ----------------------------------------------------------------------------------------------
# loading and validation
# ----------------------------------------------------------------------------------------------


def _where(section: str, key: str) -> str:
    return f"[{section}].{key}" if section else key


def _check_value(origin: str, section: str, name: str, key: Key, value: Any) -> Any:
    where = f"{origin}: {_where(section, name)}"
    bounds = {"minimum": key.minimum, "above": key.above, "maximum": key.maximum,
              "error": SceneError}
    k = key.kind
    if k == "str":
        V.text(where, value, error=SceneError)
        return V.choice(where, value, key.choices, error=SceneError) if key.choices else value
    if k == "bool":
        if not isinstance(value, bool):
            V.fail(where, value, "true or false", SceneError)
        return value
    if k == "int":
        V.integer(where, value, error=SceneError)
        return int(V.number(where, value, what="an integer", **bounds))
    if k == "float":
        return V.number(where, value, **bounds)
    if k == "table":
        if not isinstance(value, dict):
            V.fail(where, value, "a table { key = value, ... }", SceneError)
        return dict(value)
    if k == "cutoff":
        if isinstance(value, str):
            return V.choice(where, value, ("slope", "resolution"), error=SceneError)
        return V.number(where, value, what="\"slope\", \"resolution\" or a wavelength in mm",
                        above=0.0, error=SceneError)
    if k == "opt_float":
        return None if value is None else V.number(where, value, **bounds)
    if k in ("floats", "strs"):
        if isinstance(value, (int, float, str)) and not isinstance(value, bool):
            value = [value]  # a single value where a list is expected
        if not isinstance(value, list):
            V.fail(where, value, "a list", SceneError)
        if key.nonempty and not value:
            V.fail(where, value, "a non-empty list", SceneError)
        if k == "strs":
            if not all(isinstance(v, str) for v in value):
                V.fail(where, value, "a list of strings", SceneError)
            return tuple(value)
        return tuple(V.number(where, v, what="a list of numbers", shown=value, **bounds)
                     for v in value)
    raise AssertionError(k)  # pragma: no cover


def _table(origin: str, doc: dict, section: str) -> dict[str, Any]:
    """Validated values of one section (defaults filled in), unknown keys rejected."""
    keys = SCHEMA[section]
    table = doc if not section else doc.get(section, {})
    if not isinstance(table, dict):
        raise SceneError(f"{origin}: [{section}] must be a table, got {table!r}")
    allowed = list(keys) + ([] if section else list(SECTIONS))
    for name in table:
        if name not in allowed:
            what = "section" if not section and isinstance(table[name], dict) else "key"
            raise SceneError(f"{origin}: unknown {what} "
                             f"{_where(section, name)!s}{V.suggest(name, allowed)} "
                             f"(allowed: {', '.join(allowed)})")
    out = {}
    for name, key in keys.items():
        if name in table:
            out[name] = _check_value(origin, section, name, key, table[name])
        else:
            d = key.default
            out[name] = tuple(d) if isinstance(d, list) else d
    return out


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
    top = _table(origin, doc, "")
    doc, scale_tables = _scale_numerics_tables(doc)
    vals = {s: _table(origin, doc, s) for s in SECTIONS}
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
    return surface, stated_names


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
    thermal = _thermal(origin, doc, vals["thermal"]) if physics.thermal else None
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
                                    surface.block_lengths, rule, title=name)
    except SurfaceError as err:
        raise SceneError(f"{origin}: [surface] (source = {surface.source!r}, edges = "
                         f"{list(surface.edges)}, {_cutoff_text(surface)}): {err}") from None
    n = len(road.scales)
    return replace(surface, edges=tuple(report.edges), names=tuple(names[:n]),
                   block_lengths=tuple(surface.block_lengths[:n]),
                   stated_edges=tuple(surface.edges), cutoff_report=report, stated=surface)


def with_surface(scene: Scene, **changes: Any) -> Scene:
    """The scene with ``[surface]`` keys changed (``edges`` as stated, ``cutoff``, ``max_slope``,
    ...) and its cut-off rule applied again (for studies of the lowest scale)."""
    base = scene.surface.stated or scene.surface
    bad = set(changes) - {f.name for f in fields(base)}
    if bad:
        raise SceneError(f"with_surface: unknown [surface] key(s) {sorted(bad)}")
    surface = replace(base, **changes)
    if surface.source in ROAD_SOURCES:
        surface = _cut(scene.source, surface, name=scene.name)
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
            values.append((k, _check_value(origin, f"numerics.{scale}", k, keys[k], v)))
        out.append((scale, tuple(values)))
    return tuple(out)


def _thermal(origin: str, doc: dict, t: dict) -> ThermalSceneConfig:
    """The [thermal] table of a thermal scene, with the checks across its keys."""
    where = f"{origin}: [thermal]"
    if "thermal" not in doc:
        raise SceneError(f"{origin}: [physics].thermal = true: expected a [thermal] table with the "
                         "friction (mu or mu_curve_T/mu_curve_mu), kappa, h_c and the geometry")
    T, m = t["mu_curve_T"], t["mu_curve_mu"]
    if len(T) != len(m):
        raise SceneError(f"{where}.mu_curve_T has {len(T)} values and mu_curve_mu {len(m)}: "
                         "expected one friction coefficient per temperature")
    if t["mode"] == "hot-layer":
        r = t["hot_layer_rises"]
        if len(r) < 2 or r[0] != 0.0 or any(b <= a for a, b in zip(r[:-1], r[1:])):
            raise SceneError(f"{where}.hot_layer_rises = {list(r)}: expected at least two "
                             "increasing values starting at 0 K")
        if t["hot_layer"] >= t["hot_transition"]:
            raise SceneError(f"{where}.hot_layer = {t['hot_layer']} mm: expected below "
                             f"hot_transition = {t['hot_transition']} mm")
    if t["mode"] in ("coupled", "hot-layer"):
        if t["mu"] is not None or T:
            raise SceneError(f"{where}: mode = '{t['mode']}' takes mu from the lower scales (the "
                             "scene's rough cascade); remove mu / mu_curve_T (a constant part on "
                             "the macro scale: mu_const)")
        pts = t["points"]
        if pts and (any(b <= a for a, b in zip(pts[:-1], pts[1:]))
                    or pts[-1] > t["slide_distance"]):
            raise SceneError(f"{where}.points = {list(pts)}: expected increasing sliding distances "
                             f"up to slide_distance = {t['slide_distance']} mm")
        if t["slides"] > 1:
            raise SceneError(f"{where}: mode = '{t['mode']}' with slides = {t['slides']}: the loop "
                             "runs one slide (repeated slides take a given mu)")
        if t["road_surface"] != "flat":
            raise SceneError(f"{where}: mode = '{t['mode']}' with road_surface = "
                             f"'{t['road_surface']}': the loop's cascade already holds the macro "
                             "band; a rough macro road takes a given mu (mode = 'given')")
    elif doc.get("physics", {}).get("adhesion", False):
        raise SceneError(f"{where}: mode = 'given' with [physics].adhesion = true: the given mu is "
                         "the whole macro friction; put the adhesive part into mu, or use mode = "
                         "'coupled' (the bell law on every cascade's contact area)")
    elif (t["mu"] is None) == (not T):
        raise SceneError(f"{where}: expected exactly one of mu (constant) and "
                         "mu_curve_T/mu_curve_mu (mu(T_s)), or mode = 'coupled' (mu from the "
                         "lower scales)")
    if T and (len(T) < 2 or any(b <= a for a, b in zip(T[:-1], T[1:]))):
        raise SceneError(f"{where}.mu_curve_T = {list(T)}: expected at least two increasing "
                         "temperatures in K")
    r, hc = t["edge_radius"], t["h_contact"]
    if r > 0 and (abs(r / hc - round(r / hc)) > 1e-9 * max(1.0, r / hc) or r < 3.0 * hc - 1e-12
                  or r >= min(t["block_length"], t["block_height"])):
        raise SceneError(f"{where}.edge_radius = {r} mm: expected 0 (square) or a whole number of "
                         f"contact elements h_contact = {hc} mm, at least 3 of them (the mesh "
                         "grades into the arc) and below the block's length and height")
    if len(t["pauses"]) != t["slides"] - 1:
        what = ("a pause without a slide after it" if len(t["pauses"]) >= t["slides"]
                else "slides without pauses")
        raise SceneError(f"{where}.pauses = {list(t['pauses'])} with slides = {t['slides']}: "
                         f"{what}; expected slides - 1 pauses (s)")
    if len(t["probes_x"]) != len(t["probes_z"]):
        raise SceneError(f"{where}.probes_x has {len(t['probes_x'])} values and probes_z "
                         f"{len(t['probes_z'])}: expected one z per x")
    for name in ("block_length", "road_ahead", "road_behind"):
        n = t[name] / t["h_contact"]
        if abs(n - round(n)) > 1e-9 * max(1.0, n):
            raise SceneError(f"{where}.{name} = {t[name]} mm: expected a whole number of contact "
                             f"elements h_contact = {t['h_contact']} mm")
    if t["first_layer"] > min(t["block_height"], t["road_depth"]):
        raise SceneError(f"{where}.first_layer = {t['first_layer']} mm: expected at most the block "
                         "height and the road depth")
    return ThermalSceneConfig(
        mu=t["mu"], mu_curve=tuple(zip(T, m)), kappa=t["kappa"], h_c=t["h_c"], road=t["road"],
        block_length=t["block_length"], block_height=t["block_height"], edge_radius=r,
        slide_distance=t["slide_distance"], h_contact=t["h_contact"],
        step_per_element=t["step_per_element"], road_depth=t["road_depth"],
        road_ahead=t["road_ahead"], road_behind=t["road_behind"], first_layer=t["first_layer"],
        grading=t["grading"], probes=tuple(zip(t["probes_x"], t["probes_z"])), slides=t["slides"],
        pauses=tuple(t["pauses"]), mode=t["mode"], divisions=t["divisions"],
        points=tuple(t["points"]),
        partitions=t["partitions"], partition_depth=t["partition_depth"], mu_const=t["mu_const"],
        bulk_wlf=t["bulk_wlf"], hot_layer_rises=tuple(t["hot_layer_rises"]),
        hot_layer=t["hot_layer"],
        hot_transition=t["hot_transition"], auto_dT=t["auto_dT"], max_points=t["max_points"],
        warm_start=t["warm_start"], warm_window_periods=t["warm_window_periods"],
        road_mechanics=t["road_mechanics"], road_surface=t["road_surface"],
        road_start=t["road_start"])


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
