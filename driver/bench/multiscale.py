"""Benchmark: wall time and peak memory of multiscale campaigns, serial vs MPI ranks.

    rubberfriction bench multiscale [--ranks 2] [--out DIR] [--scene default] [--skip-default]
                                    [--skip-point] [--point-samples 10] [--point-velocity 100]
                                    [--modes serial,mpi]

Two campaigns, each run from scratch (``--fresh``) once serially and once with
``mpirun -n RANKS`` (the same command a user types):

1. the default scene (``rubberfriction run``; ``--scene`` picks another);
2. one full four-scale point with ten samples per scale (k = j = 10, thesis 6.4.2) of the default
   road at p = 0.3 MPa and one velocity.

Figures per campaign and mode: wall time, peak resident memory (largest single process, from its
VmHWM, and the peak sum over the process tree, sampled every 0.2 s from /proc), runs and failures,
and the share of run time per scale (from the campaign's ``samples.csv``).  It also checks that the
serial and MPI stores hold identical results.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path
from typing import Any

import tomllib

from rubberfriction.driver.runtime.store import Store


def _children(root: int) -> list[int]:
    """All descendants of a pid (from /proc/*/stat)."""
    parent: dict[int, int] = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    parent[int(d)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
    out, todo = [], [root]
    while todo:
        p = todo.pop()
        kids = [c for c, pp in parent.items() if pp == p]
        out += kids
        todo += kids
    return out


def _status_kb(pid: int, field: str) -> int:
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def run_measured(cmd: list[str], env: dict) -> dict[str, Any]:
    """Run a command; wall time, peak RSS of the largest process and of the process tree."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    hwm: dict[int, int] = {}
    peak_sum = 0
    while proc.poll() is None:
        pids = [proc.pid] + _children(proc.pid)
        total = 0
        for p in pids:
            total += _status_kb(p, "VmRSS")
            hwm[p] = max(hwm.get(p, 0), _status_kb(p, "VmHWM"))
        peak_sum = max(peak_sum, total)
        time.sleep(0.2)
    out, err = proc.communicate()
    return {"wall": time.perf_counter() - t0, "returncode": proc.returncode, "stdout": out,
            "stderr": err,
            "peak_process_MB": max(hwm.values(), default=0) / 1024.0,
            "peak_tree_MB": peak_sum / 1024.0}


def _toml(doc: dict) -> str:
    def val(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines = [f"{k} = {val(v)}" for k, v in doc.items() if not isinstance(v, dict)]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"\n[{k}]")
            lines += [f"{kk} = {val(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


def point_scene(samples: int, velocity: float) -> str:
    """The default scene reduced to one velocity with k = j = samples."""

    scenes = resources.files("rubberfriction.driver.scenes")
    doc = tomllib.loads(scenes.joinpath("default.toml").read_text())
    doc["name"] = "bench_point"
    doc["description"] = f"default road, four scales, {samples} samples per scale, one point"
    doc["samples"] = {"pressure": samples, "friction": samples}
    doc["conditions"]["velocities"] = [velocity]
    return _toml(doc)


def time_shares(out: Path) -> dict[str, float]:
    shares: dict[str, float] = {}
    path = out / "samples.csv"
    if not path.is_file():
        return shares
    with open(path) as f:
        for row in csv.DictReader(f):
            try:
                shares[row["scale_name"]] = shares.get(row["scale_name"],
                                                       0.0) + float(row["wall_time_s"] or 0)
            except ValueError:
                continue
    total = sum(shares.values()) or 1.0
    return {k: v / total for k, v in shares.items()}


def _same_store(a: Path, b: Path) -> str:

    sa, sb = Store(a / "store"), Store(b / "store")
    if sa.keys() != sb.keys():
        return f"DIFFERENT run sets ({len(sa)} vs {len(sb)})"
    for k in sa.keys():
        ra, rb = sa.load(k), sb.load(k)
        if ra.status != rb.status or not _same_values(ra.values, rb.values):
            return f"DIFFERENT results for run {k[:12]}"
    return f"identical ({len(sa)} runs)"


def _same_values(a: dict[str, float], b: dict[str, float]) -> bool:
    """Equal result scalars, NaN equal to NaN (a failed run stores NaN results)."""
    return a.keys() == b.keys() and all(
        a[k] == b[k] or (math.isnan(a[k]) and math.isnan(b[k])) for k in a)


def campaign(label: str, scene: str, out: Path, ranks: int, env: dict,
             which: tuple[str, ...] = ("serial", "mpi")) -> list[dict]:
    rows = []
    base = [sys.executable, "-m", "rubberfriction", "run", scene, "--fresh", "--quiet"]
    modes = []
    if "serial" in which:
        modes.append(("serial", base + ["--out", str(out / "serial")]))
    if ranks > 1 and "mpi" in which:
        modes.append((f"mpi x{ranks}", ["mpirun", "-n", str(ranks)] + base + ["--out",
                                                                              str(out / "mpi")]))
    for mode, cmd in modes:
        print(f"{label}: {mode} ...", flush=True)
        r = run_measured(cmd, env)
        folder = out / ("serial" if mode == "serial" else "mpi")
        n_runs = n_failed = 0
        if (folder / "samples.csv").is_file():
            with open(folder / "samples.csv") as f:
                keys = {}
                for row in csv.DictReader(f):
                    keys[row["key"]] = row["status"]
            n_runs, n_failed = len(keys), sum(s != "ok" for s in keys.values())
        rows.append({"campaign": label, "mode": mode, "wall_s": r["wall"],
                     "peak_process_MB": r["peak_process_MB"],
                     "peak_tree_MB": r["peak_tree_MB"], "runs": n_runs, "failed": n_failed,
                     "exit": r["returncode"], "shares": time_shares(folder)})
        if r["returncode"] not in (0, 1):
            print(r["stderr"][-2000:], file=sys.stderr)
    # compared whenever both stores exist (also from an earlier --modes serial invocation)
    if ranks > 1 and all(row["exit"] in (0, 1) for row in rows) and all(
            (out / m / "store").is_dir() for m in ("serial", "mpi")):
        print(f"{label}: serial vs mpi stores: {_same_store(out / 'serial', out / 'mpi')}")
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench multiscale", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", type=int, default=2,
                    help="MPI ranks for the parallel runs (default 2)")
    ap.add_argument("--out", default="rf-bench/multiscale",
                    help="work folder (default rf-bench/multiscale)")
    ap.add_argument("--scene", default="default",
                    help="scene of the first campaign (default: the default scene)")
    ap.add_argument("--skip-default", action="store_true", help="skip the first campaign")
    ap.add_argument("--skip-point", action="store_true",
                    help="skip the ten-sample four-scale point")
    ap.add_argument("--point-samples", type=int, default=10,
                    help="samples per scale of the point (default 10)")
    ap.add_argument("--point-velocity", type=float, default=100.0,
                    help="velocity of the point, mm/s")
    ap.add_argument("--modes", default="serial,mpi",
                    help="comma-separated subset of serial,mpi (e.g. two invocations with "
                         "--modes serial side by side on two cores, then --modes mpi; the stores "
                         "are compared once both exist)")
    args = ap.parse_args(argv)
    which = tuple(m.strip() for m in args.modes.split(",") if m.strip())
    if not which or set(which) - {"serial", "mpi"}:
        ap.error(f"--modes: expected a subset of serial,mpi, got {args.modes!r}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    rows: list[dict] = []
    if not args.skip_default:
        rows += campaign(f"scene {Path(args.scene).stem}", args.scene, out / "scene", args.ranks,
                         env, which)
    if not args.skip_point:
        scene = out / "point.toml"
        scene.write_text(point_scene(args.point_samples, args.point_velocity))
        rows += campaign(f"4 scales x {args.point_samples} samples, v={args.point_velocity:g}",
                         str(scene),
                         out / "point", args.ranks, env, which)
    print(f"\n{'campaign':<34} {'mode':<8} {'wall [s]':>9} {'peak proc [MB]':>15} "
          f"{'peak tree [MB]':>15} "
          f"{'runs':>5} {'failed':>6}  time per scale")
    for r in rows:
        shares = ", ".join(f"{k} {100 * v:.0f}%" for k, v in r["shares"].items())
        print(f"{r['campaign']:<34} {r['mode']:<8} {r['wall_s']:>9.1f} "
              f"{r['peak_process_MB']:>15.0f} "
              f"{r['peak_tree_MB']:>15.0f} {r['runs']:>5} {r['failed']:>6}  {shares}")
    serial = {r["campaign"]: r["wall_s"] for r in rows if r["mode"] == "serial"}
    for r in rows:
        if r["mode"] != "serial" and r["campaign"] in serial:
            print(f"speed-up {r['campaign']}: {serial[r['campaign']] / r['wall_s']:.2f} with "
                  f"{r['mode']}")
    return 0 if all(r["exit"] in (0, 1) for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
