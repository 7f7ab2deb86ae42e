"""Scenes: the shipped scene files (TOML) and the code that reads a scene.

Readers (the campaign code that runs a scene is in ``driver/multiscale``):

* ``schema`` -- every key with its type, default, unit and meaning (:data:`SCHEMA`), the check
  of one table against it, :class:`SceneError`.
* ``rough`` -- :func:`load_scene` / :func:`parse_scene`: the typed :class:`Scene` from every
  table but ``[thermal]`` (surface and its cut-off rule, samples, conditions, physics,
  adhesion, separated, numerics), one reader per section.
* ``thermal`` -- ``[thermal]`` of a thermal scene (:class:`ThermalSceneConfig`); ``thermal_loop``
  -- the checks of its loop modes (``coupled``, ``hot-layer``).

The names other code uses are re-exported here (``from rubberfriction.driver.scenes import
load_scene``).

Shipped scenes:

* ``default.toml`` -- the main job: ``rubberfriction run`` with no argument.
* ``thesis_7_4.toml`` -- the adhesion validation of thesis 7.4 (hysteresis campaign for the
  bell-law fit), with illustrative measurement files in ``thesis_7_4/``;
  ``thesis_7_4_first.toml`` -- the same with three scales and 1 + 2 samples, a first look
  (its wall time: docs/performance.md).
* ``two_sine.toml`` -- the separated-scale validation case of thesis 6.2.3 (eqs. 6.7, 6.8).
"""

from rubberfriction.driver.scenes.rough import (
    SCENES_PACKAGE,
    AdhesionFitConfig,
    ConditionsConfig,
    NumericsConfig,
    PhysicsConfig,
    SamplesConfig,
    Scene,
    SeparatedConfig,
    SurfaceConfig,
    load_scene,
    override,
    parse_scene,
    shipped_scenes,
    surface_scale_names,
    with_surface,
)
from rubberfriction.driver.scenes.schema import (
    SCENE_WIDE_NUMERICS,
    SCHEMA,
    SECTIONS,
    UNITS,
    Key,
    SceneError,
    check_value,
    schema_text,
    section_values,
    toml_value,
)
from rubberfriction.driver.scenes.thermal import ThermalSceneConfig, parse_thermal
from rubberfriction.driver.scenes.thermal_loop import LOOP_MODES, check_loop_table

__all__ = [
    "LOOP_MODES", "SCENES_PACKAGE", "SCENE_WIDE_NUMERICS", "SCHEMA", "SECTIONS", "UNITS",
    "AdhesionFitConfig", "ConditionsConfig", "Key", "NumericsConfig", "PhysicsConfig",
    "SamplesConfig", "Scene", "SceneError", "SeparatedConfig", "SurfaceConfig",
    "ThermalSceneConfig", "check_loop_table", "check_value", "load_scene", "override",
    "parse_scene", "parse_thermal", "schema_text", "section_values", "shipped_scenes",
    "surface_scale_names", "toml_value", "with_surface",
]
