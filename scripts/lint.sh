#!/usr/bin/env bash
# Style checks (run by .ci/run before the tests): flake8 on the Python tree (config: .flake8,
# 100 columns) and clang-format on the C++ contact core (config: .clang-format).  Installs
# flake8 and clang-format from Debian when they are missing; nothing comes from PyPI.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
bash "$ROOT/scripts/apt-install.sh" lint flake8 clang-format
status=0
/usr/bin/python3 -m flake8 src driver forms meshes tests scripts setup.py || status=1
clang-format --dry-run -Werror cpp_contact/*.cpp cpp_contact/*.hpp || status=1
if [ "$status" -ne 0 ]; then
  echo "[lint] style deviations above (fix them; clang-format -i cpp_contact/*.cpp cpp_contact/*.hpp fixes C++)" >&2
  exit 1
fi
echo "[lint] clean: flake8 (100 columns) and clang-format"
