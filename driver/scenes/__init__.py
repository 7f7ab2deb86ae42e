"""Scenes shipped with rubberfriction (TOML, see :mod:`rubberfriction.driver.multiscale.scene`).

* ``default.toml`` -- the main job: ``rubberfriction run`` with no argument.
* ``thesis_7_4.toml`` -- the adhesion validation of thesis 7.4 (hysteresis campaign for the
  bell-law fit), with illustrative measurement files in ``thesis_7_4/``;
  ``thesis_7_4_first.toml`` -- the same with three scales and 1 + 2 samples (about 55 min on
  2 ranks).
* ``two_sine.toml`` -- the separated-scale validation case of thesis 6.2.3 (eqs. 6.7, 6.8).
"""
