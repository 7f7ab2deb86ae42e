#!/usr/bin/env bash
# Set up whatever is missing on a Debian bookworm machine: apt packages, then the project itself
# installed (editable) with Debian's pip, which builds the C++ contact core through CMake
# (setup.py) and installs the `rubberfriction` command.  Idempotent: a second call only checks and
# rebuilds the C++ extension when its sources changed.  Nothing comes from PyPI.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY=/usr/bin/python3

APT_PACKAGES=(python3-dolfinx python3-gmsh python3-petsc4py python3-mpi4py python3-h5py
  python3-scipy python3-matplotlib python3-pytest python3-pip python3-venv python3-setuptools
  python3-wheel libdolfinx-dev pybind11-dev libeigen3-dev cmake g++ make pkg-config python3-dev
  openmpi-bin)

bash "$ROOT/scripts/apt-install.sh" setup "${APT_PACKAGES[@]}"

# The project: an editable install of this checkout (re-done when the packaging files change or
# another checkout is installed), then an incremental CMake build of the extension.
STAMP="$ROOT/build/cmake/.rf-install-stamp"
want="$ROOT $(cat "$ROOT/pyproject.toml" "$ROOT/setup.py" | sha256sum | cut -d' ' -f1)"
installed=$(cd / && $PY -c "import pathlib, rubberfriction; print(pathlib.Path(rubberfriction.__file__).resolve().parents[2])" 2>/dev/null || true)
if [ "$installed" != "$ROOT" ] || [ "$(cat "$STAMP" 2>/dev/null)" != "$want" ]; then
  echo "[setup] installing the project (pip install -e $ROOT, builds the C++ extension)"
  USER_FLAG=(); [ "$(id -u)" -ne 0 ] && USER_FLAG=(--user)
  log="$(mktemp)"
  if ! $PY -m pip install --no-build-isolation --no-deps --no-index --break-system-packages \
      "${USER_FLAG[@]}" -e "$ROOT" >"$log" 2>&1; then
    cat "$log" >&2; echo "[setup] pip install failed (log above)" >&2; exit 1
  fi
  rm -f "$log"
  echo "$want" > "$STAMP"
else
  cmake --build "$ROOT/build/cmake" -j"$(nproc)" 2>&1 | grep -E "error|warning|Error" | grep -v "lto-wrapper" || true
fi
(cd / && $PY -c "import rubberfriction._contact") \
  || { echo "[setup] the package or its C++ extension failed to import" >&2; exit 1; }
command -v rubberfriction >/dev/null \
  || echo "[setup] note: the rubberfriction command is in $($PY -c 'import site; print(site.USER_BASE)')/bin; add it to PATH"
echo "[setup] ready: rubberfriction $(cd / && $PY -c 'import rubberfriction; print(rubberfriction.__version__)') from $ROOT ($(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo no-git))"
