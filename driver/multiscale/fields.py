"""Fields of chosen runs of a campaign for ParaView: ``rubberfriction run SCENE --fields SELECT``.

A campaign stores numbers, series and depth profiles of every run, not its fields (they would
be gigabytes).  After the campaign, the selected runs are recomputed from their run files
(:func:`~rubberfriction.driver.multiscale.rerun.rerun_stored`, the machinery of
``rubberfriction rerun``) with a :class:`~rubberfriction.driver.sliding.outputs.FieldWriter`:
``<output>/fields/<point>_<branch>_<scale>_s<sample>/`` gets ``fields.xdmf`` (+ ``fields.h5``:
displacement, hydrostatic pressure, von Mises stress, viscous dissipation, dissipation rate) and
``contact_pressure.csv``.  The reruns are the stored runs again (deterministic: the same
mu_force; a run the closed-form shortcut computed is run with the FE instead, the only way to
have its fields); they run serially on rank 0 after the campaign.

Selection grammar (``SELECT``, comma-separated items, matched against every run's label)::

    ITEM   := "all" | BRANCH | [BRANCH ":"] SCALE [":" SAMPLE]
    BRANCH := down | up                      (rough scenes: pressure / friction branch)
            | macro0 | reference | micro | macro   (separated scenes)
    SCALE  := a scale name of the scene (run --check lists them; separated: also "full")
    SAMPLE := a sample index 0, 1, ...

An omitted branch or sample means all of them: ``meso`` is every run on the meso scale,
``meso:0`` its sample 0 on both branches, ``up:micro1:1`` one run, ``all`` every run.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from rubberfriction.driver.scenes import Scene, SceneError, surface_scale_names

#: Branch labels of the runs by scene variant (cascade.py: down/up; separated.py: roles).
BRANCHES: dict[str, tuple[str, ...]] = {"rough": ("down", "up"),
                                        "separated": ("macro0", "reference", "micro", "macro")}
GRAMMAR = ("all, BRANCH, or [BRANCH:]SCALE[:SAMPLE], comma-separated (e.g. meso, meso:0, "
           "up:micro1:1)")


@dataclass(frozen=True)
class FieldItem:
    """One item of a selection; None matches anything."""

    branch: str | None = None
    scale: str | None = None
    sample: int | None = None

    def matches(self, label: dict[str, Any]) -> bool:
        return ((self.branch is None or label.get("branch") == self.branch)
                and (self.scale is None or label.get("scale_name") == self.scale)
                and (self.sample is None or label.get("sample") == self.sample))


def _sample(text: str, item: str, option: str) -> int:
    if not re.fullmatch(r"\d+", text):
        raise SceneError(f"{option} {item!r}: sample {text!r} is not an index 0, 1, ...; "
                         f"expected {GRAMMAR}")
    return int(text)


def parse_selection(text: str, scene: Scene, option: str = "--fields") -> list[FieldItem]:
    """The items of ``text`` (grammar in the module docstring), checked against the scene's
    branches, scale names and sample counts; a SceneError naming ``option`` otherwise."""
    branches = BRANCHES.get(scene.variant, BRANCHES["rough"])
    scales = surface_scale_names(scene.surface) + (["full"] if scene.variant == "separated"
                                                   else [])
    n_samples = max(scene.samples.pressure, scene.samples.friction)
    items = []
    for raw in (text or "").split(","):
        item = raw.strip()
        parts = item.split(":")
        if not item or any(not p for p in parts) or len(parts) > 3:
            raise SceneError(f"{option} {text!r}: expected {GRAMMAR}")
        if item == "all":
            items.append(FieldItem())
            continue
        branch = parts[0] if parts[0] in branches else None
        rest = parts[1:] if branch is not None else parts
        if branch is None and len(parts) == 3:
            raise SceneError(f"{option} {item!r}: branch {parts[0]!r} is not one of "
                             f"{', '.join(branches)}")
        scale = rest[0] if rest else None
        sample = _sample(rest[1], item, option) if len(rest) > 1 else None
        if scale is not None and scale not in scales:
            raise SceneError(f"{option} {item!r}: no scale {scale!r} in this scene (scales: "
                             f"{', '.join(scales)}; branches: {', '.join(branches)})")
        if sample is not None and sample >= n_samples:
            raise SceneError(f"{option} {item!r}: sample {sample} does not exist (the scene "
                             f"runs {n_samples} sample(s) per scale: 0..{n_samples - 1})")
        items.append(FieldItem(branch, scale, sample))
    return items


def _slug(text: str) -> str:
    """A file-name-safe point label (the report's file names use the same rule)."""
    return re.sub(r"[^A-Za-z0-9.=_-]+", "_", text).strip("_")


def field_folder(output: Path, point_id: str, label: dict[str, Any]) -> Path:
    """``<output>/fields/<point>_<branch>_<scale>_s<sample>``."""
    return Path(output) / "fields" / (f"{_slug(point_id)}_{label.get('branch')}_"
                                      f"{label.get('scale_name')}_s{label.get('sample')}")


def selected_runs(result: Any, items: list[FieldItem]) -> list[tuple[str, dict, Any]]:
    """(point id, label, outcome) of every run of a finished campaign that ``items`` select,
    once per point, branch, scale and sample, in campaign order (``--fields``,
    ``--mesh-check``)."""
    out, seen = [], set()
    for r in result.points:
        for _stage, runs in r.runs.items():
            for task, outcome in runs:
                label = dict(task.label)
                ident = (r.point.id, label.get("branch"), label.get("scale_name"),
                         label.get("sample"))
                if ident in seen or not any(it.matches(label) for it in items):
                    continue
                seen.add(ident)
                out.append((r.point.id, label, outcome))
    return out


def compound_files(scene: Scene) -> dict[str, str]:
    """The scene's compound files by compound name (what a stored run's rebuild loads)."""
    from rubberfriction.forms.material_files import load_compound

    files = {}
    for path in scene.conditions.compound_paths:
        try:
            files[load_compound(path).name] = path
        except ValueError:
            continue
    return files


@dataclass
class FieldRun:
    """One selected run: its folder, label, store key and the rerun (None if not stored)."""

    folder: Path
    label: dict[str, Any]
    key: str
    rerun: Any = None


def write_fields(result: Any, items: list[FieldItem], every: int = 1,
                 progress: Callable[[str], None] | None = None) -> list[FieldRun]:
    """Rerun the runs of a finished campaign (``CampaignResult``) that ``items`` select, each
    with a FieldWriter(every) into :func:`field_folder`.  Runs without a stored run file, or whose
    inputs a run file cannot rebuild (a friction law object), are skipped and reported through
    ``progress``.  Serial: call on rank 0 only."""
    from rubberfriction.driver.multiscale.rerun import rerun_stored
    from rubberfriction.driver.sliding.outputs import FieldWriter

    if every < 1:
        raise SceneError(f"--fields-every {every}: expected a whole number >= 1")
    store = result.store
    files = compound_files(result.scene)
    done: list[FieldRun] = []
    for point_id, label, outcome in selected_runs(result, items):
        folder = field_folder(result.output, point_id, label)
        run = FieldRun(folder, label, outcome.key)
        done.append(run)
        if not outcome.key or not store.has(outcome.key):
            if progress:
                progress(f"fields: {folder.name}: no stored run file, skipped")
            continue
        if progress:
            progress(f"fields: {folder.name}: rerunning {outcome.key[:12]} ...")
        try:
            run.rerun = rerun_stored(store, outcome.key, [FieldWriter(folder, every=every)],
                                     compound_files=files, fe=True)
        except ValueError as err:  # inputs a run file cannot rebuild (a mu(p, v) law)
            if progress:
                progress(f"fields: {folder.name}: not rerun: {err}")
            continue
        if progress:
            res, old = run.rerun.result, run.rerun.stored.values.get("mu_force")
            fe = (": the stored run is the closed form, the fields are the FE run's"
                  if run.rerun.fe_instead_of_closed_form else "")
            progress(f"fields: {folder} ({res.status}, mu_force {res.mu_force:.6g}, "
                     f"stored {old if old is None else format(old, '.6g')}, "
                     f"{run.rerun.wall_time:.1f} s{fe})")
    if progress and not done:
        progress("fields: no run of the campaign matches the selection")
    return done
