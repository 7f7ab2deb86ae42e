"""Benchmark: how long a finished campaign takes on N ranks, replayed from its store.

    rubberfriction bench farm DIR [--ranks 1,2,4,8] [--scene FILE]

DIR is a results folder of ``rubberfriction run`` (its ``scene.toml`` and ``store/``).  The
campaign's planner is built again from the scene and driven by the farm's dispatch rule
(``driver.runtime.farm.replay``) with every run's stored outcome and wall time instead of
computing it: printed per rank count are the campaign's wall time, the speed-up over one rank,
the workers' efficiency and the critical path (the wall time with unlimited ranks).  What it
tells: where more ranks stop paying (the cascade's stages wait for all samples of the stage
before, and no run is split over ranks), before renting them.  The replay uses each run's time
as measured where it ran (next to other runs on a busy machine a run takes longer); on the
default scene it reproduces the measured 2-rank wall time (docs/performance.md, "More ranks").
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from rubberfriction.driver.multiscale.campaign import make_planner
from rubberfriction.driver.multiscale.scales import build_scales
from rubberfriction.driver.scenes import load_scene
from rubberfriction.driver.multiscale.specs import SpecBuilder, load_compounds
from rubberfriction.driver.runtime.farm import Replay, Task, replay
from rubberfriction.driver.runtime.store import Outcome, Store, run_key

#: stands for "as many ranks as there are runs": the critical path
UNLIMITED = 1_000_000


class MissingRun(LookupError):
    """The campaign needs a run its store does not hold."""


def campaign_version(folder: Path) -> str | None:
    """The code version of the campaign in ``folder`` (its ``campaign.json``), if recorded."""
    try:
        return json.loads((folder / "campaign.json").read_text()).get("code_version") or None
    except (OSError, ValueError):
        return None


def replay_folder(folder: Path, ranks: list[int], scene_file: Path | None = None) -> list[Replay]:
    """The campaign of ``folder`` replayed on each rank count (``UNLIMITED``: the critical path).
    A run is looked up by the key the campaign's code version gave its inputs (the version is
    part of every key, ``run_key``), so a store of an older release replays with this one."""
    scene = load_scene(scene_file or folder / "scene.toml")
    store = Store(folder / "store")
    version = campaign_version(folder)

    def outcome_of(task: Task) -> tuple[Outcome, float]:
        key = run_key(task.payload, version) if version else task.key
        out = store.outcome(key)
        if out is None:
            label = ", ".join(f"{k} {v}" for k, v in task.label.items()
                              if k in ("point", "branch", "scale_name", "sample"))
            raise MissingRun(f"{folder}: run {key[:12]} ({label}) is not in the store: "
                             "replay a finished campaign (run it to the end first)")
        return dataclasses.replace(out, key=task.key), out.wall_time

    n = max(scene.samples.pressure, scene.samples.friction)
    scales = build_scales(scene, n)
    builder = SpecBuilder(scene, load_compounds(scene))
    return [replay(make_planner(scene, scales, builder), outcome_of, r) for r in ranks]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench farm", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", type=Path, help="results folder of a finished campaign")
    ap.add_argument("--ranks", default="1,2,4,8", help="comma-separated rank counts")
    ap.add_argument("--scene", type=Path, default=None,
                    help="scene file (default: FOLDER/scene.toml)")
    args = ap.parse_args(argv)
    try:
        ranks = [int(r) for r in args.ranks.split(",") if r.strip()]
    except ValueError:
        ap.error(f"--ranks {args.ranks!r}: expected whole numbers separated by commas")
    if not ranks or min(ranks) < 1:
        ap.error(f"--ranks {args.ranks!r}: expected rank counts >= 1")
    try:
        rows = replay_folder(args.folder, sorted(set(ranks)) + [UNLIMITED], args.scene)
    except MissingRun as err:
        print(f"bench farm: {err}")
        return 1
    serial = rows[0].busy
    version = campaign_version(args.folder)
    print(f"{args.folder}: {rows[0].runs} runs, {serial:.1f} s of run time"
          + (f" (code {version})" if version else ""))
    print(f"{'ranks':>10} {'wall s':>10} {'speed-up':>9} {'efficiency':>10}")
    for r in rows[:-1]:
        print(f"{r.workers:>10d} {r.makespan:>10.1f} {serial / r.makespan:>9.2f} "
              f"{r.efficiency:>10.2f}")
    crit = rows[-1].makespan
    print(f"{'unlimited':>10} {crit:>10.1f} {serial / crit:>9.2f}   (critical path: the longest "
          "chain of runs, each stage waiting for its slowest sample)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
