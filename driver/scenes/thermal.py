"""The ``[thermal]`` table of a thermal scene (``[physics].thermal = true``): the typed
:class:`ThermalSceneConfig` and its reader with the checks across keys.  The loop modes'
checks are in ``thermal_loop``; the runs in ``driver.multiscale.thermal_scene`` (given mu) and
``driver.multiscale.thermal_loop_scene`` (the loop).
"""

from __future__ import annotations

from dataclasses import dataclass

from rubberfriction.driver.scenes.schema import SceneError
from rubberfriction.driver.scenes.thermal_loop import LOOP_MODES, check_loop_table


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
    stationary_blocks: int = 10  # loop modes: the point's stationary mean (window.stationary_mean)
    stationary_tol: float = 0.01


def parse_thermal(origin: str, doc: dict, t: dict) -> ThermalSceneConfig:
    """The [thermal] table of a thermal scene, with the checks across its keys."""
    where = f"{origin}: [thermal]"
    if "thermal" not in doc:
        raise SceneError(f"{origin}: [physics].thermal = true: expected a [thermal] table with the "
                         "friction (mu or mu_curve_T/mu_curve_mu), kappa, h_c and the geometry")
    T, m = t["mu_curve_T"], t["mu_curve_mu"]
    if len(T) != len(m):
        raise SceneError(f"{where}.mu_curve_T has {len(T)} values and mu_curve_mu {len(m)}: "
                         "expected one friction coefficient per temperature")
    if t["mode"] in LOOP_MODES:
        check_loop_table(where, t)
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
        road_start=t["road_start"], stationary_blocks=t["stationary_blocks"],
        stationary_tol=t["stationary_tol"])
