"""The package installs like one: pyproject.toml lists every source package, and a wheel built from
the checkout works in a fresh virtual environment from a directory outside the checkout."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import tomllib

ROOT = Path(__file__).resolve().parents[1]
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())


def _package_folder(name: str, package_dir: dict[str, str]) -> Path:
    """The folder setuptools takes package ``name`` from (longest mapped prefix, as setuptools)."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        prefix = ".".join(parts[:i])
        if prefix in package_dir:
            return ROOT / package_dir[prefix] / Path(*parts[i:])
    raise AssertionError(f"{name}: no package-dir entry maps it")


def test_every_source_package_is_listed() -> None:
    setuptools = CONFIG["tool"]["setuptools"]
    listed = set(setuptools["packages"])
    folders = {_package_folder(name, setuptools["package-dir"]): name for name in listed}
    for folder in folders:
        assert (folder / "__init__.py").is_file(), f"{folders[folder]}: no {folder}/__init__.py"
    for top in ("driver", "forms", "meshes", "src/rubberfriction"):
        for init in (ROOT / top).rglob("__init__.py"):
            assert init.parent in folders, \
                f"{init.parent.relative_to(ROOT)} missing from pyproject.toml"


def test_console_script_is_the_cli_entry_point() -> None:
    assert CONFIG["project"]["scripts"] == {"rubberfriction": "rubberfriction.driver.cli.main:main"}


def test_installed_package_is_this_checkout_without_path_hacks() -> None:
    """Imported from outside the checkout, the package resolves to this checkout's folders."""
    code = ("import json, rubberfriction, rubberfriction.forms, rubberfriction.driver, "
            "rubberfriction._contact as c; print(json.dumps([rubberfriction.__file__, "
            "rubberfriction.forms.__file__, rubberfriction.driver.__file__, c.__file__, "
            "list(rubberfriction.__path__)]))")
    out = subprocess.run([sys.executable, "-c", code], cwd="/", capture_output=True, text=True,
                         check=True)
    init, forms, driver, ext, path = json.loads(out.stdout)
    assert Path(init).resolve() == ROOT / "src" / "rubberfriction" / "__init__.py"
    assert Path(forms).resolve() == ROOT / "forms" / "__init__.py"
    assert Path(driver).resolve() == ROOT / "driver" / "__init__.py"
    assert Path(ext).resolve().parent == ROOT / "src" / "rubberfriction"
    assert [Path(p).resolve() for p in path] == [ROOT / "src" / "rubberfriction"]


@pytest.mark.slow
def test_wheel_installs_into_a_fresh_venv_and_runs_outside_the_checkout(tmp_path: Path) -> None:
    """Build the wheel (C++ through CMake), install it into a venv with the system site packages
    (the Debian stack), run ``rubberfriction verify patch --json`` from a folder outside the
    checkout: equilibrium and a uniform patch-test pressure (closed forms)."""
    wheels, venv, work = tmp_path / "wheels", tmp_path / "venv", tmp_path / "work"
    src = tmp_path / "src"  # setuptools builds inside the source folder: build a copy
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(".git", "build", "rf-results",
                                                             "__pycache__", "*.so", "*.egg-info"))
    work.mkdir()
    env = {**os.environ, "PIP_NO_INDEX": "1", "CMAKE_BUILD_PARALLEL_LEVEL": "2"}
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps",
                    "-w", str(wheels), str(src)], check=True, env=env, capture_output=True)
    (wheel,) = wheels.glob("rubberfriction-*.whl")
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-deps",
                    str(wheel)], check=True, env=env, capture_output=True)
    where = subprocess.run([str(venv / "bin" / "python"), "-c",
                            "import rubberfriction, rubberfriction._contact as c; "
                            "print(rubberfriction.__file__); print(c.__file__)"],
                           cwd=work, capture_output=True, text=True, check=True).stdout.split()
    assert all(Path(p).resolve().is_relative_to(venv.resolve()) for p in where), where
    out = work / "patch.json"
    subprocess.run([str(venv / "bin" / "rubberfriction"), "verify", "patch", "--json", str(out)],
                   cwd=work, check=True, env={**env, "OMP_NUM_THREADS": "1"},
                   capture_output=True)
    result = json.loads(out.read_text())
    assert result["case"] == "patch"
    par = result["parameters"]
    checks = {c["quantity"]: c["computed"] for c in result["checks"]}
    # equilibrium: the contact force carries the applied load p L exactly (solver tolerance);
    # the patch test: the contact pressure is uniform
    assert (abs(checks["total contact force F_z"] - par["pressure"] * par["length"])
            <= 1e-8 * par["pressure"])
    p_min, p_max = checks["contact pressure min"], checks["contact pressure max"]
    assert abs(p_max - p_min) <= 1e-8 * par["pressure"]


def test_version_is_stated_once_per_file_and_agrees() -> None:
    """The run keys contain ``rubberfriction.__version__``; pyproject.toml must say the same."""
    import rubberfriction

    assert CONFIG["project"]["version"] == rubberfriction.__version__


def test_console_shows_no_build_chatter() -> None:
    """FFCx compiles new forms with setuptools, which raises the root logger to INFO: a first run
    with a cold JIT cache printed every gcc command line.  After the CLI's logging set-up an INFO
    record on the root logger stays off the console and a warning still shows."""
    code = ("import logging; from rubberfriction.driver.cli.main import quiet_build_logging; "
            "quiet_build_logging(); logging.root.setLevel(logging.INFO); "
            "logging.info('gcc -O2 -c libffcx_forms.c'); logging.warning('kept')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/",
                         check=True)
    assert "gcc" not in out.stdout + out.stderr
    assert "kept" in out.stderr


def test_version_option_prints_the_package_version(capsys) -> None:
    from rubberfriction import __version__
    from rubberfriction.driver.cli.main import main

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.split()[:2] == ["rubberfriction", __version__]
