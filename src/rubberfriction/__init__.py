"""rubberfriction: multiscale FEM rubber friction on rough road surfaces.

One import namespace for the whole project: ``rubberfriction.forms`` (UFL forms and material
data, folder ``forms/``), ``rubberfriction.meshes`` (``meshes/``), ``rubberfriction.driver``
(``driver/``) and the compiled C++ contact core ``rubberfriction._contact`` (``cpp_contact/``).
``pyproject.toml`` maps the folders onto the package (``package-dir``); the package is used
installed (``scripts/setup.sh`` makes an editable install of the checkout), never from a path hack.
"""

from __future__ import annotations

__version__ = "0.17.0"
