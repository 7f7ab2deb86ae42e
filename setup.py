"""Build of the C++ contact core through the setuptools backend (metadata: pyproject.toml).

``pip install --no-build-isolation --no-deps [-e] .`` runs CMake (``CMakeLists.txt``) and puts the
pybind11 module ``rubberfriction._contact`` where setuptools expects the extension: next to
``src/rubberfriction/__init__.py`` for an editable install, inside the wheel otherwise.  The CMake
build folder of an editable install is ``build/cmake`` (rebuild after C++ changes with
``cmake --build build/cmake -j2``); a wheel build uses setuptools' temporary build folder.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    """An extension whose sources CMake knows (no sources for setuptools to compile)."""

    def __init__(self, name: str) -> None:
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """Configure and build the CMake project, writing the module to the extension's path."""

    def build_extension(self, ext: Extension) -> None:
        target = Path(self.get_ext_fullpath(ext.name)).resolve()
        if self.editable_mode:  # persistent build folder, module next to the package sources
            build, out = ROOT / "build" / "cmake", ROOT / "src" / "rubberfriction"
        else:
            build, out = Path(self.build_temp).resolve(), target.parent
        build.mkdir(parents=True, exist_ok=True)
        configure = ["cmake", "-S", str(ROOT), "-B", str(build),
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     "-DCMAKE_BUILD_TYPE=Release",
                     f"-DRF_CONTACT_OUTPUT_DIR={out}"]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "-j", jobs], check=True)
        built = out / target.name
        if not built.exists():
            raise RuntimeError(f"CMake did not produce {built}")
        if built != target:  # setuptools copies the module from here (editable: back in place)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(built, target)


setup(ext_modules=[CMakeExtension("rubberfriction._contact")], cmdclass={"build_ext": CMakeBuild})
