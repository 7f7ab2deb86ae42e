"""Farming independent runs: serial and MPI drivers give the same stored results, work is spread
over the ranks, a run that raises is recorded and never stops the campaign, and a killed
campaign resumes computing only the missing runs.

The task here is a cheap deterministic function of the run's inputs (`toy_run` below), which is
legitimate for testing orchestration: it is not physics.  The physics through the same farm is
tested in test_multiscale.py with the real FE runs.
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.driver.runtime.farm import Executor, StaticPlanner, Task, run_serial
from rubberfriction.driver.sliding.spec import SlidingResult
from rubberfriction.driver.runtime.store import Outcome, Store, run_key

ROOT = Path(__file__).resolve().parents[1]
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMP_NUM_THREADS": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}

# A deterministic stand-in for run_sliding (orchestration tests only), importable by subprocesses.
TOY = textwrap.dedent('''
    import os, time
    import numpy as np
    from rubberfriction.driver.sliding.spec import SlidingResult

    def toy_run(spec):
        """mu and pressure from the sample's rms slope and the applied friction; optional delay."""
        time.sleep(float(os.environ.get("TOY_DELAY", "0")))
        h, x = np.asarray(spec.surface_h), np.asarray(spec.surface_x)
        slope = float(np.sqrt(np.mean((np.diff(h) / np.diff(x)) ** 2)))
        mu0 = float(spec.friction or 0.0)
        s = np.linspace(0.0, 1.0, 9)
        return SlidingResult("ok", series={"s": s, "mu_force": mu0 + slope * (1 + np.sin(7 * s))},
                             mu_force=mu0 + 0.1 * slope + 1e-3 * spec.velocity ** 0.5,
                             mu_energy=mu0 + 0.08 * slope,
                             mean_pressure=spec.pressure * (1.0 + 3.0 * slope),
                             contact_fraction=1.0 / (1.0 + 5 * slope),
                             stats={"steps": 9})
''')

SCENE = textwrap.dedent('''
    name = "farmtest"
    [surface]
    source = "default_road"
    edges = [20.0, 3.0, 0.3, 0.04]
    [samples]
    pressure = 2
    friction = 3
    [conditions]
    pressures = [0.2, 0.4]
    velocities = [10.0, 100.0]
''')


@pytest.fixture()
def toy(tmp_path: Path, monkeypatch):
    (tmp_path / "toy_farm.py").write_text(TOY)
    monkeypatch.syspath_prepend(str(tmp_path))
    import importlib

    import toy_farm

    importlib.reload(toy_farm)
    return toy_farm.toy_run


def driver_script(tmp_path: Path) -> Path:
    """Runs the test scene with the toy runner: python script.py OUT [delay]."""
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "toy_farm.py").write_text(TOY)
    script = tmp_path / "drive.py"
    script.write_text(textwrap.dedent(f'''
        import sys
        sys.path[:0] = [{str(ROOT)!r}, {str(tmp_path)!r}]
        from rubberfriction.driver.multiscale.campaign import run_scene
        from rubberfriction.driver.multiscale.scene import load_scene
        from toy_farm import toy_run
        scene = load_scene({str(tmp_path / "scene.toml")!r})
        r = run_scene(scene, output=sys.argv[1], runner=toy_run, quiet=True)
        if r is not None:
            mus = [round(p.mu.mean, 12) for p in r.points]
            print("RESULT", r.n_runs, r.n_reused, r.workers, mus)
    '''))
    return script


def _env(**extra: str) -> dict:
    env = dict(os.environ, **MPI_ENV, **extra)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def test_serial_farm_records_failures_and_runs_each_key_once(tmp_path: Path, toy):
    from rubberfriction.driver.sliding.spec import SlidingSpec
    from rubberfriction.forms.material_files import load_compound

    c = load_compound("tread_default")
    x = np.linspace(0, 1, 16, endpoint=False)
    specs = [SlidingSpec(surface_x=x, surface_h=a * np.sin(2 * np.pi * x), period=1.0, pressure=0.3,
                         velocity=v,
                         compound=c) for a in (0.01, 0.02) for v in (1.0, 2.0, 3.0)]
    tasks = [Task(run_key(s), s, {"sample": i}) for i, s in enumerate(specs)]
    tasks.append(Task(tasks[0].key, specs[0], {"sample": 99}))  # the same run twice in one campaign
    calls = []

    def runner(spec):
        calls.append(spec.velocity)
        if spec.velocity == 2.0:
            raise RuntimeError("solver exploded")
        return toy(spec)

    store = Store(tmp_path / "store")
    planner = StaticPlanner(tasks)
    out = run_serial(planner, Executor(store, runner))
    assert len(calls) == 6 and len(out) == 6 and len(store) == 6
    res = planner.ordered()
    assert res[-1] is res[0]  # the duplicate got the outcome of the single run
    failed = [o for o in res if not o.ok]
    assert len(failed) == 2 and all(o.failure == "error" and "solver "
                                                             "exploded" in o.reason for o in failed)
    assert all(o.ok for o in res if o not in failed)


class _StagedPlanner:
    """Stage 2 repeats the run of stage 1 (as the separated variant's macro0 and a later run with the
    same spec may), stage 3 is new: the repeat is answered from the campaign's own results."""

    def __init__(self) -> None:
        self.stages = [["a"], ["a"], ["c"]]
        self.recorded: list[str] = []
        self._issued = False

    def total(self) -> int:
        return 3

    def next_tasks(self) -> list[Task]:
        if self._issued or not self.stages:
            return []
        self._issued = True
        return [Task(k, k) for k in self.stages[0]]

    def record(self, task: Task, outcome: Outcome) -> None:
        self.recorded.append(task.key)
        self.stages.pop(0)
        self._issued = False


def test_serial_farm_advances_a_planner_whose_next_run_is_already_done():
    executed: list[str] = []

    def execute(task: Task) -> Outcome:
        executed.append(task.key)
        return Outcome(task.key, "ok")

    planner = _StagedPlanner()
    run_serial(planner, execute)
    assert planner.recorded == ["a", "a", "c"] and executed == ["a", "c"]


@pytest.mark.mpi
def test_mpi_two_ranks_store_identical_results_and_share_the_work(tmp_path: Path):
    script = driver_script(tmp_path)
    serial = subprocess.run([sys.executable, str(script), str(tmp_path / "serial")],
                            env=_env(TOY_DELAY="0.02"),
                            capture_output=True, text=True, timeout=300)
    assert serial.returncode == 0, serial.stderr
    par = subprocess.run(["mpirun", "-n", "2", sys.executable, str(script), str(tmp_path / "mpi")],
                         env=_env(TOY_DELAY="0.02"), capture_output=True, text=True, timeout=300)
    assert par.returncode == 0, par.stderr + par.stdout
    line_s = [ln for ln in serial.stdout.splitlines() if ln.startswith("RESULT")][0].split(" ", 4)
    line_p = [ln for ln in par.stdout.splitlines() if ln.startswith("RESULT")][0].split(" ", 4)
    assert line_s[1] == line_p[1] == "52"  # 4 points x (2 scales x k=2 + 3 scales x j=3)
    assert line_s[3] == "1" and line_p[3] == "2"  # workers: rank 0 computes too
    assert line_s[4] == line_p[4]  # identical sample-averaged mu per point
    a, b = Store(tmp_path / "serial" / "store"), Store(tmp_path / "mpi" / "store")
    assert a.keys() == b.keys() and len(a) == 52
    pids = set()
    for key in a.keys():
        ra, rb = a.load(key), b.load(key)
        assert ra.status == rb.status and ra.values == rb.values and ra.label == rb.label
        assert ra.series.keys() == rb.series.keys()
        for name in ra.series:
            np.testing.assert_array_equal(ra.series[name], rb.series[name])
        pids.add(rb.provenance["pid"])
    assert len(pids) == 2  # dynamic load balancing gave work to both ranks
    for f in ("results.csv", "scales.csv"):
        lines_s = (tmp_path / "serial" / f).read_text().count("\n")
        assert lines_s == (tmp_path / "mpi" / f).read_text().count("\n")


@pytest.mark.mpi
def test_mpi_planner_failure_stops_every_rank(tmp_path: Path):
    script = tmp_path / "boom.py"
    script.write_text(textwrap.dedent('''
        import sys
        sys.path.insert(0, ROOT)
        from mpi4py import MPI
        from rubberfriction.driver.runtime.farm import Executor, run_farm
        from rubberfriction.driver.runtime.store import Store

        def planner():
            raise ValueError("bad surface")

        try:
            run_farm(planner, Executor(Store(sys.argv[1]), lambda s: None))
        except ValueError as err:
            sys.stdout.write(f"rank {MPI.COMM_WORLD.rank} raised {err}\\n")
        else:
            sys.stdout.write(f"rank {MPI.COMM_WORLD.rank} released\\n")
    ''').replace("ROOT", repr(str(ROOT))))
    r = subprocess.run(["mpirun", "-n", "2", sys.executable, str(script), str(tmp_path / "s")],
                       env=_env(),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "rank 0 raised bad surface" in r.stdout and "rank 1 released" in r.stdout


def test_killed_campaign_resumes_with_only_the_missing_runs(tmp_path: Path, toy):
    script = driver_script(tmp_path)
    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, str(script), str(out)], env=_env(TOY_DELAY="0.15"),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    store = Store(out / "store") if out.exists() else None
    t0 = time.time()
    while time.time() - t0 < 120:
        if (out / "store" / "runs").exists():
            store = Store(out / "store")
            if len(store) >= 12:
                break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # as hard as a kill gets: no clean-up runs
    proc.wait()
    assert store is not None
    before = set(store.keys())
    assert 12 <= len(before) < 52
    for key in before:  # everything that counts as finished is complete and readable
        assert store.load(key).status == "ok"

    calls = []

    def counting(spec):
        calls.append(run_key(spec))
        return toy(spec)

    from rubberfriction.driver.multiscale.campaign import run_scene
    from rubberfriction.driver.multiscale.scene import load_scene

    r = run_scene(load_scene(str(tmp_path / "scene.toml")), output=out, runner=counting, quiet=True)
    assert len(calls) == 52 - len(before) and not (set(calls) & before)
    assert r.n_runs == 52 and r.n_reused == len(before) and len(Store(out / "store")) == 52
    # a third pass computes nothing and gives the same answer
    calls.clear()
    r2 = run_scene(load_scene(str(tmp_path / "scene.toml")), output=out, runner=counting,
                   quiet=True)
    assert calls == [] and r2.n_reused == 52
    assert [p.mu.mean for p in r2.points] == [p.mu.mean for p in r.points]
    # --fresh moves the store aside (nothing is deleted) and computes everything again
    r3 = run_scene(load_scene(str(tmp_path / "scene.toml")), output=out, runner=counting,
                   quiet=True, fresh=True)
    assert len(calls) == 52 and r3.n_reused == 0
    assert len(list(out.glob("store-*"))) == 1


def test_a_hung_run_is_recorded_and_the_campaign_exits_for_resume(tmp_path: Path):
    """The watchdog: a run stuck where no exception reaches it is stored as failed ("timeout")."""
    script = tmp_path / "hang.py"
    script.write_text(textwrap.dedent('''
        import sys, time
        sys.path.insert(0, ROOT)
        from rubberfriction.driver.runtime.farm import Executor, Task
        from rubberfriction.driver.runtime.store import Store
        ex = Executor(Store(sys.argv[1]), lambda spec: time.sleep(600), timeout=1.0)
        ex(Task("ab" * 32, {"what": "hangs"}, {"sample": 0}))
        print("not reached")
    ''').replace("ROOT", repr(str(ROOT))))
    # hang guard only (the former bound of 60 s): without the watchdog the run sleeps 600 s and
    # subprocess.TimeoutExpired fails the test
    r = subprocess.run([sys.executable, str(script), str(tmp_path / "s")], env=_env(),
                       capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 3 and "not reached" not in r.stdout
    assert "exceeded 1 s" in r.stderr and "resume" in r.stderr
    store = Store(tmp_path / "s")
    out = store.outcome("ab" * 32)
    assert out.status == "failed" and out.failure == "timeout" and "timeout" in out.reason
    # stopped by the wall clock, not a result of its inputs: the next campaign computes it again
    calls = []

    def rerun(spec):
        calls.append(spec)
        return SlidingResult("ok", mu_force=0.5, stats={"steps": 1})

    again = Executor(store, rerun)(Task("ab" * 32, {"what": "hangs"}, {"sample": 0}))
    assert not again.reused and again.ok and len(calls) == 1
    assert store.outcome("ab" * 32).ok


def test_progress_counts_and_estimates_time_left():
    import io
    from types import SimpleNamespace

    from rubberfriction.driver.runtime.progress import Progress, format_seconds

    now = [0.0]
    out = io.StringIO()
    p = Progress(stream=out, min_interval=0.0, clock=lambda: now[0])
    p.start(10, 2)
    assert math.isnan(p.eta())  # nothing computed yet: unknown
    task = SimpleNamespace(label={"point": "c/p=0.3/v=10", "branch": "up", "scale_name": "meso", "sample": 1})
    now[0] = 10.0
    p.update(task, SimpleNamespace(status="ok", reused=False, wall_time=10.0))
    p.update(task, SimpleNamespace(status="failed", reused=False, wall_time=10.0))
    p.update(task, SimpleNamespace(status="ok", reused=True, wall_time=99.0))  # reused: costs nothing
    assert (p.done, p.computed, p.reused, p.failed) == (3, 2, 1, 1)
    assert p.eta() == pytest.approx(7 * 10.0 / 2)
    line = out.getvalue().splitlines()[-1]
    assert "[ 3/10]" in line and "failed 1" in line and "left ~35s" in line and "up meso 1" in line
    assert format_seconds(3725) == "1h02m" and format_seconds(250) == "4m10s"
    quiet = io.StringIO()
    q = Progress(quiet=True, stream=quiet)
    q.start(1, 1)
    q.update(task, SimpleNamespace(status="ok", reused=False, wall_time=1.0))
    q.finish()
    assert quiet.getvalue() == ""


def test_a_run_stopped_at_its_time_limit_is_a_timeout_and_the_campaign_goes_on(tmp_path: Path,
                                                                                monkeypatch):
    """sliding_runner(wall_limit=) hands the scene's run_timeout to run_sliding; a run that
    stopped itself there is stored as failure "timeout" without stopping the process and is
    computed again by the next campaign; the watchdog keeps a grace period."""
    from types import SimpleNamespace

    from rubberfriction.driver.runtime import farm
    from rubberfriction.driver.sliding import run as sliding

    seen = []

    def fake_run_sliding(spec, progress=None, observers=(), wall_limit=0.0):
        seen.append(wall_limit)
        return SimpleNamespace(status="failed", reason=f"wall-time limit of {wall_limit:g} s",
                               series={}, stats={"failure": "wall_limit", "wall_time": wall_limit},
                               dissipation_by_depth=None, mu_force=math.nan, mu_energy=math.nan,
                               mean_pressure=math.nan, contact_fraction=math.nan, t_reached=0.1)

    monkeypatch.setattr(sliding, "run_sliding", fake_run_sliding)
    runner = sliding.sliding_runner(wall_limit=600.0)
    store = Store(tmp_path / "s")
    ex = Executor(store, runner, timeout=farm.hard_timeout(600.0))
    assert ex.timeout == pytest.approx(720.0)
    out = ex(Task("cd" * 32, {"what": "slow"}, {"sample": 0}))
    assert seen == [600.0] and out.status == "failed" and out.failure == "timeout"
    assert not ex(Task("cd" * 32, {}, {})).reused and seen == [600.0, 600.0]
    assert farm.hard_timeout(0.0) == 0.0
