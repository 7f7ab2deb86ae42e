"""The installed package layout in pyproject.toml covers every Python package in the source tree."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_source_package_is_listed() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed_dirs = {Path(d) for d in config["package-dir"].values()}
    assert set(config["packages"]) == set(config["package-dir"])
    for top in ("driver", "forms", "meshes", "rubberfriction"):
        for init in (ROOT / top).rglob("__init__.py"):
            package_dir = init.parent.relative_to(ROOT)
            assert package_dir in listed_dirs, f"{package_dir} missing from pyproject.toml"
