"""Run independent single-scale runs serially or farmed over MPI ranks (mpi4py).

The campaign logic (:mod:`.homogenise`) is a *planner*: it hands out the tasks whose inputs are
known (``next_tasks()``) and is told every outcome (``record()``); new tasks become ready as
earlier ones finish (the pressure of scale i+1 needs all samples of scale i).  The farm drives a
planner to the end:

* **serial** (one rank): take a ready task, execute it, record it, repeat.
* **MPI** (``mpirun -n N``): dynamic load balancing with rank 0 as dispatcher.  A dispatcher
  thread on rank 0 owns the planner and answers requests; every rank, rank 0 included (its main
  thread), is a worker: it asks for a task, executes it, and sends the outcome with its next
  request.  Protocol on a private duplicate of ``COMM_WORLD``::

      worker -> 0   tag REQUEST  (outcome of the previous task or None)
      0 -> worker   tag TASK     (Task)  or  tag STOP (None)
      worker -> 0   tag PROGRESS ((key, report)) while a run goes on, at most ~1 a second

  The dispatcher polls with ``Iprobe`` (any tag, so a worker's reports come before its outcome)
  and sleeps when idle: not at all for 1 ms after an event, then from 10 us doubling up to 1 ms
  for 50 ms, then up to ``poll`` seconds (:class:`_Nap`): an answer is quick while requests
  come in and rank 0 costs almost no CPU while runs go on.  A worker waits for its next task
  the same way (a blocking receive would spin its core while it waits for the next stage of
  the cascade).  This needs
  ``MPI_THREAD_MULTIPLE`` (rank 0's worker runs PETSc on ``COMM_SELF`` while the dispatcher
  talks on the world communicator); with a lower thread level rank 0 only dispatches (one
  worker fewer) and says so.

*Executing* a task (:class:`Executor`) happens on the rank that got it: look the key up in the
store (a finished run is reused, not recomputed), otherwise run it on ``MPI.COMM_SELF`` (its own
communicator: a single-scale run never spans ranks), store it atomically from that rank and
return the small :class:`~rubberfriction.driver.runtime.store.Outcome`.  Storing on the worker
means a finished run is on disk the moment it finishes, whatever happens to the other ranks; the
store's one-file-per-run layout makes concurrent writers safe.  A run that raises is caught and
recorded as a failure (``failure="error"``, with the traceback); it never stops the campaign.

Progress inside runs: a runner may report where its run is (:class:`RunReports`: the sliding
runner's per-step dict); the farm routes the reports to the progress object on rank 0 --
directly when serial, through the dispatcher from rank 0's own worker, as small ``PROGRESS``
messages (rate-limited at the source to one a second plus phase changes) from the other ranks.

Determinism: a run depends only on its inputs (its key), and the planner combines outcomes in
sample order, not arrival order, so the stored results and the averages do not depend on which
rank ran what or when.

Scaling (many nodes, thousands of runs): the work is embarrassingly parallel within a stage; the
limits are (1) the number of runs ready at once -- in the rough-surface cascade that is
(points x samples) per stage, so ranks beyond that idle until the next stage (run many (p, v,
compound) points in one scene to fill a large allocation); (2) the longest single run (no run is
split over ranks); (3) one dispatcher: each request costs it a fraction of a millisecond
(docs/performance.md), negligible against runs of seconds to minutes even for thousands of ranks;
(4) the store folder must be on a file system every rank sees (one small file per run; thousands
are fine, millions would want an object store).
"""

from __future__ import annotations

import heapq
import math
import os
import queue
import sys
import threading
import time
import traceback
import warnings
from collections import deque
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any, Callable, Protocol

from mpi4py import MPI

from rubberfriction.driver.runtime.progress import Stage, stage_key
from rubberfriction.driver.runtime.store import Outcome, Store, reusable_failure

TAG_REQUEST, TAG_TASK, TAG_STOP, TAG_PROGRESS = 11, 12, 13, 14
#: idle sleeps of the dispatcher and of a worker waiting for a task (s): none for SPIN
#: seconds after an event, then MIN_NAP doubling up to QUICK_NAP until QUICK_WINDOW
#: seconds after it, then up to ``poll``
SPIN, MIN_NAP, QUICK_NAP, QUICK_WINDOW = 1e-3, 1e-5, 1e-3, 0.05


@dataclass(frozen=True)
class Task:
    """One independent run: its store key, the runner's input (a SlidingSpec) and a label."""

    key: str
    payload: Any
    label: dict = field(default_factory=dict, hash=False, compare=False)


class Planner(Protocol):
    """The campaign logic as the farm sees it."""

    def next_tasks(self) -> list[Task]:
        """Tasks that became ready since the last call (each task is handed out once)."""

    def record(self, task: Task, outcome: Outcome) -> None:
        """The outcome of a task returned by next_tasks."""

    def total(self) -> int:
        """Number of tasks the campaign will run in total (for progress)."""

    # optional: plan() -> list[progress.Stage], every stage the campaign will run (for the
    # time estimate; planners without it get the plain estimate)


class ProgressLike(Protocol):
    def start(self, total: int, workers: int, plan: list[Stage] | None = None) -> None: ...
    def running(self, task: Task, info: dict) -> None: ...
    def update(self, task: Task, outcome: Outcome) -> None: ...
    def finish(self) -> None: ...


class StaticPlanner:
    """A planner for a fixed list of independent tasks (studies, benchmarks, tests)."""

    def __init__(self, tasks: list[Task]):
        self.tasks = list(tasks)
        self.outcomes: dict[int, Outcome] = {}
        self._issued = False

    def total(self) -> int:
        return len(self.tasks)

    def next_tasks(self) -> list[Task]:
        if self._issued:
            return []
        self._issued = True
        return list(self.tasks)

    def record(self, task: Task, outcome: Outcome) -> None:
        for i, t in enumerate(self.tasks):
            if t is task or (t.key == task.key and t.label == task.label):
                self.outcomes[i] = outcome

    def ordered(self) -> list[Outcome]:
        """Outcomes in task order (after the farm finished)."""
        return [self.outcomes[i] for i in range(len(self.tasks))]

    def plan(self) -> list[Stage]:
        """One stage per (point, branch, scale) of the labels, all side by side, weight 1."""
        counts: dict[tuple, list] = {}
        for t in self.tasks:
            key = stage_key(t.label)
            counts.setdefault(key, [t.label, 0])[1] += 1
        return [Stage(f"static{i}", key, (str(lab.get("branch", "")),
                                          str(lab.get("scale_name", lab.get("scale", "")))), n)
                for i, (key, (lab, n)) in enumerate(counts.items())]


class FarmError(RuntimeError):
    """The campaign could not be driven (planner bug, dispatcher failure)."""


def failure_result(reason: str) -> Any:
    """A SlidingResult-like failed result for a run that raised."""
    return SimpleNamespace(status="failed", reason=reason, series={}, stats={},
                           dissipation_by_depth=None,
                           mu_force=float("nan"), mu_energy=float("nan"),
                           mean_pressure=float("nan"),
                           contact_fraction=float("nan"), t_reached=0.0)


def hard_timeout(run_timeout: float) -> float:
    """Watchdog time of a run whose runner stops itself after ``run_timeout`` s (between Newton
    solves): 10 % + 60 s of grace, so the watchdog only catches runs stuck in compiled code."""
    return 1.1 * run_timeout + 60.0 if run_timeout > 0.0 else 0.0


class RunReports:
    """The way from a running task's runner to the campaign's progress line.

    A runner made to report (``sliding_runner(progress=reports)``) calls this object with a
    small dict of plain values saying where its run is (``driver.sliding.progress``) as often as
    it likes; the :class:`Executor` says which task is running (:meth:`begin`, :meth:`end`) and
    reports ``{"phase": "set-up"}`` when a run starts; the farm driver connects ``sink``.  A
    report passes when its phase changed or ``min_interval`` seconds passed since the last one
    of the task, so an MPI worker sends rank 0 about one small message a second.  A sink that
    raises is disconnected with a warning: progress never fails a run.
    """

    def __init__(self, min_interval: float = 1.0, clock: Callable[[], float] = time.monotonic):
        self.min_interval = float(min_interval)
        self.clock = clock
        self.sink: Callable[[Task, dict], None] | None = None
        self.task: Task | None = None
        self._last = -math.inf
        self._phase: Any = None

    def begin(self, task: Task) -> None:
        self.task, self._last, self._phase = task, -math.inf, None

    def end(self) -> None:
        self.task = None

    def __call__(self, info: dict) -> None:
        task, sink = self.task, self.sink
        if task is None or sink is None:
            return
        now, phase = self.clock(), info.get("phase")
        if phase == self._phase and now - self._last < self.min_interval:
            return
        self._last, self._phase = now, phase
        try:
            sink(task, dict(info))
        except Exception as err:  # noqa: BLE001 -- a progress line must not fail a run
            self.sink = None
            warnings.warn(f"run progress reports stopped: {type(err).__name__}: {err}",
                          stacklevel=2)


class Executor:
    """Execute one task where it lands: reuse from the store, or run and store it.

    ``reports``: the :class:`RunReports` the runner was built with (if it reports); the farm
    connects it to the progress line.
    """

    def __init__(self, store: Store, runner: Callable[[Any], Any], *, retry_failed: bool = False,
                 settings: dict | None = None, timeout: float = 0.0,
                 reports: RunReports | None = None):
        self.store = store
        self.runner = runner
        self.retry_failed = retry_failed
        self.settings = settings or {}
        self.timeout = float(timeout)
        self.reports = reports if reports is not None else RunReports()

    def _reusable(self, task: Task) -> Outcome | None:
        """The stored outcome of the task's key if it counts as a result of its inputs: a
        success, or a physics failure without ``retry_failed``.  A run that raised or that the
        wall clock stopped is recomputed
        (:func:`~rubberfriction.driver.runtime.store.reusable_failure`)."""
        out = self.store.outcome(task.key)
        if out is None or not reusable_failure(out.failure, self.retry_failed):
            return None
        return out

    def __call__(self, task: Task) -> Outcome:
        out = self._reusable(task)
        if out is not None:
            return out
        t0 = time.perf_counter()
        failure = None
        watchdog = self._watchdog(task) if self.timeout > 0 else None
        self.reports.begin(task)
        try:
            self.reports({"phase": "set-up"})
            result = self.runner(task.payload)
        except Exception as err:  # noqa: BLE001 -- a failing run must never stop the campaign
            tb = traceback.format_exc(limit=6)
            result = failure_result(f"error: {type(err).__name__}: {err}\n{tb}")
            failure = "error"
        finally:
            self.reports.end()
            if watchdog is not None:
                watchdog.cancel()
        wall = time.perf_counter() - t0
        stats = getattr(result, "stats", None)
        if failure is None and getattr(result, "status", "ok") != "ok" and not stats:
            # run_sliding turns exceptions into failed results without run statistics: such a
            # failure says nothing about the inputs (bug, memory, environment), so it is retried
            failure = "error"
        if failure is None and isinstance(stats, dict) and stats.get("failure") == "wall_limit":
            failure = "timeout"  # stopped itself at the run time limit: like the watchdog's
        if isinstance(stats, dict) and "wall_time" in stats:
            wall = float(stats["wall_time"])
        return self.store.put(task.key, task.payload, result, wall_time=wall, label=task.label,
                              failure=failure, settings=self.settings)

    def _watchdog(self, task: Task) -> threading.Timer:
        """Last resort against a run that hangs (e.g. inside compiled code, where no exception can
        reach it): after ``timeout`` seconds the run is stored as failed ("timeout": shown in
        the report, not a result of its inputs) and the process exits with status 3 (under MPI
        the job is aborted).  Rerunning the scene resumes the campaign and computes this run
        again; a run that hangs every time is a bug to report."""

        def expire() -> None:
            reason = f"timeout: the run exceeded {self.timeout:g} s and was killed"
            try:
                self.store.put(task.key, task.payload, failure_result(reason),
                               wall_time=self.timeout,
                               label=task.label, failure="timeout", settings=self.settings)
            finally:
                print(f"farm: run {task.key[:12]} ({task.label}) exceeded {self.timeout:g} s: "
                      "recorded as stopped by the wall clock; exiting -- run the scene again to "
                      "resume (this run is computed again)", file=sys.stderr, flush=True)
                try:
                    if MPI.Is_initialized() and MPI.COMM_WORLD.Get_size() > 1:
                        MPI.COMM_WORLD.Abort(3)
                finally:
                    os._exit(3)

        timer = threading.Timer(self.timeout, expire)
        timer.daemon = True
        timer.start()
        return timer


class _Book:
    """In-campaign bookkeeping shared by the serial and MPI drivers: a task whose key is already
    finished (or in flight) in this campaign is not executed twice."""

    def __init__(self, planner: Planner, progress: ProgressLike | None):
        self.planner = planner
        self.progress = progress
        self.ready: deque[Task] = deque()
        self.done: dict[str, Outcome] = {}
        self.waiting: dict[str, list[Task]] = {}  # key in flight -> duplicate tasks
        self.active: dict[str, Task] = {}  # key in flight -> the task executing it
        self.in_flight = 0

    def pull(self) -> None:
        """Take the planner's new tasks; a task already done in this campaign is recorded at once,
        which may advance its planner, so ask again until nothing new comes."""
        while tasks := self.planner.next_tasks():
            for t in tasks:
                if t.key in self.done:
                    self._record(t, self.done[t.key])
                elif t.key in self.waiting:
                    self.waiting[t.key].append(t)
                else:
                    self.ready.append(t)

    def take(self) -> Task | None:
        while self.ready:
            t = self.ready.popleft()
            if t.key in self.done:
                self._record(t, self.done[t.key])
                continue
            if t.key in self.waiting:
                self.waiting[t.key].append(t)
                continue
            self.waiting[t.key] = []
            self.active[t.key] = t
            self.in_flight += 1
            return t
        return None

    def report(self, key: str, info: dict) -> None:
        """A report of the run of ``key``; late ones (the run has finished) are dropped."""
        task = self.active.get(key)
        if task is not None and self.progress is not None:
            self.progress.running(task, info)

    def finish(self, task: Task, outcome: Outcome) -> None:
        self.in_flight -= 1
        task = self.active.pop(task.key, task)  # the planner's own object (a worker returns a copy)
        self.done[task.key] = outcome
        dups = self.waiting.pop(task.key, [])
        self._record(task, outcome)
        for t in dups:
            self._record(t, outcome)
        self.pull()

    def _record(self, task: Task, outcome: Outcome) -> None:
        self.planner.record(task, outcome)
        if self.progress is not None:
            self.progress.update(task, outcome)

    @property
    def finished(self) -> bool:
        return not self.ready and self.in_flight == 0


def _plan(planner: Planner) -> list[Stage] | None:
    """The planner's stages if it gives them (``plan()`` is optional)."""
    plan = getattr(planner, "plan", None)
    return plan() if callable(plan) else None


def _connect(execute: Callable[[Task], Outcome],
             sink: Callable[[Task, dict], None] | None) -> None:
    """Route an Executor's run reports to ``sink`` (other execute callables report nothing)."""
    if isinstance(execute, Executor):
        execute.reports.sink = sink


def run_serial(planner: Planner, execute: Callable[[Task], Outcome],
               progress: ProgressLike | None = None) -> dict[str, Outcome]:
    """Drive the planner on this process alone. Returns outcomes by key."""
    book = _Book(planner, progress)
    if progress is not None:
        progress.start(planner.total(), 1, _plan(planner))
    _connect(execute, lambda task, info: book.report(task.key, info))
    try:
        book.pull()
        while True:
            task = book.take()
            if task is None:
                if book.finished:
                    break
                raise FarmError("planner deadlock: no task ready and none "
                                "running")  # pragma: no cover
            book.finish(task, execute(task))
    finally:
        _connect(execute, None)
    if progress is not None:
        progress.finish()
    return book.done


@dataclass(frozen=True)
class Replay:
    """A campaign's schedule on ``workers`` ranks, replayed from run durations (s)."""

    workers: int
    makespan: float  # wall time of the campaign
    busy: float  # run time summed over the runs (the serial makespan)
    runs: int

    @property
    def efficiency(self) -> float:
        """Share of the workers' time spent in runs."""
        return self.busy / (self.workers * self.makespan) if self.makespan > 0 else math.nan


def replay(planner: Planner, outcome_of: Callable[[Task], tuple[Outcome, float]],
           workers: int) -> Replay:
    """The farm's dynamic dispatch replayed as a discrete-event simulation: ``workers`` ranks
    take ready tasks in the order the campaign hands them out (the ready queue of the serial and
    MPI drivers, duplicates executed once), each task lasts the duration ``outcome_of`` gives with
    its outcome, and outcomes reach the planner when their run ends, which makes the next stage
    ready.  A finished campaign's stored runs and wall times answer "how long on N ranks" without
    computing anything (``rubberfriction bench farm``); the dispatcher's own time per request
    is left out."""
    if workers < 1:
        raise ValueError(f"replay on {workers} workers: expected at least 1")
    book = _Book(planner, None)
    book.pull()
    clock, busy, seq, runs = 0.0, 0.0, 0, 0
    running: list[tuple[float, int, Task, Outcome]] = []
    while True:
        while len(running) < workers and (task := book.take()) is not None:
            outcome, duration = outcome_of(task)
            heapq.heappush(running, (clock + float(duration), seq, task, outcome))
            seq, busy, runs = seq + 1, busy + float(duration), runs + 1
        if not running:
            break
        clock, _, task, outcome = heapq.heappop(running)
        book.finish(task, outcome)
    if not book.finished:  # pragma: no cover -- the planner left tasks it never handed out
        raise FarmError("replay: planner deadlock")
    return Replay(workers, clock, busy, runs)


def run_farm(make_planner: Callable[[], Planner], execute: Callable[[Task], Outcome],
             progress: ProgressLike | None = None, comm: Any = None,
             poll: float = 0.02) -> tuple[Planner | None, dict[str, Outcome]]:
    """Run a campaign on all ranks of ``comm`` (default: COMM_WORLD; serial on one rank).

    Every rank calls this with the same arguments; ``make_planner`` is only called on rank 0.
    Returns ``(planner, outcomes)`` on rank 0 and ``(None, {})`` on the other ranks.  An
    exception raised while planning on rank 0 stops all workers and is re-raised on rank 0.
    """
    comm = MPI.COMM_WORLD if comm is None else comm
    if comm.Get_size() == 1:
        planner = make_planner()
        return planner, run_serial(planner, execute, progress)
    comm = comm.Dup()
    try:
        if comm.Get_rank() == 0:
            return _master(comm, make_planner, execute, progress, poll)
        _worker(comm, execute, poll)
        return None, {}
    finally:
        comm.Free()


class _Nap:
    """Idle sleeps of a polling loop: none for SPIN seconds after an event (poll again at once),
    then MIN_NAP doubling up to QUICK_NAP until QUICK_WINDOW seconds after it (answers come
    soon after an event), then up to ``poll``.  A sleep lasts much longer than a tiny nap asks
    for (more on a loaded machine), so an answer that waits for a few of them right after an
    event is slow: the spin makes short tasks several times quicker (docs/performance.md)."""

    def __init__(self, poll: float):
        self.poll = poll
        self.event()

    def event(self) -> None:
        self.nap, self.last = 0.0, time.monotonic()

    def sleep(self) -> None:
        since = time.monotonic() - self.last
        if since < SPIN:
            return  # poll again at once: even sleep(0) is a system call that yields the core
        time.sleep(self.nap)
        cap = min(QUICK_NAP, self.poll) if since < QUICK_WINDOW else self.poll
        self.nap = min(max(2.0 * self.nap, MIN_NAP), cap)


def _wait(comm: Any, source: int, poll: float) -> None:
    """Wait for a message from ``source`` by polling: a blocking receive would spin a core at
    100 % while a worker waits for the next stage of the campaign."""
    nap = _Nap(poll)
    while not comm.Iprobe(source=source, tag=MPI.ANY_TAG):
        nap.sleep()


def _worker(comm: Any, execute: Callable[[Task], Outcome], poll: float) -> None:
    status = MPI.Status()
    outcome: tuple[Task, Outcome] | None = None
    # reports go to rank 0 as they come (RunReports rate-limits them); a small pickled dict is
    # sent eagerly, so the run does not wait for the dispatcher
    _connect(execute, lambda task, info: comm.send((task.key, info), dest=0, tag=TAG_PROGRESS))
    try:
        while True:
            comm.send(outcome, dest=0, tag=TAG_REQUEST)
            _wait(comm, 0, poll)
            task = comm.recv(source=0, tag=MPI.ANY_TAG, status=status)
            if status.Get_tag() == TAG_STOP:
                return
            outcome = (task, execute(task))
    finally:
        _connect(execute, None)


def _master(comm: Any, make_planner: Callable[[], Planner], execute: Callable[[Task], Outcome],
            progress: ProgressLike | None, poll: float) -> tuple[Planner | None,
                                                                 dict[str, Outcome]]:
    nworkers = comm.Get_size() - 1
    local = MPI.Query_thread() >= MPI.THREAD_MULTIPLE
    if not local:
        print("farm: MPI thread level below THREAD_MULTIPLE: rank 0 only dispatches "
              f"({nworkers} workers)", file=sys.stderr)
    try:
        planner = make_planner()
    except BaseException:
        _stop_all(comm, nworkers)
        raise
    book = _Book(planner, progress)
    if progress is not None:
        progress.start(planner.total(), nworkers + (1 if local else 0), _plan(planner))
    to_local: queue.Queue = queue.Queue()
    from_local: queue.Queue = queue.Queue()
    local_reports: queue.Queue = queue.Queue()  # rank 0's own runs -> the dispatcher thread
    failure: list[BaseException] = []
    abort = threading.Event()

    def dispatch() -> None:
        st = MPI.Status()
        idle: deque[int] = deque()
        local_idle = local
        nap = _Nap(poll)
        try:
            book.pull()
            while True:
                if abort.is_set():
                    raise FarmError("rank 0 worker failed")
                busy = False
                while comm.Iprobe(source=MPI.ANY_SOURCE, tag=MPI.ANY_TAG, status=st):
                    src, tag = st.Get_source(), st.Get_tag()
                    msg = comm.recv(source=src, tag=tag)
                    if tag == TAG_PROGRESS:  # needs no quick answer: not an event for the naps
                        book.report(*msg)
                        continue
                    busy = True
                    if msg is not None:
                        book.finish(*msg)
                    idle.append(src)
                _drain(local_reports, book)
                while True:
                    try:
                        msg = from_local.get_nowait()
                    except queue.Empty:
                        break
                    _drain(local_reports, book)  # the run's reports were queued before it
                    book.finish(*msg)
                    local_idle = True
                    busy = True
                while idle or local_idle:
                    task = book.take()
                    if task is None:
                        break
                    if local_idle:  # rank 0's own worker first: no message needed
                        to_local.put(task)
                        local_idle = False
                    else:
                        comm.send(task, dest=idle.popleft(), tag=TAG_TASK)
                    busy = True
                if book.finished and (local_idle or not local) and len(idle) == nworkers:
                    break
                if busy:
                    nap.event()
                else:
                    nap.sleep()
        except BaseException as err:  # noqa: BLE001 -- reported on the main thread
            failure.append(err)
        finally:
            for _ in range(nworkers):  # every worker is (or will be) waiting for an answer
                if not idle:
                    idle.append(_next_request(comm, st))
                comm.send(None, dest=idle.popleft(), tag=TAG_STOP)
            to_local.put(None)

    thread = threading.Thread(target=dispatch, name="rf-dispatcher", daemon=True)
    thread.start()
    _connect(execute, lambda task, info: local_reports.put((task.key, info)))
    try:
        while local:
            task = to_local.get()
            if task is None:
                break
            from_local.put((task, execute(task)))
    except BaseException:
        abort.set()  # the dispatcher stops the workers, then we re-raise
        thread.join()
        raise
    finally:
        _connect(execute, None)
    thread.join()
    if failure:
        raise FarmError(f"campaign dispatcher failed: {failure[0]!r}") from failure[0]
    if progress is not None:
        progress.finish()
    return planner, book.done


def _drain(reports: queue.Queue, book: _Book) -> None:
    """Hand the reports rank 0's own worker queued to the book."""
    while True:
        try:
            book.report(*reports.get_nowait())
        except queue.Empty:
            return


def _next_request(comm: Any, st: Any) -> int:
    """Wait for a worker's next request (dropping its progress reports); returns its rank."""
    while True:
        comm.recv(source=MPI.ANY_SOURCE, tag=MPI.ANY_TAG, status=st)
        if st.Get_tag() == TAG_REQUEST:
            return st.Get_source()


def _stop_all(comm: Any, nworkers: int) -> None:
    st = MPI.Status()
    for _ in range(nworkers):
        comm.send(None, dest=_next_request(comm, st), tag=TAG_STOP)
