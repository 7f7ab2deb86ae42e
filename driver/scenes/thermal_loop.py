"""The thermal-loop part of a scene's ``[thermal]`` table: the checks of ``mode = "coupled"``
(the thermal multiscale loop, mu from the scene's rough cascade at each homogenisation point)
and ``mode = "hot-layer"`` (the hot-layer variant of the loop).

:func:`rubberfriction.driver.scenes.thermal.parse_thermal` calls :func:`check_loop_table` for
these modes; the loop itself (``driver.multiscale.thermal_loop``, ``thermal_loop_scene``) runs
what the checked table says.
"""

from __future__ import annotations

from typing import Any

from rubberfriction.driver.scenes.schema import SceneError

#: [thermal].mode values whose friction comes from the lower scales (the loop)
LOOP_MODES = ("coupled", "hot-layer")


def check_loop_table(where: str, t: dict[str, Any]) -> None:
    """Checks across the [thermal] keys of a loop mode (``where`` = "<origin>: [thermal]"): the
    hot layer's temperature rises and thickness, no given mu, the homogenisation points within
    the slide, one slide (on the flat road or the macro band, ``road_surface``)."""
    if t["mode"] == "hot-layer":
        r = t["hot_layer_rises"]
        if len(r) < 2 or r[0] != 0.0 or any(b <= a for a, b in zip(r[:-1], r[1:])):
            raise SceneError(f"{where}.hot_layer_rises = {list(r)}: expected at least two "
                             "increasing values starting at 0 K")
        if t["hot_layer"] >= t["hot_transition"]:
            raise SceneError(f"{where}.hot_layer = {t['hot_layer']} mm: expected below "
                             f"hot_transition = {t['hot_transition']} mm")
    if t["mu"] is not None or t["mu_curve_T"]:
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
