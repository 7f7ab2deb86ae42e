"""Scenes shipped with rubberfriction (TOML, see :mod:`rubberfriction.driver.multiscale.scene`).

* ``default.toml`` -- the main job: ``rubberfriction run`` with no argument.
* ``two_sine.toml`` -- the separated-scale validation case of thesis 6.2.3 (eqs. 6.7, 6.8).
"""
