#!/usr/bin/env bash
# Set up what is missing, then run the test suite (default: everything but the `slow` marker;
# pass `--all` to include slow cases, other arguments go to pytest).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
MARK=(-m "not slow")
if [ "${1:-}" = "--all" ]; then MARK=(); shift; fi
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec /usr/bin/python3 -m pytest "${MARK[@]}" "$@"
