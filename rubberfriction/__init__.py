"""rubberfriction: multiscale FEM rubber friction on rough road surfaces.

The repository's top-level folders ``forms/``, ``driver/`` and ``meshes/`` are the sub-packages
``rubberfriction.forms``, ``rubberfriction.driver`` and ``rubberfriction.meshes``.  In a source
checkout this package extends its search path to the repository root so the folders are found
where they are; an installed wheel maps them with ``package-dir`` (see ``pyproject.toml``).
The compiled C++ contact module is ``rubberfriction._contact``.
"""

from __future__ import annotations

import os as _os

__version__ = "0.2.0"

_root = _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__)))
if _os.path.isdir(_os.path.join(_root, "forms")) and _root not in __path__:
    __path__.append(_root)  # noqa: F821  (module attribute of a package)
