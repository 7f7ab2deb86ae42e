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
from rubberfriction.driver.runtime.store import Store, StoreError, canonical, canonical_json, run_key
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


def test_failures_are_stored_with_reason_and_reused_or_retried(tmp_path: Path, spec: SlidingSpec):
    store = Store(tmp_path / "store")
    calls = []

    def failing_run(s):
        calls.append(s)
        return result(status="failed")

    def raising_run(s):
        calls.append(s)
        raise MemoryError("out of memory in the linear solver")

    t1 = Task(run_key(spec), spec, {"sample": 0})
    spec2 = dataclasses.replace(spec, velocity=10.0)
    t2 = Task(run_key(spec2), spec2, {"sample": 1})
    o1 = Executor(store, failing_run)(t1)
    o2 = Executor(store, raising_run)(t2)
    assert (o1.status, o1.failure) == ("failed", "physics") and "no convergence" in o1.reason
    assert (o2.status, o2.failure) == ("failed", "error") and "MemoryError" in o2.reason
    assert "out of memory" in store.load(t2.key).reason
    calls.clear()
    again = Executor(store, failing_run)
    assert again(t1).reused and calls == []  # a physics failure is a result of the inputs: reused
    assert not again(t2).reused and len(calls) == 1  # a run that raised is retried
    calls.clear()
    assert not Executor(store, failing_run, retry_failed=True)(t1).reused and len(calls) == 1


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


def test_a_failed_result_without_run_statistics_counts_as_an_error(tmp_path: Path, spec: SlidingSpec):
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
    assert _same_values({"mu_force": nan, "mean_pressure": 1.5}, {"mu_force": nan, "mean_pressure": 1.5})
    assert not _same_values({"mu_force": 0.5}, {"mu_force": nan})
    assert not _same_values({"mu_force": 0.5}, {"mu_force": 0.5 + 1e-15})
    assert not _same_values({"mu_force": 0.5}, {"mu_energy": 0.5})
