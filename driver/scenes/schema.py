"""The scene schema: every key of a scene with its type, default, admissible values, unit and
meaning (:data:`SCHEMA`, the one place defaults are written down; ``rubberfriction run
--schema`` and ``docs/scene-reference.md`` are generated from it), and the check of one table
against it (unknown keys rejected with a did-you-mean suggestion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from rubberfriction import validation as V


class SceneError(V.InputError):
    """A scene that cannot be run; the message names the key, the value and what is expected."""


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
    below: float | None = None  # value < below
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
        "height_scale": Key("float", 1.0, "every height of the road times this factor (all "
                            "bands, measured and generated; sines: the amplitudes) before bands "
                            "and samples are cut: a rougher (> 1) or smoother (< 1) road, thesis "
                            "6.5.2.  Band rms heights and slopes scale with it, so cutoff = "
                            "\"slope\" sees steeper bands and may keep fewer scales: compare "
                            "roads at the same scales with a wavelength cutoff", above=0.0),
        "polish_fraction": Key("float", 0.0, "polishing (thesis 6.5.3, fig. 6.26, 6.28: flattened "
                               "asperities): on every sample of the polish_scales the heights "
                               "above the level this fraction of the sample's points exceed are "
                               "set to that level (flat tops covering this fraction of the "
                               "sample; driver.surfaces.polish.truncate_tips); 0: unpolished",
                               minimum=0.0, below=1.0),
        "polish_scales": Key("strs", [], "scales whose samples polish_fraction truncates (names "
                             "of scales the cut-off keeps); empty: every scale below the coarsest "
                             "two (the micro scales)"),
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
                                            "shortest wavelength of a sample's band (at least 4 "
                                            "per contact element): coarser samples are refined "
                                            "by band-limited interpolation, finer ones keep "
                                            "a subset of their points (0: as sampled)",
                                            minimum=0),
        "grading": Key("float", 1.2, "growth ratio of element height away from the contact face",
                       minimum=1.0, maximum=3.0),
        "window": Key("str", "converged",
                      "time homogenisation of every run (eq. 6.2; driver.sliding.window): "
                      "converged = slide whole block lengths until the mean mu (pressure "
                      "branch: the contact fraction, whose reciprocal is the pressure passed "
                      "down) of the last w >= window_periods "
                      "and of the w before agree within convergence_tol and average the last w "
                      "(a run that cannot "
                      "within max_slide_periods is marked unconverged and not averaged); fixed = "
                      "slide slide_periods block lengths and average after window_start "
                      "(thesis 6.2.3)", choices=("converged", "fixed")),
        "convergence_tol": Key("float", 0.01, "window = converged: largest relative change of "
                               "the mean mu (pressure branch: contact fraction) of the last w "
                               "periods against the w before", above=0.0,
                               maximum=0.5),
        "window_periods": Key("int", 1, "window = converged: fewest periods averaged, w; "
                              "one-period windows are compared at half convergence_tol (the "
                              "same bound on a drift per period as w = 2) and only once the "
                              "contact face no longer creeps (driver.sliding.periods); 2: the "
                              "rule before 0.21.0", minimum=1, maximum=4),
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
        "period_extrapolation": Key("bool", True, "with steady_state and window = converged, a "
                                    "frictionless cell's state is extrapolated to the limit of "
                                    "its slowest mode (the block's creep under the mean shear of "
                                    "the friction force) where the period changes are geometric "
                                    "(driver.sliding.slowmode)"),
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
        "newton_rtol": Key("float", 1e-8, "Newton converges when the residual norm is at most "
                           "this x the load p L of the cell (every scale's runs; "
                           "docs/performance.md has what a looser test saves and moves)",
                           above=0.0, maximum=1e-3),
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
                                           "road_start on (thesis figs. 8.2, 8.17 a); given: the "
                                           "given mu is that of the scales below; coupled, "
                                           "hot-layer: the block is the cascade's macro scale, "
                                           "its contact gets the mu the cascade hands to it and "
                                           "the point's mu is its F_x / F_z "
                                           "(driver/multiscale/thermal_loop.py)",
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
                                             "agree as [numerics] window_periods = 1 asks; 2 "
                                             "after 4 at the least (on the default road "
                                             "1.3-1.5x slower than 1, the points' mu within "
                                             "0.6 %; README)",
                                   minimum=1),
        "partitions": Key("int", 4, "coupled: temperature partitions n_p over partition_depth "
                                    "(thesis 8.3.3, 8.4.2)", minimum=1),
        "partition_depth": Key("float", 0.09, "coupled: depth below the contact face the "
                                              "partitions cover, mm (thesis 8.4.2: 0.09)",
                               above=0.0),
        "mu_const": Key("float", 0.0, "coupled: constant friction added on the macro scale to the "
                                      "lower scales' mu (thesis 8.3.2 adhesive part, 8.4.3: 0.6)",
                        minimum=0.0),
        "stationary_blocks": Key("int", 10, "coupled, hot-layer: the point's mu is the macro mu "
                                            "averaged over its stationary part, by the converged "
                                            "rule on this many equal blocks of the slide "
                                            "(driver/sliding/window.py stationary_mean; coupled "
                                            "with divisions: the intervals are the blocks)",
                                 minimum=1),
        "stationary_tol": Key("float", 0.01, "coupled, hot-layer: the relative tolerance of that "
                                             "rule", above=0.0),
        "bulk_wlf": Key("bool", True, "the macro block's relaxation times follow its temperature "
                                      "cell by cell (WLF)"),
        "hot_layer_rises": Key("floats", [0.0, 5.0, 10.0, 20.0, 40.0, 80.0],
                               "hot-layer mode (thesis 8.5.3): surface temperatures T_S - T0 in "
                               "K of the precomputed lower scales (increasing, from 0); a "
                               "hotter macro contact adds twice the largest, at most twice; "
                               "contact nodes still hotter are accepted only while the normal "
                               "load they carry bounds their effect on mu within 1 % (noted), "
                               "else the point is refused",
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
    "[surface].wavelengths": "mm", "[surface].height_scale": "1", "[surface].polish_fraction": "1",
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
    "[numerics].newton_rtol": "1",
    "[thermal].mu": "1", "[thermal].mu_curve_T": "K", "[thermal].mu_curve_mu": "1",
    "[thermal].kappa": "1", "[thermal].h_c": "mW/(mm^2 K)", "[thermal].block_length": "mm",
    "[thermal].block_height": "mm", "[thermal].edge_radius": "mm",
    "[thermal].slide_distance": "mm", "[thermal].h_contact": "mm",
    "[thermal].step_per_element": "h_contact", "[thermal].road_depth": "mm",
    "[thermal].road_start": "mm", "[thermal].road_ahead": "mm", "[thermal].road_behind": "mm",
    "[thermal].first_layer": "mm", "[thermal].grading": "1", "[thermal].probes_x": "mm",
    "[thermal].probes_z": "mm", "[thermal].pauses": "s", "[thermal].points": "mm",
    "[thermal].auto_dT": "K", "[thermal].partition_depth": "mm", "[thermal].mu_const": "1",
    "[thermal].stationary_tol": "1",
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
            default = toml_value(key.default)
            extra = f" (one of {', '.join(map(str, key.choices))})" if key.choices else ""
            lines.append(f"{name} = {default}  # {key.doc}{extra}")
        if section == "numerics":
            lines.append("\n# [numerics.<scale>]  (e.g. [numerics.micro2]): any key of [numerics] "
                         f"but {', '.join(SCENE_WIDE_NUMERICS)}, for the runs on that scale only")
    return "\n".join(lines).lstrip() + "\n"


def toml_value(v: Any, short: bool = False) -> str:
    """A value as TOML text (``<unset>`` for None): the schema listing (exact numbers) and, with
    ``short``, the scene reference (finite floats to 6 significant digits)."""
    if v is None:
        return "<unset>"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x, short) for x in v) + "]"
    if short and isinstance(v, float) and math.isfinite(v):
        return f"{v:.6g}"
    return repr(v)


#: [numerics] keys that a [numerics.<scale>] table may not change: the window rule is the
#: scene's (one convergence statement per campaign), the wall clock is the executor's
SCENE_WIDE_NUMERICS = ("window", "run_timeout")


def _where(section: str, key: str) -> str:
    return f"[{section}].{key}" if section else key


def check_value(origin: str, section: str, name: str, key: Key, value: Any) -> Any:
    where = f"{origin}: {_where(section, name)}"
    bounds = {"minimum": key.minimum, "above": key.above, "maximum": key.maximum,
              "below": key.below, "error": SceneError}
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


def section_values(origin: str, doc: dict, section: str) -> dict[str, Any]:
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
            out[name] = check_value(origin, section, name, key, table[name])
        else:
            d = key.default
            out[name] = tuple(d) if isinstance(d, list) else d
    return out
