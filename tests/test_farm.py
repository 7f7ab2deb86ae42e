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
    cutoff = 0.04
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
        from rubberfriction.driver.scenes import load_scene
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
    """Stage 2 repeats the run of stage 1 (as the separated variant's macro0 and a later run with
    the same spec may), stage 3 is new: the repeat is answered from the campaign's own results."""

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
        assert ra.status == rb.status and ra.label == rb.label
        assert ra.values.keys() == rb.values.keys()
        # NaN = NaN
        np.testing.assert_array_equal(list(ra.values.values()), list(rb.values.values()))
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
    from rubberfriction.driver.scenes import load_scene

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
    task = SimpleNamespace(label={"point": "c/p=0.3/v=10", "branch": "up", "scale_name": "meso",
                                  "sample": 1})
    now[0] = 10.0
    p.update(task, SimpleNamespace(status="ok", reused=False, wall_time=10.0))
    p.update(task, SimpleNamespace(status="failed", reused=False, wall_time=10.0))
    # reused: costs nothing
    p.update(task, SimpleNamespace(status="ok", reused=True, wall_time=99.0))
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


def test_progress_counts_runs_left_out_of_the_averages():
    """A successful run the campaign leaves out (unconverged, over-stabilised) stops its point
    like a failure: the status lines count it, a terminal names it, and the end line says how
    many planned runs were not needed."""
    import io
    from types import SimpleNamespace

    from rubberfriction.driver.runtime.progress import Progress

    def why(outcome):
        return "" if outcome.converged else "no stationary window within the sliding budget"

    task = SimpleNamespace(label={"point": "c/p=0.3/v=100", "branch": "down",
                                  "scale_name": "micro1", "sample": 0})
    for tty in (False, True):
        out = io.StringIO()
        p = Progress(stream=out, min_interval=0.0, clock=lambda: 5.0, tty=tty, unusable=why)
        p.start(6, 1)
        p.update(task, SimpleNamespace(status="ok", reused=False, wall_time=1.0, converged=True))
        assert "left out" not in out.getvalue()
        p.update(task, SimpleNamespace(status="ok", reused=False, wall_time=1.0, converged=False))
        p.update(task, SimpleNamespace(status="failed", reused=False, wall_time=1.0,
                                       converged=False))  # a failure is not also left out
        assert (p.failed, p.left_out) == (1, 1)
        text = out.getvalue()
        last = text.splitlines()[-1]
        assert ("failed 1, left out 1" if tty else "failed 1  left out 1  elapsed") in last
        assert ("left out: micro1 down #0: no stationary window" in text) == tty
        p.finish()
        end = out.getvalue().splitlines()[-1]
        assert "(3 computed, 0 reused, 1 failed, 1 left out (unconverged or over-stabilised))" \
            in end and "3 of 6 planned runs not needed" in end


def test_a_run_stopped_at_its_time_limit_is_a_timeout_and_the_campaign_goes_on(
        tmp_path: Path, monkeypatch):
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


# ----------------------------------------------------------------------------------------------
# progress inside runs and the time estimate (constructed data: the oracles are hand sums)
# ----------------------------------------------------------------------------------------------


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_cost_estimate_uses_the_same_group_then_the_same_scale_then_the_model():
    from rubberfriction.driver.runtime.progress import CostEstimate

    est = CostEstimate()
    assert math.isnan(est.expect(("up", "micro2"), 10.0))  # nothing finished yet
    est.observe(("down", "macro"), 1.0, 12.0)
    est.observe(("down", "macro"), 1.0, 8.0)
    est.observe(("up", "micro2"), 50.0, 400.0)
    assert est.expect(("down", "macro"), 1.0) == pytest.approx(10.0)  # mean of its group
    assert est.expect(("up", "macro"), 1.0) == pytest.approx(10.0)  # same scale, other branch
    assert est.expect(("down", "micro2"), 50.0) == pytest.approx(400.0)
    # no run of micro1 yet: weight x (12 + 8 + 400) s / (1 + 1 + 50)
    assert est.expect(("up", "micro1"), 20.0) == pytest.approx(20.0 * 420.0 / 52.0)


def _cascade_plan():
    """One point, four stages run one after another: macro (weight 1) and micro2 (weight 50)."""
    from rubberfriction.driver.runtime.progress import Stage

    pid = "c/p=0.3/v=100"
    return pid, [Stage(pid, (pid, "down", 0), ("down", "macro"), 2, 1.0),
                 Stage(pid, (pid, "down", 1), ("down", "micro2"), 2, 50.0),
                 Stage(pid, (pid, "up", 1), ("up", "micro2"), 2, 50.0),
                 Stage(pid, (pid, "up", 0), ("up", "macro"), 2, 1.0)]


def _task(pid: str, branch: str, scale: int, name: str, sample: int) -> Task:
    label = {"point": pid, "branch": branch, "scale": scale, "scale_name": name,
             "sample": sample, "velocity": 100.0}
    return Task(f"{branch}{scale}{sample}".ljust(64, "0"), None, label)


def test_time_left_weighs_the_runs_left_by_scale_and_follows_the_cascade():
    """After the first (cheap) macro runs the estimate must see the dear micro2 runs to come and
    that the cascade runs its stages one after another, whatever the number of workers."""
    from types import SimpleNamespace

    from rubberfriction.driver.runtime.progress import Progress

    import io

    pid, plan = _cascade_plan()
    clock = FakeClock()
    p = Progress(stream=io.StringIO(), min_interval=0.0, clock=clock, tty=False)
    p.start(8, 4, plan)
    assert math.isnan(p.eta())
    for s in (0, 1):
        p.update(_task(pid, "down", 0, "macro", s), SimpleNamespace(status="ok", reused=False,
                                                                    wall_time=10.0))
    # micro2 by the model: 50 x (20 s / 2) = 500 s a run; macro up like macro down: 10 s.
    # work 2 x 500 + 2 x 500 + 2 x 10 = 2020 s over 4 workers = 505 s; the chain of the
    # three stages left, 500 + 500 + 10 = 1010 s, is longer
    assert p.eta() == pytest.approx(1010.0)
    # the old estimate (runs left x mean run time / workers) said 6 x 10 / 4 = 15 s
    # two micro2 runs in flight: one reported at clock 100 (distance 3/4 done, 40 s left), one
    # only its set-up at clock 0
    clock.now = 0.0
    p.running(_task(pid, "down", 1, "micro2", 1), {"phase": "set-up"})
    t = _task(pid, "down", 1, "micro2", 0)
    p.running(t, {"phase": "set-up"})
    clock.now = 100.0
    p.running(t, {"phase": "sliding", "distance": 3.0, "slide_distance": 4.0, "left": 40.0})
    clock.now = 110.0
    # t: 3/4 x (40 - 10) + 1/4 x (500 - 110) = 120 s; the other: 500 - 110 = 390 s
    # chain: max(120, 390) + 500 + 10 = 900 s; work (120 + 390 + 1000 + 20) / 4 = 382.5 s
    assert p.eta() == pytest.approx(900.0)
    p.update(t, SimpleNamespace(status="ok", reused=False, wall_time=120.0))
    assert t.key not in p.in_flight and p.left[(pid, "down", 1)] == 1
    # micro2 down now measured (120 s): the one in flight 120 - 110 -> 10 s, micro2 up by the
    # same scale 120 s: chain 10 + 120 + 10 = 140 s, work (10 + 240 + 20) / 4 = 67.5 s
    assert p.eta() == pytest.approx(140.0)


def test_progress_line_shows_the_runs_in_flight_on_a_tty_and_in_plain_lines(monkeypatch):
    import io
    from types import SimpleNamespace

    from rubberfriction.driver.runtime.progress import Progress

    monkeypatch.setenv("COLUMNS", "200")  # the terminal width the TTY line is cut to
    pid, plan = _cascade_plan()
    clock = FakeClock()
    tty = io.StringIO()
    p = Progress(stream=tty, min_interval=1.0, clock=clock, tty=True)
    p.start(8, 2, plan)
    task = _task(pid, "down", 1, "micro2", 0)
    info = {"phase": "sliding", "step": 84, "steps": 240, "distance": 0.42,
            "slide_distance": 1.2, "cutbacks": 3, "after": "", "left": 130.0}
    p.running(task, info)
    out = tty.getvalue()
    assert out.count("\n") == 1 and out.endswith("\x1b[K")  # the start line, then in place
    line = out.rsplit("\r", 1)[-1]
    assert line.startswith("[0/8]    0%  0s, left ~?  | micro2 down #0 v=100: 0.42/1.2 mm, "
                           "step 84/240, 3 cut-backs, ~2m10s  | computed 0, reused 0, failed 0")
    clock.now = 0.5
    p.running(task, dict(info, step=85))
    assert tty.getvalue() == out  # at most one redraw a second
    clock.now = 1.0
    p.running(task, dict(info, step=90, after="mortar", cutbacks=1))
    assert "step 90/240, 1 cut-back," in tty.getvalue() and "(after mortar failed)" in \
        tty.getvalue()
    clock.now = 2.0
    p.running(task, dict(info, step=91, stabilised=4))
    assert "step 91/240, 3 cut-backs, 4 stabilised, ~" in tty.getvalue()
    p.update(task, SimpleNamespace(status="failed", reused=False, wall_time=5.0,
                                   failure="timeout", reason="wall-time limit of 600 s\nmore"))
    assert "\r\x1b[Kfailed: micro2 down #0 v=100: wall-time limit of 600 s\n" in tty.getvalue()
    p.finish()
    assert tty.getvalue().endswith("1 failed, 1 stopped by the wall clock) in 2s; 7 of 8 planned "
                                   "runs not needed (their point stopped at a failed scale)\n")

    plain = io.StringIO()
    q = Progress(stream=plain, min_interval=1.0, plain_interval=30.0, clock=clock, tty=False)
    clock.now = 0.0
    q.start(8, 2, plan)
    for now in (0.0, 10.0, 29.0, 31.0, 45.0):
        clock.now = now
        q.running(task, info)
    lines = plain.getvalue().splitlines()
    assert len(lines) == 3 and "\r" not in plain.getvalue()  # start, at 0 s and at 31 s
    assert "elapsed 31s" in lines[-1] and "running: micro2 down #0" in lines[-1]

    from rubberfriction.driver.runtime.progress import run_name

    assert run_name({"scale_name": "micro", "branch": "micro", "sample": 3, "velocity": 500.0,
                     "velocity_in": 250.0}) == "micro micro #3 v=250"
    quiet = io.StringIO()
    r = Progress(quiet=True, stream=quiet, tty=True)
    r.start(8, 2, plan)
    r.running(task, info)
    r.update(task, SimpleNamespace(status="ok", reused=False, wall_time=1.0))
    r.finish()
    assert quiet.getvalue() == ""


def test_run_reports_pass_phase_changes_and_one_report_a_second():
    from rubberfriction.driver.runtime.farm import RunReports

    clock = FakeClock()
    got: list[tuple[str, dict]] = []
    reports = RunReports(min_interval=1.0, clock=clock)
    reports({"phase": "set-up"})  # not connected, no task: nothing
    reports.sink = lambda task, info: got.append((task.key, info))
    task = Task("ab" * 32, None, {})
    reports.begin(task)
    for now, phase in ((0.0, "set-up"), (0.1, "sliding"), (0.5, "sliding"), (1.2, "sliding"),
                       (1.3, "set-up"), (1.4, "sliding")):
        clock.now = now
        reports({"phase": phase, "at": now})
    assert [info["at"] for _, info in got] == [0.0, 0.1, 1.2, 1.3, 1.4]
    reports.end()
    reports({"phase": "later"})
    assert len(got) == 5

    def broken(task, info):
        raise BrokenPipeError("gone")

    reports.sink = broken
    reports.begin(task)
    with pytest.warns(UserWarning, match="progress reports stopped"):
        reports({"phase": "set-up"})
    assert reports.sink is None


def test_step_reporter_says_where_a_sliding_run_is():
    from types import SimpleNamespace

    from rubberfriction.driver.sliding.progress import StepReporter

    clock = FakeClock()
    got: list[dict] = []
    rep = StepReporter(got.append, clock=clock)
    run = SimpleNamespace(spec=SimpleNamespace(velocity=2.0), t_start=1.0, slide_distance=4.0,
                          n_slide_steps=8, cutbacks=0)
    clock.now = 5.0
    rep.on_start(run)
    assert got[-1]["phase"] == "sliding" and got[-1]["distance"] == 0.0
    assert math.isnan(got[-1]["left"])
    clock.now = 15.0
    run.cutbacks, run.stabilised_steps = 3, 2
    rep.on_step(run, 4, 2.0)  # 2 mm/s x 1 s = 2 mm of 4 in 10 s: 10 s left
    assert got[-1] == {"phase": "sliding", "step": 4, "steps": 8, "distance": 2.0,
                       "slide_distance": 4.0, "cutbacks": 3, "stabilised": 2, "after": "",
                       "left": 10.0}
    failed = SimpleNamespace(ok=False, stats={"attempt": "mortar", "cutbacks": 9})
    rep.on_finish(run, failed)
    assert got[-1] == {"phase": "set-up", "after": "mortar", "cutbacks": 9}
    n = len(got)
    rep.on_finish(run, SimpleNamespace(ok=False, stats={"failure": "wall_limit"}))
    rep.on_finish(run, SimpleNamespace(ok=True, stats={}))
    assert len(got) == n  # no next attempt follows these
    rep.on_start(run)
    assert got[-1]["after"] == "mortar"


def test_serial_farm_routes_run_reports_to_the_progress():
    from rubberfriction.driver.runtime.farm import RunReports

    class Recorder:
        def __init__(self) -> None:
            self.events: list[tuple] = []

        def start(self, total, workers, plan=None):
            self.events.append(("start", total, workers, len(plan)))

        def running(self, task, info):
            self.events.append(("running", task.label["sample"], info.get("step")))

        def update(self, task, outcome):
            self.events.append(("done", task.label["sample"]))

        def finish(self):
            self.events.append(("finish",))

    reports = RunReports(min_interval=0.0)

    def runner(spec):
        for k in (1, 2):
            reports({"phase": "sliding", "step": k})
        return SlidingResult("ok", mu_force=0.1, stats={"steps": 2})

    import tempfile

    tasks = [Task(f"{i:064x}", {"i": i}, {"point": "p", "branch": "b", "scale": 0, "sample": i})
             for i in range(2)]
    rec = Recorder()
    with tempfile.TemporaryDirectory() as d:
        ex = Executor(Store(d), runner, reports=reports)
        run_serial(StaticPlanner(tasks), ex, rec)
        assert ex.reports.sink is None  # disconnected after the campaign
    assert rec.events == [("start", 2, 1, 1),
                          ("running", 0, None), ("running", 0, 1), ("running", 0, 2),
                          ("done", 0),
                          ("running", 1, None), ("running", 1, 1), ("running", 1, 2),
                          ("done", 1), ("finish",)]


@pytest.mark.mpi
def test_mpi_workers_report_their_runs_to_rank_0(tmp_path: Path):
    """Reports of runs on rank 1 reach the progress object on rank 0 in order, before the run's
    outcome, and none is lost (rate limit off here)."""
    script = tmp_path / "reports.py"
    script.write_text(textwrap.dedent('''
        import json, sys, time
        sys.path.insert(0, ROOT)
        from mpi4py import MPI
        from rubberfriction.driver.runtime.farm import (Executor, RunReports, StaticPlanner,
                                                        Task, run_farm)
        from rubberfriction.driver.runtime.progress import Progress
        from rubberfriction.driver.runtime.store import Store
        from rubberfriction.driver.sliding.spec import SlidingResult

        class Recorder(Progress):
            def __init__(self):
                super().__init__(quiet=True)
                self.seen, self.order = {}, []
            def running(self, task, info):
                super().running(task, info)
                self.seen.setdefault(task.key, []).append(info.get("step"))
                self.order.append(("report", task.key))
            def update(self, task, outcome):
                super().update(task, outcome)
                self.order.append(("done", task.key))

        reports = RunReports(min_interval=0.0)
        def runner(spec):
            for k in range(1, 6):
                reports({"phase": "sliding", "step": k, "distance": k, "slide_distance": 5})
                time.sleep(0.01)
            return SlidingResult("ok", mu_force=float(MPI.COMM_WORLD.rank), stats={"steps": 5})

        tasks = [Task(f"{i:064x}", {"i": i}, {"point": "p", "branch": "b", "scale": 0,
                                              "sample": i}) for i in range(8)]
        rec = Recorder() if MPI.COMM_WORLD.rank == 0 else None
        planner, out = run_farm(lambda: StaticPlanner(tasks), Executor(Store(sys.argv[1]),
                                runner, reports=reports), rec)
        if rec is not None:
            last = {key: i for i, (what, key) in enumerate(rec.order) if what == "report"}
            done = {key: i for i, (what, key) in enumerate(rec.order) if what == "done"}
            print("RESULT", json.dumps({"ranks": {k: o.values["mu_force"] for k, o in out.items()},
                                        "seen": rec.seen,
                                        "before": all(last[k] < done[k] for k in done)}))
    ''').replace("ROOT", repr(str(ROOT))))
    r = subprocess.run(["mpirun", "-n", "2", sys.executable, str(script), str(tmp_path / "s")],
                       env=_env(), capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr + r.stdout
    import json

    res = json.loads([ln for ln in r.stdout.splitlines() if ln.startswith("RESULT")][0][7:])
    assert len(res["ranks"]) == 8 and 1.0 in res["ranks"].values()  # rank 1 ran some
    assert all(res["seen"][k] == [None, 1, 2, 3, 4, 5] for k in res["ranks"])  # set-up, steps
    assert res["before"]


def test_idle_naps_spin_after_an_event_then_double_up_to_the_poll(monkeypatch):
    """The dispatcher's (and a waiting worker's) idle sleeps: none for SPIN s after an event,
    then MIN_NAP doubling up to QUICK_NAP until QUICK_WINDOW s after it, then up to poll."""
    from types import SimpleNamespace

    from rubberfriction.driver.runtime import farm

    clock, slept = FakeClock(), []

    def sleep(s: float) -> None:
        slept.append(s)
        clock.now += s

    monkeypatch.setattr(farm, "time", SimpleNamespace(monotonic=clock, sleep=sleep))
    nap = farm._Nap(poll=0.02)
    clock.now = 0.5 * farm.SPIN
    nap.sleep()
    assert slept == []  # spinning: poll again at once
    clock.now = farm.SPIN
    for _ in range(12):
        nap.sleep()
    quick = [min(farm.MIN_NAP * 2 ** k, farm.QUICK_NAP) for k in range(12)]
    assert slept[0] == 0.0 and slept[1:] == pytest.approx(quick[:11])
    clock.now = farm.QUICK_WINDOW
    slept.clear()
    for _ in range(8):
        nap.sleep()
    assert slept == pytest.approx([0.001, 0.002, 0.004, 0.008, 0.016, 0.02, 0.02, 0.02])
    nap.event()
    slept.clear()
    clock.now += 2 * farm.SPIN
    nap.sleep()
    assert slept == [0.0]  # back to short naps after an event


class _Stages:
    """Stages of (key, duration); a stage is handed out when the one before is recorded."""

    def __init__(self, stages: list[list[tuple[str, float]]]):
        self.stages = [list(s) for s in stages]
        self.durations = {k: d for s in stages for k, d in s}
        self._left = 0

    def total(self) -> int:
        return sum(len(s) for s in self.stages)

    def next_tasks(self) -> list[Task]:
        if self._left or not self.stages:
            return []
        stage = self.stages.pop(0)
        self._left = len(stage)
        return [Task(k, k) for k, _ in stage]

    def record(self, task: Task, outcome: Outcome) -> None:
        self._left -= 1


def test_replay_schedules_stages_in_hand_out_order_on_n_workers():
    """Hand-computed schedules of the farm's rule (a free worker takes the next ready task in the
    order handed out; a stage starts when the stage before has finished): stage 1 lasts 3, 1, 1 s
    and stage 2 2, 2 s: 9 s on one worker, 5 s on two (a | b, c), 5 s on three (the critical path
    3 + 2); handed out as 1, 1, 3 the long run starts late on two workers: 1 + 3 + 2 = 6 s.  A
    key handed out twice in a stage runs once."""
    from rubberfriction.driver.runtime.farm import replay

    def outcome_of(durations):
        return lambda task: (Outcome(task.key, "ok"), durations[task.key])

    stages = [[("a", 3.0), ("b", 1.0), ("c", 1.0)], [("d", 2.0), ("e", 2.0)]]
    for workers, makespan in ((1, 9.0), (2, 5.0), (3, 5.0)):
        p = _Stages(stages)
        r = replay(p, outcome_of(p.durations), workers)
        assert (r.makespan, r.busy, r.runs) == (makespan, 9.0, 5)
    assert math.isclose(r.efficiency, 9.0 / 15.0)
    late = [[("b", 1.0), ("c", 1.0), ("a", 3.0)], [("d", 2.0), ("e", 2.0)]]
    p = _Stages(late)
    assert replay(p, outcome_of(p.durations), 2).makespan == 6.0
    p = _Stages([[("a", 3.0), ("a", 3.0), ("b", 1.0)]])
    r = replay(p, outcome_of(p.durations), 2)
    assert (r.makespan, r.busy, r.runs) == (3.0, 4.0, 2)
    with pytest.raises(ValueError, match="at least 1"):
        replay(_Stages(stages), outcome_of(p.durations), 0)


def test_bench_farm_replays_a_finished_campaign_from_its_store(tmp_path: Path, toy):
    """The scene's own planner over the stored runs: one rank takes the sum of the stored wall
    times exactly; more ranks never take longer than fewer, nor less than the critical path; a
    store of another code version (part of every run key) replays with the keys of its own; a
    run missing from the store is named."""
    import rubberfriction
    from rubberfriction.driver.bench.farm import UNLIMITED, MissingRun, main, replay_folder
    from rubberfriction.driver.multiscale.campaign import run_scene
    from rubberfriction.driver.scenes import load_scene

    (tmp_path / "scene.toml").write_text(SCENE)
    out = tmp_path / "out"
    with pytest.MonkeyPatch.context() as mp:  # an older release computed this campaign
        mp.setattr(rubberfriction, "__version__", "0.0.1")
        r = run_scene(load_scene(str(tmp_path / "scene.toml")), output=out, runner=toy,
                      quiet=True)
    store = Store(out / "store")
    total = sum(store.outcome(k).wall_time for k in store.keys())
    rows = replay_folder(out, [1, 2, 4, UNLIMITED], tmp_path / "scene.toml")
    assert [x.runs for x in rows] == [r.n_runs] * 4 and r.n_runs == 52
    assert math.isclose(rows[0].makespan, total, rel_tol=1e-12)
    spans = [x.makespan for x in rows]
    assert spans == sorted(spans, reverse=True) and spans[-1] > 0
    assert main([str(out), "--ranks", "1,2", "--scene", str(tmp_path / "scene.toml")]) == 0
    victim = next(iter(store.keys()))
    next((out / "store" / "runs").rglob(f"{victim}.h5")).unlink()
    with pytest.raises(MissingRun, match=victim[:12]):
        replay_folder(out, [2], tmp_path / "scene.toml")
