"""Campaign store: every single-scale run kept by the hash of its inputs (HDF5, one file per run).

A single-scale run is a pure function of its :class:`~rubberfriction.driver.sliding.run.SlidingSpec`
(README, "Conventions").  The store turns that into bookkeeping:

* **key** = sha256 of a canonical serialisation of the run inputs: every SlidingSpec field
  (surface arrays by their bytes, the compound with its Mooney-Rivlin, Prony, WLF and thermal
  data, the friction law), the store schema and the code version ``rubberfriction.__version__``.
  Same inputs, same key, on any rank and in any campaign; a different material constant, sample
  or setting gives a different key.  A code change that alters results must bump the version
  (``rubberfriction/__init__.py`` and ``pyproject.toml``): a store made by older code is otherwise
  reused (``--fresh`` recomputes everything).
* **layout** (a directory, ``<output>/store``)::

      store/
        runs/<key[:2]>/<key>.h5     one HDF5 file per finished run (status ok or failed)
        .lock                       campaign lock (fcntl; released when the process dies)

  and inside a run file::

      /                 attrs: key, status ("ok" | "failed"),
                        failure ("" | "physics" | "error" | "timeout"),
                        reason, schema, code_version, git_describe, host, pid, created, wall_time,
                        label (JSON: campaign, point, branch, scale, sample)
      /inputs           attrs: spec (canonical JSON, arrays as sha256), pressure, velocity, ...
        surface_x, surface_h
      /results          attrs: mu_force, mu_energy, mean_pressure, contact_fraction, t_reached
        series/<name>   time series (t, s, Fx, Fz, contact_length, energies, mean_pressure,
                        mu_force)
        stats           attrs: cutbacks, newton_iterations, steps, wall_time, attempt (the
                        fallback that gave the result, e.g. "nts x2 mesh"), ...
        dissipation_by_depth/z, /d   (when the run gives it)
      /state            the run's final state when it kept one (``SlidingSpec.keep_state``:
                        the thermal loop's warm starts), fields as datasets and attrs

* **atomic**: a run is written to a temporary file in the same folder, flushed and fsync'ed and
  then renamed onto ``<key>.h5`` (``os.replace``, atomic on POSIX).  A file named ``<key>.h5``
  is therefore always complete; a campaign killed while writing leaves at most a stray
  ``.tmp`` file, never a half-written run that counts as finished, and it cannot damage runs
  already stored.  (One shared HDF5 file cannot promise that: HDF5 is not crash-safe, a kill
  during a metadata update can make the whole file unreadable.)  Several processes may write
  different runs at the same time without a lock -- this is what lets every MPI rank store its
  own finished runs the moment they finish (:mod:`.farm`).
* **failures** are stored like results, with their reason, and the report shows them.  Whether
  a stored failure is reused depends on whether it is a result of the inputs
  (:func:`reusable_failure`):

  - ``failure = "physics"``: the run returned ``status="failed"`` (no convergence after
    cut-backs and fallbacks, distortion).  A result of the inputs: reused on resume
    (``--retry-failed`` recomputes it).
  - ``failure = "error"``: the run raised (a bug, a missing module, memory).  Says nothing about
    the inputs: kept for the report, recomputed on the next campaign.
  - ``failure = "timeout"``: the wall clock stopped the run -- it reached the scene's
    ``run_timeout`` and stopped itself, or the watchdog killed it (hung).  Where the clock
    stops a run depends on the machine and its load, not on the inputs, so it is not a result
    either: kept for the report ("N runs stopped by the wall clock"), recomputed on the next
    campaign.

Query API: :meth:`Store.has`, :meth:`Store.outcome` (scalars only, cheap),
:meth:`Store.load` (everything), :meth:`Store.keys`, :meth:`Store.query` (by status and label),
:meth:`Store.export` (all runs into one HDF5 file for sharing).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import enum
import fcntl
import functools
import hashlib
import json
import math
import os
import socket
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

import h5py
import numpy as np

import rubberfriction

#: Bump when the canonical serialisation or the file layout changes (changes every key).
#: 2: classes enter keys by qualified name without their module (1: with the module path).
STORE_SCHEMA = 2

#: Scalar results every run file carries (NaN when the run failed).
RESULT_SCALARS = ("mu_force", "mu_energy", "mean_pressure", "contact_fraction", "t_reached",
                  "window_drift", "mu_error", "converged", "stabilisation_share", "min_det_F",
                  "road_intrusion", "contact_drift", "contact_error", "contact_elements",
                  "mu_interface")


class StoreError(RuntimeError):
    """The store folder is unusable (locked by another campaign, unreadable run file, ...)."""


# ----------------------------------------------------------------------------------------------
# canonical serialisation and keys
# ----------------------------------------------------------------------------------------------


def _array_digest(a: np.ndarray) -> dict[str, Any]:
    a = np.ascontiguousarray(a)
    if a.dtype.byteorder == ">":
        a = a.astype(a.dtype.newbyteorder("<"))
    return {"__ndarray__": a.dtype.str, "shape": list(a.shape),
            "sha256": hashlib.sha256(a.tobytes()).hexdigest()}


def canonical(obj: Any) -> Any:
    """A JSON-ready, order-independent image of ``obj`` that changes whenever its value does.

    Floats keep their exact value (Python's shortest round-trip repr), numpy arrays enter by
    dtype, shape and sha256 of their bytes, dataclasses by their class name (no module) and all
    fields (sorted), mappings by sorted keys.  Objects that are none of these must provide
    ``canonical_state()`` or ``to_dict()``; anything else raises ``TypeError`` -- a run whose
    inputs cannot be written down cannot be keyed, and guessing (e.g. ``repr``) could make two
    different runs share a key.
    """
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, bool):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return v
    if isinstance(obj, np.ndarray):
        return _array_digest(obj)
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, enum.Enum):
        return f"{type(obj).__qualname__}.{obj.name}"
    if isinstance(obj, (list, tuple)):
        return [canonical(v) for v in obj]
    if isinstance(obj, dict):
        return {str(k): canonical(obj[k]) for k in sorted(obj, key=str)}
    if hasattr(obj, "canonical_state"):
        return {"__type__": _qualname(obj), "state": canonical(obj.canonical_state())}
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        fields = {f.name: canonical(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
        return {"__type__": _qualname(obj), **dict(sorted(fields.items()))}
    if hasattr(obj, "to_dict"):
        return {"__type__": _qualname(obj), "state": canonical(obj.to_dict())}
    raise TypeError(f"cannot serialise {type(obj).__qualname__} canonically for the store key; "
                    "give it a "
                    "canonical_state() or to_dict() method (or make it a dataclass)")


def _qualname(obj: Any) -> str:
    """The class name that enters a key: its qualified name without the module, so that moving a
    class to another module does not change the keys of the runs it is part of (schema 2)."""
    return type(obj).__qualname__


def canonical_json(obj: Any) -> str:
    """Compact JSON of :func:`canonical` with sorted keys (the hashed text)."""
    return json.dumps(canonical(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)


def code_version() -> str:
    """``rubberfriction.__version__`` (part of every key)."""
    return str(rubberfriction.__version__)


@functools.lru_cache(maxsize=1)
def git_describe() -> str:
    """``git describe --always --dirty`` of the source checkout, or "" (provenance only)."""
    root = Path(__file__).resolve().parents[1]
    if not (root / ".git").exists():
        return ""
    try:
        out = subprocess.run(["git", "-C", str(root), "describe", "--always", "--dirty", "--tags"],
                             capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return ""
    return out.stdout.strip() if out.returncode == 0 else ""


def run_key(spec: Any, version: str | None = None) -> str:
    """sha256 key of one run: canonical inputs + store schema + code version."""
    doc = {"spec": canonical(spec), "schema": STORE_SCHEMA,
           "code_version": code_version() if version is None else version}
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


# ----------------------------------------------------------------------------------------------
# records
# ----------------------------------------------------------------------------------------------


#: failure kinds that are results of the run's inputs (reused on resume unless retried)
INPUT_FAILURES = ("physics",)


def reusable_failure(failure: str, retry_failed: bool = False) -> bool:
    """Whether a stored run with this ``failure`` kind ("" = ok) is reused on resume.

    A success is always reused; a physics failure unless ``retry_failed``; a run that raised
    ("error") or that the wall clock stopped ("timeout") never: neither is a result of the
    inputs (see the module docstring).
    """
    if not failure:
        return True
    return failure in INPUT_FAILURES and not retry_failed


@dataclass
class Outcome:
    """What the campaign logic needs from a finished run (small, picklable, rank-independent)."""

    key: str
    status: str  # "ok" | "failed"
    reason: str = ""
    failure: str = ""  # "" | "physics" | "error" | "timeout"
    values: dict[str, float] = field(default_factory=dict)  # RESULT_SCALARS
    wall_time: float = 0.0
    reused: bool = False  # taken from the store, not computed in this campaign
    attempt: str = ""  # the fallback attempt that produced it (sliding stats "attempt")

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def timed_out(self) -> bool:
        """Stopped by the wall clock (``failure == "timeout"``): not a result of the inputs."""
        return self.failure == "timeout"

    def value(self, name: str) -> float:
        return float(self.values.get(name, math.nan))


def result_values(result: Any) -> dict[str, float]:
    """The RESULT_SCALARS of a SlidingResult (NaN where it has none)."""
    return {name: float(getattr(result, name, math.nan)) for name in RESULT_SCALARS}


def result_outcome(result: Any, key: str = "") -> Outcome:
    """The Outcome of a result that is not stored (benchmarks): what the campaign logic would
    see of it, e.g. for ``statistics.usable``."""
    status = str(getattr(result, "status", "failed"))
    return Outcome(key, status, str(getattr(result, "reason", "")),
                   "" if status == "ok" else "physics", result_values(result))


@dataclass
class StoredRun:
    """Everything a run file holds (see the module docstring for the layout)."""

    key: str
    status: str
    reason: str
    failure: str
    values: dict[str, float]
    series: dict[str, np.ndarray]
    stats: dict[str, Any]
    provenance: dict[str, Any]
    label: dict[str, Any]
    inputs: dict[str, Any]
    dissipation_by_depth: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def outcome(self, reused: bool = True) -> Outcome:
        return Outcome(self.key, self.status, self.reason, self.failure, dict(self.values),
                       float(self.provenance.get("wall_time", 0.0)), reused,
                       str(self.stats.get("attempt", "")))


def _attr(value: Any) -> Any:
    """An HDF5-storable attribute value."""
    if value is None:
        return "None"
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, float, str, np.integer, np.floating)):
        return value
    return json.dumps(canonical(value), sort_keys=True)


def _decode(value: Any) -> Any:
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


def spec_scalars(spec: Any) -> dict[str, Any]:
    """Readable scalar inputs of a SlidingSpec-like object (everything but arrays and objects)."""
    out: dict[str, Any] = {}
    if dataclasses.is_dataclass(spec):
        for f in dataclasses.fields(spec):
            v = getattr(spec, f.name)
            if v is None or isinstance(v, (bool, int, float, str, np.integer, np.floating)):
                out[f.name] = _attr(v)
            elif f.name == "compound":
                out["compound"] = str(getattr(v, "name", type(v).__name__))
            elif f.name == "friction":
                out["friction"] = (getattr(v, "describe", lambda: type(v).__name__)()
                                   if not isinstance(v, (int, float)) else float(v))
    return out


def _put_state(group: Any, state: Any) -> None:
    """A run's final state (a dataclass of arrays and scalars) into ``/state``."""
    for f in dataclasses.fields(state):
        v = getattr(state, f.name)
        if isinstance(v, np.ndarray):
            group.create_dataset(f.name, data=v)
        else:
            group.attrs[f.name] = _attr(v)


# ----------------------------------------------------------------------------------------------
# the store
# ----------------------------------------------------------------------------------------------


class Store:
    """A folder of run files keyed by :func:`run_key` (see the module docstring)."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.runs = self.root / "runs"
        self.runs.mkdir(parents=True, exist_ok=True)
        self._lock_fh = None

    # --- paths -----------------------------------------------------------------------------
    def path(self, key: str) -> Path:
        if len(key) != 64 or any(c not in "0123456789abcdef" for c in key):
            raise StoreError(f"not a run key: {key!r} (expected 64 hex digits)")
        return self.runs / key[:2] / f"{key}.h5"

    def has(self, key: str) -> bool:
        """True when a complete run file exists (ok or failed)."""
        return self.path(key).is_file()

    def keys(self) -> list[str]:
        return sorted(p.stem for p in self.runs.glob("??/*.h5"))

    def __len__(self) -> int:
        return len(self.keys())

    # --- campaign lock ---------------------------------------------------------------------
    def lock(self) -> None:
        """Take the campaign lock (one running campaign per store); StoreError if held elsewhere.

        fcntl locks die with their process, so a killed campaign never leaves a stale lock.
        """
        fh = open(self.root / ".lock", "a+")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.seek(0)
            holder = fh.read().strip()
            fh.close()
            raise StoreError(f"store {self.root} is in use by another campaign "
                             f"({holder or 'unknown'}); "
                             "wait for it or use another output folder") from None
        fh.seek(0)
        fh.truncate()
        fh.write(f"pid {os.getpid()} on {socket.gethostname()}\n")
        fh.flush()
        self._lock_fh = fh

    def unlock(self) -> None:
        if self._lock_fh is not None:
            fcntl.flock(self._lock_fh, fcntl.LOCK_UN)
            self._lock_fh.close()
            self._lock_fh = None

    # --- writing -----------------------------------------------------------------------------
    def put(self, key: str, spec: Any, result: Any, *, wall_time: float, label: dict | None = None,
            failure: str | None = None, settings: dict | None = None) -> Outcome:
        """Store one finished run atomically and return its :class:`Outcome`.

        ``result`` is a SlidingResult (status, reason, series, scalars, stats,
        dissipation_by_depth).  ``failure`` defaults to "physics" for a failed result; the farm
        passes "error" for a run that raised.
        """
        status = str(getattr(result, "status", "failed"))
        reason = str(getattr(result, "reason", ""))
        if failure is None:
            failure = "" if status == "ok" else "physics"
        values = result_values(result)
        target = self.path(key)
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{key}.", suffix=".tmp", dir=target.parent)
        os.close(fd)
        try:
            with h5py.File(tmp, "w") as f:
                f.attrs.update({
                    "key": key, "status": status, "reason": reason, "failure": failure,
                    "schema": STORE_SCHEMA, "code_version": code_version(),
                                "git_describe": git_describe(),
                    "host": socket.gethostname(), "pid": os.getpid(),
                                "created": _dt.datetime.now(_dt.timezone.utc).isoformat(),
                    "wall_time": float(wall_time),
                                "label": json.dumps(canonical(label or {}), sort_keys=True),
                    "settings": json.dumps(canonical(settings or {}), sort_keys=True),
                })
                g = f.create_group("inputs")
                if spec is not None:
                    g.attrs["spec"] = canonical_json(spec)
                    for k, v in spec_scalars(spec).items():
                        g.attrs[k] = v
                    for name in ("surface_x", "surface_h"):
                        if hasattr(spec, name):
                            g.create_dataset(name,
                                             data=np.asarray(getattr(spec, name), dtype=float))
                r = f.create_group("results")
                for k, v in values.items():
                    r.attrs[k] = v
                s = r.create_group("series")
                for name, arr in (getattr(result, "series", None) or {}).items():
                    s.create_dataset(name, data=np.asarray(arr, dtype=float))
                st = r.create_group("stats")
                for k, v in (getattr(result, "stats", None) or {}).items():
                    st.attrs[k] = _attr(v)
                dd = getattr(result, "dissipation_by_depth", None)
                if dd is not None:
                    d = r.create_group("dissipation_by_depth")
                    d.create_dataset("z", data=np.asarray(dd[0], dtype=float))
                    d.create_dataset("d", data=np.asarray(dd[1], dtype=float))
                state = getattr(result, "final_state", None)
                if state is not None and dataclasses.is_dataclass(state):
                    _put_state(f.create_group("state"), state)
                f.flush()
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
            os.replace(tmp, target)  # atomic: the key appears complete or not at all
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
        stats = getattr(result, "stats", None) or {}
        return Outcome(key, status, reason, failure, values, float(wall_time), False,
                       str(stats.get("attempt", "")))

    def remove(self, key: str) -> None:
        p = self.path(key)
        if p.exists():
            p.unlink()

    # --- reading -------------------------------------------------------------------------------
    def _open(self, key: str):
        p = self.path(key)
        try:
            return h5py.File(p, "r")
        except OSError as err:
            raise StoreError(f"run file {p} is unreadable ({err}); delete it to "
                             f"recompute the run") from None

    def outcome(self, key: str) -> Outcome | None:
        """Status, reason and scalar results of a stored run (None if absent)."""
        if not self.has(key):
            return None
        with self._open(key) as f:
            a = {k: _decode(v) for k, v in f.attrs.items()}
            values = {k: float(v) for k, v in f["results"].attrs.items()}
            stats = f["results"].get("stats")
            attempt = _decode(stats.attrs.get("attempt", "")) if stats is not None else ""
        return Outcome(key, a["status"], a.get("reason", ""), a.get("failure", ""), values,
                       float(a.get("wall_time", 0.0)), True, str(attempt))

    def load(self, key: str) -> StoredRun:
        """Everything stored for a run (KeyError if absent)."""
        if not self.has(key):
            raise KeyError(key)
        with self._open(key) as f:
            a = {k: _decode(v) for k, v in f.attrs.items()}
            res = f["results"]
            values = {k: float(v) for k, v in res.attrs.items()}
            series = {k: np.asarray(v[()]) for k, v in res["series"].items()}
            stats = {k: _decode(v) for k, v in res["stats"].attrs.items()}
            dd = None
            if "dissipation_by_depth" in res:
                dd = (np.asarray(res["dissipation_by_depth/z"][()]),
                      np.asarray(res["dissipation_by_depth/d"][()]))
            inputs = {k: _decode(v) for k, v in f["inputs"].attrs.items()}
            for name in ("surface_x", "surface_h"):
                if name in f["inputs"]:
                    inputs[name] = np.asarray(f["inputs"][name][()])
        label = json.loads(a.pop("label", "{}"))
        prov = {k: a[k] for k in ("schema", "code_version", "git_describe", "host", "pid",
                                  "created", "wall_time")
                if k in a}
        prov["settings"] = json.loads(a.get("settings", "{}"))
        return StoredRun(key, a["status"], a.get("reason", ""), a.get("failure", ""), values,
                         series, stats,
                         prov, label, inputs, dd)

    def load_state(self, key: str) -> dict[str, Any] | None:
        """The final state a run kept (``/state``: its fields, arrays as datasets, the rest as
        attributes; the sliding run's ``InitialState``), or None if the run has none."""
        if not self.has(key):
            return None
        with self._open(key) as f:
            if "state" not in f:
                return None
            g = f["state"]
            out: dict[str, Any] = {k: _decode(v) for k, v in g.attrs.items()}
            out.update({k: np.asarray(v[()]) for k, v in g.items()})
        return out

    def iter_runs(self) -> Iterator[StoredRun]:
        for key in self.keys():
            yield self.load(key)

    def query(self, status: str | None = None, **label: Any) -> list[StoredRun]:
        """Stored runs with the given status whose label has all the given items.

        ``store.query(status="ok", branch="up", scale=2)`` -> the friction-branch runs of scale 2.
        """
        out = []
        for run in self.iter_runs():
            if status is not None and run.status != status:
                continue
            if all(run.label.get(k) == v for k, v in label.items()):
                out.append(run)
        return out

    def export(self, path: str | Path, keys: list[str] | None = None) -> Path:
        """Copy runs (default: all) into one HDF5 file ``/runs/<key>/...`` for sharing."""
        path = Path(path)
        with h5py.File(path, "w") as out:
            out.attrs["schema"] = STORE_SCHEMA
            grp = out.create_group("runs")
            for key in keys if keys is not None else self.keys():
                with self._open(key) as f:
                    f.copy(f["/"], grp, name=key)
        return path
