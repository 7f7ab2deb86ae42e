#!/usr/bin/env bash
# Set up what is missing, then run the main job (default: the embedded default scene), farmed
# over all cores: `mpirun -n $(nproc)` when there is more than one and mpirun is installed.
# RF_RANKS=N chooses the number of ranks (RF_RANKS=1: serial, no mpirun).  Results are identical
# on 1 and N ranks.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
CORES="$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)"  # nproc obeys OMP_NUM_THREADS
export OMP_NUM_THREADS=1
RANKS="${RF_RANKS:-$CORES}"
if ! [[ "$RANKS" =~ ^[1-9][0-9]*$ ]]; then
  echo "run.sh: RF_RANKS=$RANKS: expected a whole number of ranks >= 1" >&2; exit 2
fi
if [ "$RANKS" -gt 1 ] && command -v mpirun >/dev/null; then
  # Open MPI refuses root without these; counting hardware threads as slots lets -n $(nproc)
  # start on machines with hyper-threading, and more ranks than cores need --oversubscribe
  if [ "$(id -u)" -eq 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  fi
  MPI_ARGS=(-n "$RANKS" --use-hwthread-cpus)
  [ "$RANKS" -gt "$CORES" ] && MPI_ARGS+=(--oversubscribe)
  # mpirun gives its processes a pseudo-terminal whatever our output is: say which it is
  MPI_ARGS+=(-x OMP_NUM_THREADS -x RF_PROGRESS)
  if [ -t 1 ]; then
    export RF_PROGRESS=tty COLUMNS="${COLUMNS:-$(tput cols 2>/dev/null || echo 100)}"
    MPI_ARGS+=(-x COLUMNS)
  else
    export RF_PROGRESS=plain
  fi
  exec mpirun "${MPI_ARGS[@]}" /usr/bin/python3 -m rubberfriction run "$@"
fi
exec /usr/bin/python3 -m rubberfriction run "$@"
