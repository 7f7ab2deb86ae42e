#!/usr/bin/env bash
# Set up what is missing, then run the main job on the embedded default scene.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
export OMP_NUM_THREADS=1
exec /usr/bin/python3 -m rubberfriction run "$@"
