#!/usr/bin/env bash
# Style checks (run by .ci/run before the tests): flake8 on the Python tree (config: .flake8,
# 100 columns) and clang-format on the C++ contact core (config: .clang-format).  Installs
# flake8 and clang-format from Debian when they are missing; nothing comes from PyPI.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
missing=()
for p in flake8 clang-format; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
if ((${#missing[@]})); then
  echo "[lint] installing apt packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
status=0
/usr/bin/python3 -m flake8 src driver forms meshes tests scripts setup.py || status=1
clang-format --dry-run -Werror cpp_contact/*.cpp cpp_contact/*.hpp || status=1
if [ "$status" -ne 0 ]; then
  echo "[lint] style deviations above (fix them; clang-format -i cpp_contact/*.cpp cpp_contact/*.hpp fixes C++)" >&2
  exit 1
fi
echo "[lint] clean: flake8 (100 columns) and clang-format"
