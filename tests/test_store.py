"""Campaign store: keys follow the inputs exactly, runs are stored atomically with provenance,
failures keep their reason, and the query API finds what a campaign stored.

The stored "results" here are made-up SlidingResults: these tests check bookkeeping, not physics.
"""

from __future__ import annotations

import dataclasses
import os
import socket
from pathlib import Path

import h5py
import numpy as np
import pytest

from rubberfriction.driver.runtime.farm import Executor, Task
from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec
from rubberfriction.driver.runtime.store import (Store, StoreError, canonical, canonical_json,
                                                 run_key)
from rubberfriction.forms.material_files import load_compound


@pytest.fixture(scope="module")
def spec() -> SlidingSpec:
    x = np.linspace(0.0, 1.0, 32, endpoint=False)
    return SlidingSpec(surface_x=x, surface_h=0.01 * np.sin(2 * np.pi * x), period=1.0,
                       pressure=0.3,
                       velocity=100.0, compound=load_compound("tread_default"))


def result(mu: float = 0.1, status: str = "ok") -> SlidingResult:
    t = np.linspace(0.0, 1.0, 7)
    return SlidingResult(status, reason="" if status == "ok" else "sliding: no convergence after 8 "
                                                                  "cut-backs",
                         t_reached=1.0, series={"t": t, "Fx": -mu * np.ones(7), "Fz": np.ones(7)},
                         mu_force=mu if status == "ok" else float("nan"), mu_energy=0.9 * mu,
                         mean_pressure=0.41, contact_fraction=0.7,
                         dissipation_by_depth=(np.linspace(0, 1, 4), np.arange(4.0)),
                         stats={"cutbacks": 2, "contact_formulation": "nts", "wall_time": 1.5,
                                "attempt": "nts x2 mesh"})


def test_key_follows_every_input(spec: SlidingSpec):
    k = run_key(spec)
    assert len(k) == 64 and run_key(dataclasses.replace(spec)) == k  # same inputs, same key
    x2 = spec.surface_h.copy()
    x2[3] = np.nextafter(x2[3], 1.0)  # one ulp of one surface point
    changed = [
        dataclasses.replace(spec, surface_h=x2),
        dataclasses.replace(spec, pressure=0.3000000000000001),
        dataclasses.replace(spec, friction=0.2),
        dataclasses.replace(spec, temperature=293.15),
        dataclasses.replace(spec, compound=load_compound("m1")),
    ]
    c = spec.compound
    changed.append(dataclasses.replace(spec, compound=dataclasses.replace(
        c, prony=dataclasses.replace(c.prony, tau=c.prony.tau * (1 + 1e-12)))))
    keys = {run_key(s) for s in changed}
    assert k not in keys and len(keys) == len(changed)
    assert run_key(spec, version="0.0.0-other") != k  # the code version is part of the key


def test_canonical_serialisation():
    assert canonical({"b": 1, "a": [1.5, np.float64(0.1)]}) == {"a": [1.5, 0.1], "b": 1}
    assert canonical_json({"b": 1, "a": 2}) == canonical_json({"a": 2, "b": 1})
    a = np.arange(4.0)
    assert canonical(a) != canonical(a.astype(np.float32)) and canonical(a) == canonical(a.copy())
    assert canonical(float("nan")) == "nan"

    class Opaque:
        pass

    with pytest.raises(TypeError, match="cannot serialise .*Opaque canonically"):
        canonical(Opaque())


def test_put_and_load_round_trip_with_provenance(tmp_path: Path, spec: SlidingSpec):
    store = Store(tmp_path / "store")
    key = run_key(spec)
    label = {"point": "tread_default/p=0.3/v=100", "branch": "up", "scale": 2, "sample": 1}
    out = store.put(key, spec, result(0.123), wall_time=1.5, label=label, settings={"scene": "t"})
    assert out.ok and out.values["mu_force"] == 0.123 and not out.reused
    assert store.has(key) and store.keys() == [key] and len(store) == 1
    run = store.load(key)
    assert run.status == "ok" and run.values["mean_pressure"] == 0.41
    assert run.values["contact_fraction"] == 0.7
    np.testing.assert_array_equal(run.series["Fx"], -0.123 * np.ones(7))
    assert run.stats["cutbacks"] == 2 and run.stats["contact_formulation"] == "nts"
    # the fallback attempt that produced the result, fresh and reused alike (samples.csv column)
    assert out.attempt == store.outcome(key).attempt == run.outcome().attempt == "nts x2 mesh"
    assert run.label == label
    np.testing.assert_array_equal(run.dissipation_by_depth[1], np.arange(4.0))
    p = run.provenance
    assert p["code_version"] and p["host"] == socket.gethostname() and p["pid"] == os.getpid()
    assert p["wall_time"] == 1.5 and p["settings"] == {"scene": "t"} and "git_describe" in p
    np.testing.assert_array_equal(run.inputs["surface_h"], spec.surface_h)
    assert run.inputs["pressure"] == 0.3 and run.inputs["compound"] == "tread_default"
    assert store.outcome(key).reused and store.outcome("0" * 64) is None
    assert [r.key for r in store.query(status="ok", branch="up", scale=2)] == [key]
    assert store.query(branch="down") == [] and store.query(status="failed") == []
    exported = store.export(tmp_path / "all.h5")
    with h5py.File(exported, "r") as f:
        assert f[f"runs/{key}"].attrs["status"] == "ok"
        assert f[f"runs/{key}/results"].attrs["mu_force"] == 0.123


def test_write_is_atomic(tmp_path: Path, spec: SlidingSpec, monkeypatch):
    store = Store(tmp_path / "store")
    key = run_key(spec)
    # a crash between writing and renaming leaves nothing that counts as finished
    import rubberfriction.driver.runtime.store as store_mod

    def crash(src, dst):
        raise KeyboardInterrupt("killed while storing")

    monkeypatch.setattr(store_mod.os, "replace", crash)
    with pytest.raises(KeyboardInterrupt):
        store.put(key, spec, result(), wall_time=1.0)
    monkeypatch.undo()
    assert not store.has(key) and store.keys() == []
    assert not list(store.runs.rglob("*.tmp"))  # the temporary file was removed
    # a stray temporary file (process killed hard) is ignored too
    stray = store.path(key).parent / f".{key}.12345.tmp"
    stray.write_bytes(b"half an HDF5 file")
    assert not store.has(key) and store.keys() == []
    store.put(key, spec, result(), wall_time=1.0)
    assert store.has(key) and store.keys() == [key]


def wall_limit_result() -> SlidingResult:
    """What run_sliding returns when the run stopped itself at its wall-time limit."""
    return SlidingResult("failed", reason="wall-time limit of 600 s reached at t = 0.1 s (mortar)",
                         t_reached=0.1, stats={"failure": "wall_limit", "cutbacks": 3})


def test_failures_are_stored_with_reason_and_reused_or_retried(tmp_path: Path, spec: SlidingSpec):
    """Physics failures are results of the inputs (reused; retry_failed recomputes them); runs
    that raised or that the wall clock stopped are kept for the report but always recomputed."""
    store = Store(tmp_path / "store")
    calls = []

    def failing_run(s):
        calls.append(s)
        return result(status="failed")

    def raising_run(s):
        calls.append(s)
        raise MemoryError("out of memory in the linear solver")

    def slow_run(s):
        calls.append(s)
        return wall_limit_result()

    t1 = Task(run_key(spec), spec, {"sample": 0})
    spec2 = dataclasses.replace(spec, velocity=10.0)
    t2 = Task(run_key(spec2), spec2, {"sample": 1})
    spec3 = dataclasses.replace(spec, velocity=1.0)
    t3 = Task(run_key(spec3), spec3, {"sample": 2})
    o1 = Executor(store, failing_run)(t1)
    o2 = Executor(store, raising_run)(t2)
    o3 = Executor(store, slow_run)(t3)
    assert (o1.status, o1.failure) == ("failed", "physics") and "no convergence" in o1.reason
    assert (o2.status, o2.failure) == ("failed", "error") and "MemoryError" in o2.reason
    assert (o3.status, o3.failure) == ("failed", "timeout") and o3.timed_out
    assert not o1.timed_out and not o2.timed_out
    assert "out of memory" in store.load(t2.key).reason
    assert store.outcome(t3.key).timed_out and "wall-time limit" in store.load(t3.key).reason
    calls.clear()
    again = Executor(store, failing_run)
    assert again(t1).reused and calls == []  # a physics failure is a result of the inputs: reused
    assert not again(t2).reused and len(calls) == 1  # a run that raised is retried
    assert not again(t3).reused and len(calls) == 2  # so is one the wall clock stopped
    calls.clear()
    assert not Executor(store, failing_run, retry_failed=True)(t1).reused and len(calls) == 1


@pytest.mark.parametrize("failure, retry, reused", [
    ("", False, True), ("", True, True), ("physics", False, True), ("physics", True, False),
    ("error", False, False), ("error", True, False), ("timeout", False, False),
    ("timeout", True, False)])
def test_which_stored_runs_are_results_of_their_inputs(failure: str, retry: bool, reused: bool):
    from rubberfriction.driver.runtime.store import reusable_failure

    assert reusable_failure(failure, retry) is reused


def test_summary_says_how_many_runs_the_wall_clock_stopped(tmp_path: Path):
    from rubberfriction.driver.multiscale.campaign import CampaignResult
    from rubberfriction.driver.multiscale.report import summary_text
    from rubberfriction.driver.scenes import parse_scene
    from rubberfriction.driver.runtime.store import Outcome

    scene = parse_scene('name = "t"\n[surface]\nsource = "sines"\namplitudes = [0.01]\n'
                        'wavelengths = [5.0]\n', "<test>", tmp_path)
    kinds = ["", "physics", "timeout", "error", "timeout"]
    outcomes = {f"{i:064x}": Outcome(f"{i:064x}", "ok" if not k else "failed", failure=k)
                for i, k in enumerate(kinds)}

    def summary(outs: dict) -> str:
        return summary_text(CampaignResult(scene, tmp_path, [], outs, None, 1.0, 1, "now",
                                           Store(tmp_path / "store")))

    r = CampaignResult(scene, tmp_path, [], outcomes, None, 1.0, 1, "now", Store(tmp_path / "s"))
    assert (r.n_failed, r.n_timed_out) == (4, 2) and r.provenance()["runs_timed_out"] == 2
    text = summary(outcomes)
    assert "5 single-scale runs (0 reused, 4 failed)" in text
    assert "2 runs stopped by the wall clock (run_timeout); they are recomputed on the next run" \
        in text
    one = {k: o for k, o in outcomes.items() if o.failure != "timeout" or k.endswith("2")}
    assert "1 run stopped by the wall clock (run_timeout); it is recomputed" in summary(one)
    none = {k: o for k, o in outcomes.items() if o.failure != "timeout"}
    assert "wall clock" not in summary(none)


def test_campaign_lock(tmp_path: Path):
    a, b = Store(tmp_path / "store"), Store(tmp_path / "store")
    a.lock()
    with pytest.raises(StoreError, match="in use by another campaign"):
        b.lock()
    a.unlock()
    b.lock()
    b.unlock()


def test_unreadable_run_file_is_reported(tmp_path: Path, spec: SlidingSpec):
    store = Store(tmp_path / "store")
    key = run_key(spec)
    store.path(key).parent.mkdir(parents=True)
    store.path(key).write_bytes(b"not hdf5")
    with pytest.raises(StoreError, match="unreadable"):
        store.load(key)


def test_a_failed_result_without_run_statistics_counts_as_an_error(tmp_path: Path,
                                                                   spec: SlidingSpec):
    """run_sliding returns exceptions as failed results with empty stats: retried on resume."""
    store = Store(tmp_path / "store")
    t = Task(run_key(spec), spec, {})
    o = Executor(store, lambda s: SlidingResult("failed", reason="RuntimeError: PETSc error 76"))(t)
    assert o.failure == "error"
    assert not Executor(store, lambda s: result())(t).reused  # retried, now ok


def test_bench_store_comparison_treats_failed_runs_nan_results_as_equal():
    """Serial and MPI stores of a campaign with a failed run (NaN results) compare identical;
    a real difference (a number against NaN, or two numbers) does not."""
    from rubberfriction.driver.bench.multiscale import _same_values

    nan = float("nan")
    assert _same_values({"mu_force": nan, "mean_pressure": 1.5},
                        {"mu_force": nan, "mean_pressure": 1.5})
    assert not _same_values({"mu_force": 0.5}, {"mu_force": nan})
    assert not _same_values({"mu_force": 0.5}, {"mu_force": 0.5 + 1e-15})
    assert not _same_values({"mu_force": 0.5}, {"mu_energy": 0.5})


def test_an_unstored_result_is_judged_as_the_campaign_judges_a_stored_one(tmp_path: Path):
    """result_outcome (benchmarks) gives the same Outcome values as Store.put, so
    statistics.usable refuses an over-stabilised run whichever way it came."""
    from rubberfriction.driver.multiscale.statistics import usable, why_unusable
    from rubberfriction.driver.runtime.store import result_outcome

    res = SlidingResult("ok", mu_force=0.3)
    res.stabilisation_share = 0.2
    stored = Store(tmp_path / "s").put("a" * 64, None, res, wall_time=1.0)
    free = result_outcome(res)
    assert free.values == stored.values and free.status == stored.status == "ok"
    assert not usable(free) and "stabilisation carried 20 %" in why_unusable(free)
    res.stabilisation_share = 0.01
    assert usable(result_outcome(res))
    assert not usable(result_outcome(SlidingResult("failed", reason="stagnated")))


def test_an_overstabilised_run_on_single_nodes_says_its_contact_is_unresolved():
    """The reason a campaign gives for an over-stabilised run: contact lost where at times no
    contact element carried the load, unresolved contact where the contact shrank below
    UNRESOLVED_CONTACT elements (SlidingResult.contact_elements, through the store like every
    result scalar), the stabilisation share otherwise; a usable run stays usable whatever its
    contact."""
    from rubberfriction.driver.multiscale.statistics import (UNRESOLVED_CONTACT, usable,
                                                             why_unusable)
    from rubberfriction.driver.runtime.store import result_outcome

    res = SlidingResult("ok", mu_force=0.3, stabilisation_share=0.97, contact_elements=1.2)
    assert UNRESOLVED_CONTACT == 2.0
    why = why_unusable(result_outcome(res))
    assert why.startswith("unresolved contact: at times 1.2 contact elements") and "97 %" in why
    res.contact_elements = 0.0  # the block lifted off: the dashpots held it
    assert why_unusable(result_outcome(res)).startswith("contact lost: at times no contact")
    res.contact_elements = 2.5
    assert why_unusable(result_outcome(res)).startswith("stabilisation carried 97 %")
    res.stabilisation_share, res.contact_elements = 0.01, 0.5
    assert usable(result_outcome(res))
