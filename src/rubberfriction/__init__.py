"""rubberfriction: multiscale FEM rubber friction on rough road surfaces.

``import rubberfriction as rf`` gives the Python API (``rf.__all__``, ``docs/api.md``).  One
import namespace for the whole project: ``rubberfriction.forms`` (UFL forms and material
data, folder ``forms/``), ``rubberfriction.meshes`` (``meshes/``), ``rubberfriction.driver``
(``driver/``) and the compiled C++ contact core ``rubberfriction._contact`` (``cpp_contact/``).
``pyproject.toml`` maps the folders onto the package (``package-dir``); the package is used
installed (``scripts/setup.sh`` makes an editable install of the checkout), never from a path hack.
"""

from __future__ import annotations

__version__ = "0.29.0"

#: The Python API (``docs/api.md``): ``import rubberfriction as rf; rf.load_scene("two_sine")``.
#: The names live in :mod:`rubberfriction.api` and are imported on first use (PEP 562), so that
#: ``import rubberfriction`` (and the command's start) does not load DOLFINx, PETSc or MPI.
__all__ = [
    "InputError",
    "arrays",
    "check",
    "default_profile",
    "default_road",
    "fit_compound",
    "fit_hdc",
    "format_table",
    "hdc",
    "load_compound",
    "load_profile",
    "load_scene",
    "mesh_check",
    "modify_scene",
    "psd",
    "run",
    "scene_from_toml",
    "scene_schema",
    "shipped_scenes",
    "split_bands",
    "study_trends",
    "table",
    "theory",
    "theory_curves",
    "verification_cases",
    "verify",
]


def __getattr__(name: str) -> object:
    """An API name (``__all__``) from :mod:`rubberfriction.api`, imported on first use."""
    if name in __all__:
        from rubberfriction import api

        value = getattr(api, name)
        globals()[name] = value  # later look-ups do not come here again
        return value
    raise AttributeError(f"module 'rubberfriction' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
