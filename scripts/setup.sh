#!/usr/bin/env bash
# Set up whatever is missing on a Debian bookworm machine: apt packages, the C++ contact build,
# and the `rubberfriction` command.  Idempotent: a second call only checks.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY=/usr/bin/python3

APT_PACKAGES=(python3-dolfinx python3-dolfinx-mpc python3-gmsh python3-petsc4py python3-mpi4py
  python3-h5py python3-scipy python3-matplotlib python3-pytest libdolfinx-dev pybind11-dev
  libeigen3-dev cmake g++ make pkg-config python3-dev openmpi-bin)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing apt packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# C++ contact extension, written into rubberfriction/ (rebuilt only when sources changed).
cmake -S "$ROOT" -B "$ROOT/build" -DPython3_EXECUTABLE=$PY -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$ROOT/build" -j"$(nproc)" 2>&1 | grep -E "error|warning: unused|Error" || true
$PY -c "import sys; sys.path.insert(0, '$ROOT'); import rubberfriction._contact" \
  || { echo "[setup] the C++ extension failed to import" >&2; exit 1; }

# The `rubberfriction` command: a launcher for /usr/bin/python3 -m rubberfriction on this checkout.
BIN_DIR=/usr/local/bin
[ -w "$BIN_DIR" ] || BIN_DIR="$HOME/.local/bin"
mkdir -p "$BIN_DIR"
cat > "$BIN_DIR/rubberfriction" <<LAUNCH
#!/bin/sh
PYTHONPATH="$ROOT\${PYTHONPATH:+:\$PYTHONPATH}" exec $PY -m rubberfriction "\$@"
LAUNCH
chmod +x "$BIN_DIR/rubberfriction"
echo "[setup] ready: $BIN_DIR/rubberfriction ($(cd "$ROOT" && git rev-parse --short HEAD 2>/dev/null || echo no-git))"
