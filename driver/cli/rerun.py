"""``rubberfriction rerun FOLDER KEY``: one stored single-scale run of a campaign again.

Every run of a campaign is stored by the hash of its inputs (``driver.runtime.store``); its key
is in ``samples.csv`` (column key).  ``rerun`` rebuilds that run's SlidingSpec from the run file
(checked field by field against the stored image, so it is exactly the stored run or an error)
and runs it again, serially, with progress, optionally with another contact formulation, shorter
contact elements, changed scalar inputs (``--set``), another volumetric energy of the rubber
(``--volumetric``) or only the first attempt of the fallback chain, and writes its outputs for
a look.  For reproducing a result, or diagnosing a failed run without the campaign around it:

    rubberfriction rerun rf-results/default 6b9a9635                 # as stored, all fallbacks
    rubberfriction rerun rf-results/default 6b9a9635 --first-attempt --out diag/
    rubberfriction rerun rf-results/default 6b9a9635 --contact surface --refine 2
    rubberfriction rerun tests/data/failing_runs f280d52c --set penalty_alpha=30 --first-attempt
    rubberfriction rerun tests/data/failing_runs f280d52c --set newton=trust-region
    rubberfriction rerun rf-results/default 6b9a9635 --volumetric logarithmic
    rubberfriction rerun rf-results/thermal_road 3f0c11 --from-rest --set slide_distance=600
    rubberfriction rerun rf-results/default 6b9a9635 --fields fields/ --fields-every 5

``--fields DIR`` adds the field writer (``driver.sliding.outputs.FieldWriter``): DIR/fields.xdmf
(+ fields.h5: displacement, hydrostatic pressure, von Mises stress, viscous dissipation,
dissipation rate; open the .xdmf in ParaView, warp by displacement) and
DIR/contact_pressure.csv, every ``--fields-every`` sliding steps.  ``rubberfriction run SCENE
--fields SELECT`` does the same for chosen runs of a campaign.

The compound is loaded again by its name; a folder of kept runs whose compound file has changed
since holds the file as it was in ``FOLDER/compounds/<name>.toml``, which is taken first (the
stored image still has to match).

Exit status: 0 when the run succeeds, 1 when it fails, 2 on bad input (unknown key, a run whose
inputs cannot be rebuilt).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

from rubberfriction.forms.compound import VOLUMETRIC_FORMS


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("rerun", help="run one stored single-scale run of a campaign again "
                       "(reproduce a result, diagnose a failure)", description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder", help="a campaign's output folder (holding store/) or a store folder")
    p.add_argument("key", help="the run's key or its first 6 or more characters (samples.csv, key)")
    p.add_argument("--contact", choices=("mortar", "nts", "surface"),
                   help="contact formulation of the first attempt (default: the stored one)")
    p.add_argument("--refine", type=int, default=1, metavar="N",
                   help="contact elements N times shorter (sliding steps follow them)")
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                   help="override a scalar input of the run (SlidingSpec field), e.g. "
                        "steady_state=false, penalty_alpha=100, tangential_penalty=0.01; "
                        "repeatable")
    p.add_argument("--volumetric", choices=VOLUMETRIC_FORMS,
                   help="volumetric energy of the rubber (the compound's hyperelastic.volumetric; "
                        "forms/hyperelastic.py)")
    p.add_argument("--from-rest", action="store_true",
                   help="a warm-started run (the thermal loop's) from rest instead of from the "
                        "state it slid on from")
    p.add_argument("--first-attempt", action="store_true",
                   help="only the first attempt of the fallback chain: see where it fails")
    p.add_argument("--out", metavar="DIR", help="write series.csv, mu.png, summary.json and the "
                   "dissipation by depth of the rerun into DIR")
    p.add_argument("--json", metavar="FILE", help="write the stored and the new result as JSON")
    p.add_argument("--fields", metavar="DIR", help="write XDMF fields (+ .h5) for ParaView and "
                   "contact_pressure.csv of the rerun into DIR")
    p.add_argument("--fields-every", type=int, default=1, metavar="N",
                   help="with --fields: the fields of every N-th sliding step (default 1)")
    p.set_defaults(func=_rerun)


def _rerun(args: argparse.Namespace) -> int:
    from rubberfriction.driver.multiscale.rerun import (load_stored, rerun_spec,
                                                        shortcut_admits, store_root)
    from rubberfriction.driver.multiscale.report import balance_parts, energy_balance
    from rubberfriction.driver.runtime.store import Outcome, Store, result_values
    from rubberfriction.driver.sliding.outputs import (DissipationByDepth, FieldWriter,
                                                       write_run_outputs)
    from rubberfriction.driver.sliding.progress import StepReporter
    from rubberfriction.driver.sliding.spec import refined

    root = store_root(args.folder)
    if not (root / "runs").is_dir():
        print(f"rerun: {args.folder}: no campaign store here (expected {root}/runs)",
              file=sys.stderr)
        return 2
    if args.refine < 1:
        print(f"rerun: --refine {args.refine}: expected a whole number >= 1", file=sys.stderr)
        return 2
    if args.fields_every < 1:
        print(f"rerun: --fields-every {args.fields_every}: expected a whole number >= 1",
              file=sys.stderr)
        return 2
    store = Store(root)
    try:
        loaded = load_stored(store, args.key, compound_dir=Path(args.folder) / "compounds")
    except ValueError as err:
        print(f"rerun: {err}", file=sys.stderr)
        return 2
    key, stored, spec = loaded.key, loaded.stored, loaded.spec
    lab = stored.label
    print(f"run {key[:12]}: {lab.get('point', '?')} {lab.get('branch', '')} "
          f"{lab.get('scale_name', '')} sample {lab.get('sample', '?')}; "
          f"p = {spec.pressure:.4g} MPa, v = {spec.velocity:g} mm/s, "
          f"friction {spec.friction if spec.friction is not None else 'none'}, "
          f"contact {spec.contact}, h_contact {spec.h_contact:.4g} mm")
    print(f"  stored: {stored.status}, mu_force {stored.values.get('mu_force', math.nan):.6g}, "
          f"{stored.provenance.get('wall_time', math.nan):.1f} s"
          + (f" ({stored.reason.splitlines()[0]})" if stored.reason else ""))
    try:
        spec = _overrides(spec, args.set)
    except ValueError as err:
        print(f"rerun: {err}", file=sys.stderr)
        return 2
    if args.from_rest:
        spec = dataclasses.replace(spec, initial_state=None)
    if args.contact:
        spec = dataclasses.replace(spec, contact=args.contact)
    if args.volumetric:
        c = spec.compound
        hyper = dataclasses.replace(c.hyperelastic, volumetric=args.volumetric)
        spec = dataclasses.replace(spec, compound=dataclasses.replace(c, hyperelastic=hyper))
    if args.refine > 1:
        spec = refined(spec, args.refine)
    progress = _Progress()
    observers = [DissipationByDepth(), StepReporter(progress)]
    fe_instead = False
    if args.fields:
        observers.append(FieldWriter(args.fields, every=args.fields_every))
        if shortcut_admits(spec):  # the closed form has no fields: the FE run instead
            spec = dataclasses.replace(spec, shortcut=False)
            fe_instead = True
            print("  the stored run is the closed form (shortcut); --fields runs the FE instead")
    # the campaign's path (the closed-form shortcut where admitted, failures as results), or
    # only the first attempt of the fallback chain
    result, wall = rerun_spec(spec, observers, first_attempt=args.first_attempt)
    progress.done()
    st = result.stats
    print(f"  rerun:  {result.status}, mu_force {result.mu_force:.6g}, "
          f"mu_energy {result.mu_energy:.6g}, "
          f"window drift {result.window_drift:.3g} (contact fraction "
          f"{result.contact_fraction:.4g}, drift {result.contact_drift:.3g}), "
          f"attempt {st.get('attempt', '?')}, "
          f"{st.get('steps', 0):.0f} steps, {st.get('newton_iterations', 0):.0f} "
          f"Newton iterations, "
          f"{st.get('cutbacks', 0):.0f} cut-backs, {st.get('stabilised_steps', 0):.0f} stabilised "
          f"(share {result.stabilisation_share:.3g}), {wall:.1f} s"
          + (f" ({result.reason.splitlines()[0]})" if result.reason else ""))
    done = Outcome(key, result.status, values=result_values(result))
    contact, rubber = balance_parts(done)
    if result.ok and math.isfinite(contact):
        print(f"  energy balance {energy_balance(done):+.3%}: the contact takes up "
              f"{contact:+.3%} of the friction work (its resolution and step), the rubber "
              f"stores {rubber:+.3%} over the window (docs/notes-energy.md)")
    if st.get("attempts"):
        print(f"  failed attempts: {st['attempts']}")
    if math.isfinite(result.road_intrusion):
        print(f"  road intrusion: {result.road_intrusion:.3g} contact elements deep "
              "(>= 1: the road's "
              "features are narrower than the contact elements)"
              + (f"; trust region refused {st['rejected_steps']:.0f} trial steps"
                 if st.get("rejected_steps") else ""))
    same = (not args.contact and args.refine == 1 and not args.first_attempt and not args.set
            and not args.volumetric and not fe_instead
            and math.isfinite(stored.values.get("mu_force", math.nan)))
    if same:
        diff = result.mu_force - stored.values["mu_force"]
        print(f"  reproduces the stored mu_force: difference {diff:.3g}")
    if args.out:
        written = write_run_outputs(result, spec, args.out)
        print("  written: " + ", ".join(str(p) for p in written.values()))
    if args.fields:
        fw = observers[-1]
        print(f"  fields: {fw.xdmf_path} (+ .h5, {len(fw.times)} steps)"
              + (f", {fw.contact_path}" if fw.contact_csv else ""))
    if args.json:
        doc = {"key": key, "label": lab, "stored": {"status": stored.status, **stored.values},
               "rerun": {"status": result.status, "reason": result.reason,
                         "mu_force": result.mu_force,
                         "mu_energy": result.mu_energy, "mu_interface": result.mu_interface,
                         "window_drift": result.window_drift,
                         "contact_fraction": result.contact_fraction,
                         "contact_drift": result.contact_drift,
                         "converged": result.converged,
                         "stabilisation_share": result.stabilisation_share,
                         "road_intrusion": result.road_intrusion,
                         "contact_elements": result.contact_elements,
                         "wall_time": wall, "stats": {k: v for k, v in st.items()
                                                      if isinstance(v, (int, float, str))}},
               "contact": spec.contact, "refine": args.refine, "first_attempt": args.first_attempt}
        Path(args.json).write_text(json.dumps(doc, indent=2, default=float, allow_nan=True))
        print(f"  written: {args.json}")
    return 0 if result.ok else 1


def _overrides(spec, items: list[str]):
    """spec with FIELD=VALUE overrides of its scalar fields (bool, int, float, str), converted
    to the field's current type; anything else is a ValueError naming the field."""
    changes = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not hasattr(spec, name):
            raise ValueError(f"--set {item!r}: expected FIELD=VALUE with a SlidingSpec field")
        old = getattr(spec, name)
        if isinstance(old, bool):
            if text.strip().lower() not in ("true", "false", "1", "0"):
                raise ValueError(f"--set {name}: {text!r} is not true or false")
            changes[name] = text.strip().lower() in ("true", "1")
        elif isinstance(old, (int, float)) and not isinstance(old, bool):
            try:
                changes[name] = type(old)(text)
            except ValueError:
                raise ValueError(f"--set {name}: {text!r} is not a {type(old).__name__}") from None
        elif isinstance(old, str):
            changes[name] = text
        else:
            raise ValueError(f"--set {name}: only scalar fields can be set "
                             f"(it is a {type(old).__name__})")
    return dataclasses.replace(spec, **changes)


class _Progress:
    """Where the rerun is, on stderr: an overwritten line on a terminal (at most every 0.5 s),
    a plain line every 30 s otherwise (logs)."""

    def __init__(self) -> None:
        self.tty = sys.stderr.isatty()
        self.last = -math.inf
        self.shown = False

    def __call__(self, info: dict) -> None:
        now = time.perf_counter()
        if now - self.last < (0.5 if self.tty else 30.0) and info.get("phase") == "sliding":
            return
        self.last = now
        if info.get("phase") == "sliding":
            left = info.get("left", math.nan)
            text = (f"sliding {info['distance']:.4g}/{info['slide_distance']:.4g} mm, step "
                    f"{info['step']}/{info['steps']}, {info['cutbacks']} cut-backs"
                    + (f", ~{left:.0f} s left" if math.isfinite(left) else "")
                    + (f" (after {info['after']} failed)" if info.get("after") else ""))
        else:
            text = f"{info.get('after')} failed; next attempt"
        self.shown = True
        if self.tty:
            print(f"\r  {text[:120]:<120}", end="", file=sys.stderr, flush=True)
        else:
            print(f"  {text}", file=sys.stderr, flush=True)

    def done(self) -> None:
        if self.tty and self.shown:
            print(file=sys.stderr)
