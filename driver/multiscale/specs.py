"""One SlidingSpec per run from the scene's numerical settings, and the scene's compounds.

:class:`SpecBuilder` is the ``make_spec`` of the planners: from a point, a scale's sample, the
pressure and the friction coming from the scale below it writes down every input of one
single-scale run (thesis 6.5.1 element size rule, the band-limited rigid master).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from rubberfriction.driver.multiscale.results import Point
from rubberfriction.driver.scenes import Scene, SceneError, surface_scale_names
from rubberfriction.driver.runtime.store import Store, StoredRun, canonical
from rubberfriction.driver.sliding.spec import InitialState, SlidingSpec
from rubberfriction.driver.surfaces.profile import UNIFORM_RTOL
from rubberfriction.driver.surfaces.samples import refine_periodic
from rubberfriction.forms.material_files import load_compound
from rubberfriction.meshes.block import polyline_element_size
from rubberfriction.meshes.common import contact_divisions


#: the master keeps a subset of a sample's points only where its polyline stays within this
#: part of a contact element of every point left out (``master_polyline``)
MASTER_DEVIATION = 0.005


def master_polyline(x: np.ndarray, h: np.ndarray, period: float, lam_min: float,
                    points_per_wavelength: int, uniform: bool = False,
                    max_deviation: float = math.inf) -> tuple[np.ndarray, np.ndarray]:
    """The rigid master polyline of a periodic sample with about ``points_per_wavelength``
    vertices per shortest wavelength ``lam_min`` of its band, every vertex a point of the sample:

    * coarser samples are refined by band-limited interpolation by a whole factor
      (``surfaces.samples.refine_periodic``).  The default road's micro2 samples (0.04-0.003 mm
      band at 0.0005 mm spacing, rms slope 4) have 6 points per shortest wavelength; refined to
      36, far fewer of the default scene's micro2 runs fail (docs/performance.md);
    * samples finer by a factor k_max >= 2 keep a subset of their points with at least
      ``points_per_wavelength`` per ``lam_min`` whose polyline passes within ``max_deviation``
      of every sample point: every k-th point, k the largest such divisor of the point count in
      [k_max / 2, k_max] (the spacing stays uniform over the periodic seam), else (not
      ``uniform``: the node-to-surface contact needs a uniform master) the points nearest to
      n / k equal steps, k as large as passes.  The mortar integrals cost one term per master
      segment a slave segment meets: the four-scale road's macro samples (20 mm at 4 um, 5000
      points, 125 per contact element) spent 88 % of a run in contact; every 20th point stays
      within 0.4 % of an element of the sample, and mu moves by 4e-4 relative
      (docs/performance.md, "Contact cost and the road's vertices").  The default road's macro
      samples have sharp tips between their points (every 2nd point: 1.3 % of an element off,
      a macro run at 1 mm/s 3.9 % off): kept whole.

    Non-uniform samples and ``points_per_wavelength = 0`` pass as they are."""
    n = x.size
    if points_per_wavelength <= 0 or n < 4 or not period > 0.0:
        return x, h
    dx = period / n
    if not np.allclose(np.diff(x), dx, rtol=UNIFORM_RTOL, atol=0.0):
        return x, h
    factor = math.ceil(points_per_wavelength * dx / lam_min - 1e-9)
    if factor > 1:
        return x[0] + np.arange(n * factor) * (dx / factor), refine_periodic(h, factor)
    k_max = math.floor(lam_min / (points_per_wavelength * dx) + 1e-9)
    whole = [k for k in range(k_max, 1, -1) if n % k == 0 and 2 * k >= k_max]
    near = [] if uniform else [k for k in range(k_max, 1, -1) if k not in whole]
    for k in whole + near:
        if n % k == 0:
            keep = np.arange(0, n, k)
        else:
            m = math.ceil(n / k)
            keep = np.unique(np.floor(np.arange(m) * (n / m) + 0.5).astype(int) % n)
        xp, hp = np.append(x[keep], x[keep[0]] + period), np.append(h[keep], h[keep[0]])
        if np.max(np.abs(np.interp(x, xp, hp) - h)) <= max_deviation:
            return x[keep], h[keep]
    return x, h


#: vertices of the rigid master per contact element at least (``master_points``)
MASTER_POINTS_PER_ELEMENT = 4


def master_points(num: Any) -> int:
    """Vertices of the master per shortest wavelength for a scale's numerics: the scene's
    ``master_points_per_wavelength`` (0: the sample as cut), at least MASTER_POINTS_PER_ELEMENT
    per contact element of a finer mesh (``elements_per_wavelength``)."""
    p = int(num.master_points_per_wavelength)
    return max(p, MASTER_POINTS_PER_ELEMENT * int(num.elements_per_wavelength)) if p > 0 else 0


def points(scene: Scene) -> list[Point]:
    """The (compound, p, v) points of a scene, in the order campaigns run and report them."""
    c = scene.conditions
    return [Point(name, p, v) for name in c.compounds for p in c.pressures for v in c.velocities]


class SpecBuilder:
    """SlidingSpec of one run from the scene's settings (the ``make_spec`` of the planners)."""

    def __init__(self, scene: Scene, compounds: dict[str, Any]):
        self.scene = scene
        self.compounds = compounds
        # the numerics of scale i: [numerics] with its [numerics.<name>] table
        self.numerics = [scene.numerics.for_scale(nm) for nm in surface_scale_names(scene.surface)]

    def _window_quantity(self, role: str) -> str:
        """What a run's converged window waits for (sliding.window.WINDOW_QUANTITIES): what it
        hands on.  A pressure-branch run hands on its pooled pressure (eq. 6.11), the reciprocal
        of its contact fraction; a friction-branch run its mu, and with adhesion also its contact
        fraction (the real contact area of eq. 7.5)."""
        if role == "down":
            return "contact"
        return "both" if self.scene.physics.adhesion else "mu"

    def __call__(self, point: Point, scale: int, sample: Any, pressure: float, friction: Any,
                 role: str) -> Any:
        num = self.numerics[scale]
        window, slide = num.window_start, num.slide_periods
        tol, steady, extrapolate = 0.0, num.steady_state, num.period_extrapolation
        if num.window == "converged":
            tol = num.convergence_tol
            slide = num.pressure_slide_periods if role == "down" else num.max_slide_periods
        if role == "micro" and self.scene.separated is not None:
            # thesis 6.2.3: the micro average includes the run-in, over a fixed distance
            sep = self.scene.separated
            window, slide = sep.micro_window_start, sep.micro_slide_periods
            tol, steady, extrapolate = 0.0, False, False
        x, h, period = np.asarray(sample.x, float), np.asarray(sample.h,
                                                               float), float(sample.period)
        if x.size > 1 and abs(x[-1] - x[0] - period) < 1e-9 * period:
            x, h = x[:-1], h[:-1]  # one period given: the closing vertex repeats the first
        band = getattr(sample, "band", None)
        lam_band = float(band[1]) if band is not None and np.isfinite(band[1]) and band[1] > 0 \
            else None  # the band's short edge, where the sample knows its band
        if lam_band is not None:
            x, h = master_polyline(x, h, period, lam_band, master_points(num),
                                   uniform=num.contact == "surface",
                                   max_deviation=MASTER_DEVIATION * lam_band
                                   / num.elements_per_wavelength)
        base = SlidingSpec(surface_x=x, surface_h=h, period=period, pressure=float(pressure),
                           velocity=float(point.velocity), compound=self.compounds[point.compound],
                           temperature=self.scene.conditions.T0, friction=friction,
                           element=num.element, newton=num.newton,
                           newton_rtol=num.newton_rtol,
                           contact=num.contact, elements_per_wavelength=num.elements_per_wavelength,
                           grading=num.grading, compression_steps=num.compression_steps,
                           window_start=window, converge_tol=tol, steady_state=steady,
                           window_periods=num.window_periods,
                           period_extrapolation=extrapolate,
                           window_quantity=self._window_quantity(role),
                           shortcut=num.shortcut,
                           max_cutbacks=num.max_cutbacks, stabilisation=num.stabilisation,
                           min_jacobian=num.min_jacobian,
                           penalty_alpha=num.penalty_alpha,
                           tangential_penalty=num.tangential_penalty)
        # contact element size: the shortest wavelength of the sample / elements_per_wavelength;
        # the shortest wavelength is the band's short edge (thesis 6.5.1), else (or if shorter)
        # the run's estimate from slope sign changes
        hc = float(polyline_element_size(base.surface_x, base.surface_h, base.period,
                                         base.elements_per_wavelength))
        if lam_band is not None:
            hc = min(hc, lam_band / num.elements_per_wavelength)
        # the mesh's column width: a whole number of columns per period, so that the step is
        # a whole fraction of a column (the "column" Newton start, driver.sliding.steps)
        hc = period / contact_divisions(period, None, hc) if period > 0 else hc
        return dataclasses.replace(base, h_contact=hc, step_length=num.step_per_element * hc,
                                   slide_distance=slide * period)


def load_compounds(scene: Scene) -> dict[str, Any]:
    """Compounds of the scene by the name written in it; elastic (no Prony) without hysteresis."""
    out = {}
    for i, (name, path) in enumerate(zip(scene.conditions.compounds,
                                         scene.conditions.compound_paths)):
        try:
            c = load_compound(path)
        except ValueError as err:
            raise SceneError(f"{scene.source}: [conditions].compounds[{i}] = {name!r}: "
                             f"{err}") from None
        if not scene.physics.hysteresis:
            c = dataclasses.replace(c, prony=None)  # no history variables are built
        out[name] = c
    return out


def find_key(store: Store, prefix: str) -> str:
    """The store key starting with ``prefix`` (at least 6 characters), or a clear error."""
    if len(prefix) < 6:
        raise ValueError(f"run key {prefix!r}: give at least 6 characters of the key "
                         "(samples.csv, column key)")
    hits = [k for k in store.keys() if k.startswith(prefix)]
    if not hits:
        raise ValueError(f"run key {prefix!r}: no such run in {store.root}")
    if len(hits) > 1:
        raise ValueError(f"run key {prefix!r} is ambiguous in {store.root}: "
                         + ", ".join(h[:12] for h in hits))
    return hits[0]


#: SlidingSpec fields whose default changed the computation when they were added: a run file
#: written before holds no value for them and was computed with this one
BEFORE_FIELD: dict[str, Any] = {"stabilisation": 0.0, "min_jacobian": 0.0,
                                "period_extrapolation": False}
#: the same for fields of the compound's Mooney-Rivlin spring
BEFORE_HYPERELASTIC: dict[str, Any] = {"volumetric": "quadratic"}


def _before_fields(compound: Any, image: dict) -> Any:
    """``compound`` with the Mooney-Rivlin fields a run file written before them does not hold set
    to what that run computed with (``BEFORE_HYPERELASTIC``); the stored ``image`` of the compound
    gets the same values, so the two compare equal."""
    hyper = image["hyperelastic"]
    missing = {k: v for k, v in BEFORE_HYPERELASTIC.items() if k not in hyper}
    if not missing:
        return compound
    hyper.update(missing)
    return dataclasses.replace(
        compound, hyperelastic=dataclasses.replace(compound.hyperelastic, **missing))


def stored_spec(stored: StoredRun, compound_dir: Path | None = None,
                states: Callable[[str], dict | None] | None = None,
                compound_files: Mapping[str, str | Path] | None = None) -> SlidingSpec:
    """The SlidingSpec of a stored run, rebuilt from its run file: the surface arrays, the scalar
    inputs, the compound loaded again by its name (from ``compound_dir/<name>.toml`` where that
    file exists: a folder of kept runs holds the compound files as they were when it ran; else
    ``compound_files[name]``, a scene's compound file by the compound's name; else the shipped
    file), a constant (or no) friction coefficient.

    The rebuilt spec is checked against the canonical image the run file holds (every field,
    arrays by their sha256, the compound by all its values), so a rerun computes exactly the
    stored inputs or refuses: a compound file that changed since the run, or a friction law
    object (a mu(p, v) spline) that a run file does not hold, is an error naming the field.  A
    warm-started run (``SlidingSpec.initial_state``) takes its initial state from the run it
    came from: ``states`` (``Store.load_state``) gives that run's kept final state."""
    key = stored.key
    image = json.loads(stored.inputs["spec"])
    if image.get("__type__") != "SlidingSpec":
        raise ValueError(f"run {key[:12]}: its inputs are a {image.get('__type__')}, not a "
                         "SlidingSpec")
    kw: dict[str, Any] = {}
    for f in dataclasses.fields(SlidingSpec):
        v = image.get(f.name)
        if f.name not in image and f.name not in ("surface_x", "surface_h", "compound"):
            if f.name in BEFORE_FIELD:  # a field added after the run: what the run computed with
                kw[f.name] = BEFORE_FIELD[f.name]
            continue  # otherwise its default is what the run computed with
        if f.name in ("surface_x", "surface_h"):
            kw[f.name] = np.asarray(stored.inputs[f.name], dtype=float)
        elif f.name == "compound":
            name = str(stored.inputs.get("compound"))
            try:
                kept = compound_dir / f"{name}.toml" if compound_dir is not None else None
                source = kept if kept is not None and kept.is_file() else \
                    (compound_files or {}).get(name, name)
                kw["compound"] = _before_fields(load_compound(source), v)
            except ValueError as err:
                raise ValueError(f"run {key[:12]}: compound {name!r}: {err}") from None
        elif f.name == "friction":
            if isinstance(v, dict):
                raise ValueError(f"run {key[:12]}: friction is a {v.get('__type__')} law; a run "
                                 "file holds constant coefficients only, so this run cannot be "
                                 "rebuilt")
            kw["friction"] = v
        elif f.name == "temperature_layers":
            kw[f.name] = tuple(tuple(float(x) for x in layer) for layer in v)
        elif f.name == "initial_state" and isinstance(v, dict):
            source = str(v.get("source", ""))
            state = states(source) if states is not None and source else None
            if state is None:
                raise ValueError(f"run {key[:12]}: it slides on from the final state of run "
                                 f"{source[:12]}, which this store does not hold")
            kw[f.name] = InitialState.stored(state, source)
        elif v in ("nan", "inf", "-inf"):
            kw[f.name] = float(v)
        else:
            kw[f.name] = v
    spec = SlidingSpec(**kw)
    rebuilt = canonical(spec)
    differ = sorted(k for k in image if rebuilt.get(k) != image[k])
    if differ:
        hint = (" (the compound file changed since the run)" if differ == ["compound"] else "")
        raise ValueError(f"run {key[:12]}: the rebuilt inputs differ from the stored ones in "
                         f"{', '.join(differ)}{hint}")
    return spec
