"""One stored single-scale run of a campaign run again, with observers: the layer under
``rubberfriction rerun`` and ``rubberfriction run --fields``.

A stored run (``driver.runtime.store``) holds every input of its SlidingSpec;
:func:`~rubberfriction.driver.multiscale.specs.stored_spec` rebuilds it exactly (or refuses), and
:func:`rerun_spec` runs it the campaign's way (``driver.sliding.run.run_sliding``: the
closed-form shortcut where admitted, the fallback chain, failures as results) with the given
observers, e.g. a :class:`~rubberfriction.driver.sliding.outputs.FieldWriter` for ParaView.  The
run is deterministic: the same inputs on the same code give the stored mu_force again.  A run
the closed-form shortcut admitted (frictionless, full contact, small slopes) has no FE fields;
``fe=True`` computes it with the FE instead (then its mu is the FE's, not the stored closed
form's).  Serial (one process, ``MPI.COMM_SELF`` meshes like the campaign's workers).
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Any, Mapping, Sequence

from rubberfriction.driver.multiscale.specs import find_key, stored_spec
from rubberfriction.driver.runtime.store import Store, StoredRun


@dataclasses.dataclass
class Rerun:
    """A stored run and its rerun: ``stored`` (the run file), ``spec`` (rebuilt), ``result``
    (the new SlidingResult) and its wall time in s."""

    key: str
    stored: StoredRun
    spec: Any
    result: Any = None
    wall_time: float = 0.0
    #: the stored run is the closed form (shortcut) and the rerun is the FE run (``fe=True``)
    fe_instead_of_closed_form: bool = False


def store_root(folder: str | Path) -> Path:
    """The store of a campaign folder (``FOLDER/store``) or the folder itself."""
    folder = Path(folder)
    return folder / "store" if (folder / "store" / "runs").is_dir() else folder


def load_stored(store: Store, key: str, *, compound_dir: Path | None = None,
                compound_files: Mapping[str, str | Path] | None = None) -> Rerun:
    """The stored run of ``key`` (or a prefix of at least 6 characters) with its rebuilt spec;
    a ValueError naming the key or the field that cannot be rebuilt otherwise."""
    key = find_key(store, key)
    stored = store.load(key)
    spec = stored_spec(stored, compound_dir=compound_dir, states=store.load_state,
                       compound_files=compound_files)
    return Rerun(key, stored, spec)


def rerun_spec(spec: Any, observers: Sequence[Any] = (), *, first_attempt: bool = False
               ) -> tuple[Any, float]:
    """Run ``spec`` with ``observers`` the campaign's way (``run_sliding``), or only the first
    attempt of its fallback chain; returns (SlidingResult, wall time in s)."""
    from rubberfriction.driver.sliding.run import (SlidingRun, block_mesh, run_sliding,
                                                   sliding_contact)

    t0 = time.perf_counter()
    if first_attempt:
        run = SlidingRun(spec, block_mesh, sliding_contact, observers=list(observers))
        first = run.attempts()[0]
        run.attempts = lambda: [first]  # noqa: E731 (this run only)
        result = run.run()
    else:
        result = run_sliding(spec, observers=list(observers))
    return result, time.perf_counter() - t0


def shortcut_admits(spec: Any) -> bool:
    """Whether ``run_sliding`` takes the closed-form shortcut for ``spec`` (no FE run)."""
    from rubberfriction.driver.sliding import shortcut

    return bool(spec.shortcut) and shortcut.check(spec).admitted


def rerun_stored(store: Store, key: str, observers: Sequence[Any] = (), *,
                 compound_dir: Path | None = None,
                 compound_files: Mapping[str, str | Path] | None = None,
                 fe: bool = False) -> Rerun:
    """The stored run of ``key`` rebuilt (:func:`load_stored`) and run again as stored with
    ``observers`` (:func:`rerun_spec`); ``fe``: an FE run also where the stored one is the
    closed form (for fields)."""
    done = load_stored(store, key, compound_dir=compound_dir, compound_files=compound_files)
    spec = done.spec
    if fe and shortcut_admits(spec):
        spec = dataclasses.replace(spec, shortcut=False)
        done.fe_instead_of_closed_form = True
    done.result, done.wall_time = rerun_spec(spec, observers)
    return done
