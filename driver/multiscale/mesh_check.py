"""Mesh convergence of a finished campaign: ``rubberfriction run SCENE --mesh-check [SELECT]``.

Every homogenised number should show that it converged: in its window (the stationarity
line), over its samples (the confidence interval), in its cut-off (the scale table) and in its
mesh.  The campaign itself runs each scale at one mesh (``elements_per_wavelength`` contact
elements per shortest wavelength of the band, sliding steps to match).  This check runs chosen
runs of the campaign again with contact elements ``factor`` times shorter
(:func:`~rubberfriction.driver.sliding.spec.refined`: the block's element columns and its first
rows, the sliding step and the automatic penalty c_N = alpha |E*| / h follow), with the same
inputs as the stored run (the pressure handed down, the friction of the scale below, the
sample).  So each row is that scale's own discretisation error, the lower scales held as they
are.

What it reports per run (``mesh_check.csv``) and per scale (the summary's ``mesh:`` line and
``mesh_check.png``): mu_force and the contact fraction at h and at h / factor, the relative
change of mu, and the first-order estimate of the fine run's own error (mu_fine - mu_coarse) /
(factor - 1): on the default road's macro pressure run at 100 mm/s, mu_force at h, h/2 and h/4
is 0.1756 / 0.2169 / 0.2360, an observed order of 1.1 (``docs/scales.md``, "Mesh check").  A
scale whose mu moves by more than :data:`MESH_TOL` is not converged in its mesh: its mu is
biased (coarse contact elements blunt the contact patches' edges, where the dissipation is), by
about the change again.

The refined runs go through the campaign's store (keyed by their inputs like every run), so a
second ``--mesh-check`` reuses them; they are farmed over the ranks like a campaign's runs.
Default selection: sample 0 of every scale of the friction branch (``up:SCALE:0``), the runs
whose mu makes the point's.  The selection grammar is ``--fields``'
(:mod:`~rubberfriction.driver.multiscale.fields`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Sequence

from rubberfriction.driver.multiscale.fields import (
    FieldItem,
    compound_files,
    parse_selection,
    selected_runs,
)
from rubberfriction.driver.scenes import Scene, SceneError

__all__ = ["MESH_TOL", "DEFAULT_SELECTION", "MeshRow", "check_factor", "mesh_selection",
           "mesh_tasks",
           "mesh_rows", "mesh_lines", "with_mesh_lines", "run_mesh_check", "write_mesh_check",
           "plot_mesh_check"]

#: a scale whose sample-0 mu moves by more than this under refinement is not mesh-converged
#: (issue 42: each scale within 2 % of its finest setting)
MESH_TOL = 0.02

#: sample 0 of every scale of the friction branch
DEFAULT_SELECTION = (FieldItem("up", None, 0),)


@dataclass(frozen=True)
class MeshRow:
    """One run at its campaign mesh (h) and refined (h / factor)."""

    point: str
    branch: str
    scale_name: str
    sample: int
    factor: int
    h_contact: float
    key: str
    key_fine: str
    attempt: str
    attempt_fine: str
    status_fine: str
    reason_fine: str
    mu: float
    mu_fine: float
    contact: float
    contact_fine: float
    energy_balance: float
    energy_balance_fine: float
    wall: float
    wall_fine: float

    @property
    def change(self) -> float:
        """(mu_fine - mu) / mu: the relative change of mu_force under refinement."""
        return (self.mu_fine - self.mu) / self.mu if self.mu else math.nan

    @property
    def fine_error(self) -> float:
        """First-order estimate of the fine run's own relative error, change / (factor - 1)
        (observed order about 1: module docstring)."""
        return self.change / (self.factor - 1)

    @property
    def converged(self) -> bool:
        return abs(self.change) <= MESH_TOL

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d.update(change=self.change, fine_error=self.fine_error,
                 mu_limit_first_order=self.mu_fine * (1 + self.fine_error)
                 if math.isfinite(self.mu_fine) else math.nan,
                 converged=int(self.converged))
        return d


def check_factor(factor: int) -> None:
    """A SceneError unless the refinement factor is a whole number >= 2."""
    if not isinstance(factor, int) or factor < 2:
        raise SceneError(f"mesh factor {factor!r} (--mesh-factor, rf.mesh_check(factor=...)): "
                         "expected a whole number >= 2")


def mesh_selection(text: str | None, scene: Scene, factor: int = 2) -> list[FieldItem]:
    """The runs ``--mesh-check [SELECT]`` chooses: :data:`DEFAULT_SELECTION` without a value,
    else ``--fields``' grammar; a SceneError for scenes without a rough-surface cascade or a
    factor below 2 (:func:`check_factor`)."""
    check_factor(factor)
    if scene.variant != "rough" or scene.physics.thermal or scene.adhesion_fit is not None:
        raise SceneError("--mesh-check: for rough-surface cascades (not thermal, separated or "
                         "adhesion-fit scenes); rerun single runs with rubberfriction rerun "
                         "FOLDER KEY --refine 2")
    if text is None or text == "":
        return list(DEFAULT_SELECTION)
    return parse_selection(text, scene, option="--mesh-check")


def mesh_tasks(result: Any, items: Sequence[FieldItem], factor: int = 2,
               notes: list[str] | None = None) -> list[Any]:
    """The refined runs of the selected runs of ``result`` (a CampaignResult) as farm Tasks; a
    run whose stored inputs cannot be rebuilt is left out with a line in ``notes``."""
    from rubberfriction.driver.multiscale.rerun import load_stored
    from rubberfriction.driver.runtime.farm import Task
    from rubberfriction.driver.runtime.store import run_key
    from rubberfriction.driver.sliding.spec import default_h_contact, refined

    check_factor(factor)
    files = compound_files(result.scene)
    tasks = []
    for point_id, label, outcome in selected_runs(result, items):
        if not outcome.ok or not outcome.key:  # a failed run has no mu to compare
            continue
        try:
            spec = load_stored(result.store, outcome.key, compound_files=files).spec
        except ValueError as err:
            if notes is not None:
                notes.append(f"{point_id} {label.get('branch')} {label.get('scale_name')} "
                             f"{label.get('sample')}: not rebuilt: {err}")
            continue
        fine = refined(spec, factor)
        h = spec.h_contact or default_h_contact(spec)
        tasks.append(Task(run_key(fine), fine,
                          {**label, "point": point_id, "mesh_factor": factor,
                           "coarse_key": outcome.key, "h_contact": float(h)}))
    return tasks


def mesh_rows(tasks: Sequence[Any], outcomes: Sequence[Any], coarse: dict[str, Any]
              ) -> list[MeshRow]:
    """One row per refined task and its outcome, beside the coarse outcome of its label's
    ``coarse_key`` (``coarse``: key -> Outcome of the campaign)."""
    from rubberfriction.driver.multiscale.report.tables import energy_balance
    from rubberfriction.driver.multiscale.statistics import first_line

    rows = []
    for task, fine in zip(tasks, outcomes):
        lab = task.label
        c = coarse[lab["coarse_key"]]
        ok = fine.ok
        rows.append(MeshRow(
            point=str(lab.get("point")), branch=str(lab.get("branch")),
            scale_name=str(lab.get("scale_name")), sample=int(lab.get("sample", 0)),
            factor=int(lab["mesh_factor"]), h_contact=float(lab["h_contact"]),
            key=c.key, key_fine=fine.key, attempt=c.attempt, attempt_fine=fine.attempt,
            status_fine=fine.status,
            reason_fine=first_line(fine.reason) if fine.reason else "",
            mu=c.value("mu_force"), mu_fine=fine.value("mu_force") if ok else math.nan,
            contact=c.value("contact_fraction"),
            contact_fine=fine.value("contact_fraction") if ok else math.nan,
            energy_balance=energy_balance(c),
            energy_balance_fine=energy_balance(fine) if ok else math.nan,
            wall=c.wall_time, wall_fine=fine.wall_time))
    return rows


def mesh_lines(rows: Sequence[MeshRow]) -> list[str]:
    """The summary's lines: per branch and scale the largest and mean change of mu under
    refinement, and how many runs move by more than MESH_TOL."""
    if not rows:
        return ["  mesh: no run checked (none selected, or none succeeded)"]
    f = rows[0].factor
    lines = [f"  mesh (runs again with contact elements {f}x shorter, inputs as stored; "
             f"{100 * MESH_TOL:g} % tolerance):"]
    groups: dict[tuple[str, str], list[MeshRow]] = {}
    for r in rows:
        groups.setdefault((r.branch, r.scale_name), []).append(r)
    for (branch, scale), rs in groups.items():
        good = [r for r in rs if math.isfinite(r.change)]
        failed = len(rs) - len(good)
        if not good:
            lines.append(f"    {branch:<4} {scale:<8} {len(rs)} run(s), every refined run failed "
                         f"({rs[0].reason_fine or rs[0].status_fine})")
            continue
        if all(r.attempt == r.attempt_fine == "closed form" for r in rs):
            lines.append(f"    {branch:<4} {scale:<8} {len(rs)} run(s) of the closed form "
                         "(driver.sliding.shortcut): no mesh to converge")
            continue
        worst = max(good, key=lambda r: abs(r.change))
        mean = sum(r.change for r in good) / len(good)
        off = sum(not r.converged for r in good)
        verdict = "converged" if off == 0 else f"{off} of {len(good)} beyond"
        lines.append(f"    {branch:<4} {scale:<8} mu changes by {100 * mean:+.1f} % on average, "
                     f"largest {100 * worst.change:+.1f} % ({worst.mu:.4g} -> {worst.mu_fine:.4g}"
                     f", {worst.point}); {verdict}"
                     + (f"; {failed} refined run(s) failed" if failed else ""))
    if any(not r.converged for r in rows if math.isfinite(r.change)):
        lines.append("    not mesh-converged: those scales' mu is biased by about the change again "
                     "(first order); raise [numerics.<scale>] elements_per_wavelength, see "
                     "mesh_check.csv")
    return lines


def with_mesh_lines(summary: Sequence[str], lines: Sequence[str]) -> list[str]:
    """``summary``'s lines with its mesh block (a line starting with "  mesh" and the deeper
    indented lines after it: the "not checked" line or an earlier check) replaced by
    ``lines``, appended where there was none."""
    out: list[str] = []
    at = None
    skipping = False
    for ln in summary:
        if ln.startswith("  mesh"):
            at, skipping = len(out), True
            continue
        if skipping and ln.startswith("    "):
            continue
        skipping = False
        out.append(ln)
    at = len(out) if at is None else at
    return out[:at] + list(lines) + out[at:]


def write_mesh_check(rows: Sequence[MeshRow], output: Path) -> Path:
    from rubberfriction.driver.multiscale.report.tables import write_csv

    return write_csv(Path(output) / "mesh_check.csv", [r.as_dict() for r in rows])


def plot_mesh_check(rows: Sequence[MeshRow], output: Path) -> Path | None:
    """``mesh_check.png``: mu of each checked run at h (open) and h / factor (filled), one
    colour per scale, points along the x axis."""
    if not rows:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points = list(dict.fromkeys(r.point for r in rows))
    fig, ax = plt.subplots(figsize=(max(6.0, 1.2 * len(points) + 2), 4.2))
    groups: dict[tuple[str, str, int], list[MeshRow]] = {}
    for r in rows:
        groups.setdefault((r.branch, r.scale_name, r.sample), []).append(r)
    for i, ((branch, scale, sample), rs) in enumerate(groups.items()):
        x = [points.index(r.point) + 0.08 * (i - len(groups) / 2) for r in rs]
        color = f"C{i % 10}"
        ax.plot(x, [r.mu for r in rs], "o", mfc="none", color=color,
                label=f"{branch} {scale} s{sample}: h")
        ax.plot(x, [r.mu_fine for r in rs], "o", color=color,
                label=f"{branch} {scale} s{sample}: h/{rs[0].factor}")
        for xi, r in zip(x, rs):
            ax.plot([xi, xi], [r.mu, r.mu_fine], "-", color=color, lw=0.8)
    ax.set_xticks(range(len(points)))
    ax.set_xticklabels(points, rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("mu_force of the run")
    ax.set_title("mesh check: each run at its campaign mesh h and refined", fontsize=10)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    path = Path(output) / "mesh_check.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run_mesh_check(scene: Scene, result: Any, items: Sequence[FieldItem], *, factor: int = 2,
                   quiet: bool = False, comm: Any = None) -> list[MeshRow] | None:
    """Run the refined runs of ``result``'s selected runs, farmed over ``comm`` (every rank
    calls this; ``result`` is the CampaignResult on rank 0, None elsewhere); rank 0 writes
    ``mesh_check.csv``, ``mesh_check.png``, appends the ``mesh:`` lines to ``summary.txt`` (and
    prints them) and returns the rows, the other ranks None."""
    from mpi4py import MPI

    from rubberfriction.driver.multiscale.campaign import (_on_rank0, open_store,
                                                           runner_and_timeout)
    from rubberfriction.driver.runtime.farm import Executor, RunReports, StaticPlanner, run_farm
    from rubberfriction.driver.runtime.progress import Progress

    comm = MPI.COMM_WORLD if comm is None else comm
    rank = comm.Get_rank()
    notes: list[str] = []
    tasks = _on_rank0(lambda: mesh_tasks(result, items, factor, notes), comm)
    out = Path(scene.output)  # the campaign's folder and store (run_scene's default)
    reports = RunReports()
    runner, timeout = runner_and_timeout(scene, None, reports)
    store = open_store(out, comm)
    try:
        executor = Executor(store, runner, timeout=timeout, reports=reports,
                            settings={"scene": scene.name, "mesh_check": factor})
        progress = Progress(quiet=quiet, title="mesh check") if rank == 0 else None
        if rank == 0 and not quiet:
            print(f"mesh check: {len(tasks)} run(s) again with contact elements {factor}x "
                  "shorter")
        planner, _ = run_farm(lambda: StaticPlanner(tasks), executor, progress, comm)
    finally:
        store.unlock()
    if rank != 0:
        return None
    assert isinstance(planner, StaticPlanner)
    rows = mesh_rows(tasks, planner.ordered(), result.outcomes)
    write_mesh_check(rows, out)
    plot_mesh_check(rows, out)
    lines = mesh_lines(rows) + [f"    {n}" for n in notes]
    summary = out / "summary.txt"
    if summary.exists():
        summary.write_text("\n".join(with_mesh_lines(summary.read_text().splitlines(), lines))
                           + "\n")
    if not quiet:
        print("\n".join(lines))
        print(f"mesh check: {out / 'mesh_check.csv'}, {out / 'mesh_check.png'}")
    return rows
