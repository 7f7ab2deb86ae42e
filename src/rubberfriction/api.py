"""The Python API: ``import rubberfriction as rf`` and call ``rf.<name>`` (``docs/api.md``).

A thin facade over the modules that do the work: each function below delegates to the code the
``rubberfriction`` command runs (named in its docstring), so a script and the command line give
the same numbers.  Nothing here computes physics.  Heavy modules (DOLFINx, PETSc, the campaign
driver) are imported inside the functions that need them, and the package exposes these names
lazily (``rubberfriction.__getattr__``, PEP 562): ``import rubberfriction`` stays cheap.

Units everywhere: mm, s, t, N, MPa, mJ, K (temperatures in kelvin); speeds mm/s; wavenumbers
q = 2 pi / lambda in 1/mm; 1D PSD C1D in mm^3 (Persson convention, h_rms^2 = 2 Int_0^inf C1D dq).
"""

from __future__ import annotations

import csv
import difflib
import math
from collections.abc import Sequence
from dataclasses import fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

import rubberfriction as _package
from rubberfriction.validation import InputError

if TYPE_CHECKING:  # types of the signatures only; imported by the functions that need them
    from rubberfriction.driver.multiscale.baseline import TheoryResult
    from rubberfriction.driver.multiscale.campaign import CampaignResult
    from rubberfriction.driver.scenes import Scene
    from rubberfriction.driver.surfaces import HDCFit, MultiScaleSurface, Profile
    from rubberfriction.driver.theory.curves import TheoryCurve
    from rubberfriction.forms.compound import Compound
    from rubberfriction.forms.prony import PronyFit

# the API's names: the one list is the package's (rubberfriction.__all__, loaded lazily)
__all__ = list(_package.__all__)

#: the tables of a campaign (``<output>/<name>.csv``; driver/multiscale/report/tables.py)
TABLES = ("results", "scales", "samples")


def _mpi() -> None:
    """Initialise MPI before anything imports DOLFINx/PETSc, as the command does
    (``driver/cli/run.py``: the campaign farm needs MPI_THREAD_MULTIPLE)."""
    from mpi4py import MPI  # noqa: F401


# ---------------------------------------------------------------------------------- scenes


def shipped_scenes() -> list[str]:
    """Names of the scenes shipped with the package (``driver/scenes/*.toml``), e.g.
    ``"default"``, ``"two_sine"``; any of them is a valid :func:`load_scene` argument.

    Delegates to ``driver.scenes.shipped_scenes``."""
    from rubberfriction.driver.scenes import shipped_scenes as names

    return names()


def load_scene(source: str | Path | None = None) -> Scene:
    """Load and validate a scene: a TOML file path, a shipped scene name
    (:func:`shipped_scenes`) or None for the default scene.  Returns a frozen ``Scene``
    (``scene.conditions.pressures`` in MPa, ``.velocities`` in mm/s, ``scene.output`` the
    output folder).  A bad value raises a ``SceneError`` (an :class:`InputError`) naming it.

    Delegates to ``driver.scenes.load_scene`` (what ``rubberfriction run`` reads)."""
    from rubberfriction.driver.scenes import load_scene as load

    return load(source)


def scene_from_toml(text: str, *, base: str | Path | None = None,
                    origin: str = "<code>") -> Scene:
    """Build a scene in code from TOML text (the keys of :func:`scene_schema`), validated as a
    scene file is.  ``base``: folder that relative paths in the text (profile files, compound
    files) are relative to (default: the current directory); ``origin`` names the text in
    messages.

    Delegates to ``driver.scenes.parse_scene``."""
    from rubberfriction.driver.scenes import parse_scene

    return parse_scene(text, origin, Path(base) if base is not None else Path.cwd())


def modify_scene(scene: Scene, **changes: Any) -> Scene:
    """A copy of ``scene`` with fields replaced: a top-level field by value
    (``output="out/"``, ``name="v100"``) or a section by a dict of its fields
    (``conditions={"velocities": (100.0,)}``, ``samples={"friction": 4}``,
    ``numerics={"elements_per_wavelength": 12}``).  Unknown section fields raise a
    ``SceneError``.  Values are taken as given (not re-validated like a TOML file; build
    from TOML with :func:`scene_from_toml` for that).

    Delegates to ``driver.scenes.override``."""
    from rubberfriction.driver.scenes import override

    return override(scene, **changes)


def scene_schema() -> str:
    """Every scene key with its default, unit and meaning, as commented TOML (what
    ``rubberfriction run --schema`` prints).

    Delegates to ``driver.scenes.schema_text``."""
    from rubberfriction.driver.scenes import schema_text

    return schema_text()


def _multiscale(scene: Scene, what: str) -> None:
    if scene.physics.thermal:
        raise InputError(f"{what}: scene {scene.name!r} is a thermal scene ([physics] thermal = "
                         "true); run it with `rubberfriction run`")


def check(scene: Scene) -> str:
    """Validate a scene fully without computing: read every compound and surface file it
    names, cut its samples, count the runs.  Returns the text ``rubberfriction run SCENE
    --check`` prints (plan: scales, points x runs per point = single-scale runs, output folder;
    resolution of the samples).  A bad input raises a ``SceneError``.  Not for thermal scenes.

    Delegates to ``driver.multiscale.campaign.check_summary``."""
    _multiscale(scene, "check")
    _mpi()
    from rubberfriction.driver.multiscale.campaign import check_summary

    return check_summary(scene)


def run(scene: Scene, *, output: str | Path | None = None, quiet: bool = False,
        fresh: bool = False, retry_failed: bool = False, report: bool = True
        ) -> CampaignResult:
    """Run (or resume) a multiscale campaign, as ``rubberfriction run`` does: a progress line
    on the terminal unless ``quiet``, every single-scale run kept in ``<output>/store`` (a
    second call reuses them; ``fresh`` moves the store aside, ``retry_failed`` recomputes
    stored failures), and with ``report`` the tables, plots and summary written into
    ``output`` (default ``scene.output``) and the summary printed unless ``quiet``.

    Returns the ``CampaignResult``: ``.points`` (one ``PointResult`` per compound, p, v with
    ``.mu.mean``, ``.ok``), ``.output``, ``.wall_time`` (s); read it with :func:`table` or
    :func:`arrays`.  Not for thermal scenes.  Under ``mpirun`` every rank calls this and only
    rank 0 gets the result (None elsewhere).

    Delegates to ``driver.multiscale.campaign.run_scene``."""
    _multiscale(scene, "run")
    _mpi()
    from rubberfriction.driver.multiscale.campaign import run_scene

    return run_scene(scene, output=output, quiet=quiet, fresh=fresh, retry_failed=retry_failed,
                     report=report)


def mesh_check(scene: Scene, result: CampaignResult | None, *, select: str | None = None,
               factor: int = 2, quiet: bool = False) -> list[dict[str, Any]] | None:
    """How far a finished campaign is from mesh convergence, as ``rubberfriction run SCENE
    --mesh-check [SELECT] --mesh-factor F``: the selected runs (default: sample 0 of every
    scale's friction runs; ``select`` in ``--fields``' grammar) run again with contact elements
    ``factor`` times shorter and the stored inputs, kept in the campaign's store;
    ``mesh_check.csv`` / ``.png`` and the summary's ``mesh:`` block written.  Returns one dict
    per checked run (``mu``, ``mu_fine``, ``change`` = mu_fine / mu - 1, ``converged``, ...).
    ``result``: what :func:`run` returned for ``scene``; under ``mpirun`` every rank calls
    this (with None on the ranks where :func:`run` returned None) and only rank 0 gets rows.

    Delegates to ``driver.multiscale.mesh_check.run_mesh_check``."""
    _mpi()
    from rubberfriction.driver.multiscale.mesh_check import mesh_selection, run_mesh_check

    rows = run_mesh_check(scene, result, mesh_selection(select, scene, factor), factor=factor,
                          quiet=quiet)
    return None if rows is None else [r.as_dict() for r in rows]


# --------------------------------------------------------------------------------- results


def _number(text: str) -> Any:
    try:
        return float(text)
    except ValueError:
        return text


def table(result: CampaignResult | str | Path, which: str = "results") -> list[dict[str, Any]]:
    """The rows of a campaign table as plain dicts (no pandas): ``which`` is ``"results"`` (one
    row per compound, p, v: ``mu``, ``mu_std``, ``mu_ci95``, ``pressure_MPa``,
    ``velocity_mm_s``, ``status``, ...), ``"scales"`` (per point and scale) or ``"samples"``
    (every single-scale run).  ``result``: what :func:`run` returned, or the output folder of
    a finished campaign (its ``<which>.csv`` is read; numbers come back as floats).

    Delegates to ``driver.multiscale.report.tables.point_rows`` / ``scale_rows`` / ``sample_rows``
    (the rows ``results.csv``, ``scales.csv``, ``samples.csv`` are written from)."""
    if which not in TABLES:
        raise InputError(f"table(which={which!r}): expected one of {', '.join(TABLES)}")
    if isinstance(result, (str, Path)):
        path = Path(result) / f"{which}.csv"
        if not path.is_file():
            raise InputError(f"table({str(result)!r}): no {which}.csv there (expected the output "
                             "folder of a finished campaign)")
        with open(path, newline="") as fh:
            return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(fh)]
    from rubberfriction.driver.multiscale.report import tables

    rows = {"results": tables.point_rows, "scales": tables.scale_rows,
            "samples": tables.sample_rows}[which]
    return rows(result.points)


def arrays(result: CampaignResult | str | Path, which: str = "results"
           ) -> dict[str, np.ndarray]:
    """The columns of :func:`table` as numpy arrays (float where every value is a number,
    NaN for a missing one; str otherwise), e.g. ``arrays(res)["mu"]`` over
    ``arrays(res)["velocity_mm_s"]``."""
    rows = table(result, which)
    names: list[str] = []
    for r in rows:
        names += [k for k in r if k not in names]
    out = {}
    for k in names:
        col = [r.get(k, math.nan) for r in rows]
        numeric = all(isinstance(v, (int, float, np.integer, np.floating))
                      and not isinstance(v, bool) for v in col)
        out[k] = np.asarray(col, dtype=float) if numeric else np.asarray([str(v) for v in col])
    return out


def format_table(rows: Sequence[dict[str, Any]], columns: Sequence[str] | None = None) -> str:
    """A plain-text table of dict rows (e.g. :func:`table`): one line per row, the given
    ``columns`` (default: every key), numbers with 4 significant digits."""
    if columns is None:
        columns = []
        for r in rows:
            columns += [k for k in r if k not in columns]

    def cell(v: Any) -> str:
        if isinstance(v, (float, np.floating)):
            return f"{v:.4g}"
        return str(v)

    body = [[cell(r.get(c, "")) for c in columns] for r in rows]
    widths = [max([len(c)] + [len(b[i]) for b in body]) for i, c in enumerate(columns)]
    lines = ["  ".join(c.rjust(w) for c, w in zip(columns, widths))]
    lines += ["  ".join(x.rjust(w) for x, w in zip(b, widths)) for b in body]
    return "\n".join(lines)


# -------------------------------------------------------------------------------- surfaces


def load_profile(path: str | Path, **options: Any) -> Profile:
    """Read a line-scan road profile (text/CSV, ``.gz``, HDF5) in mm, cleaned (uniform grid,
    dropouts and outliers repaired).  ``options``: ``x_col``, ``h_col``, ``units``
    (``"mm"``, ``"um"``, ``"auto"``, ...), ``dx``, ``delimiter``, ``skiprows``, ``clean``, ...
    Returns a ``Profile`` (``.x``, ``.h`` arrays in mm, ``.dx``, ``.length``).  A bad file
    raises a ``ProfileFormatError`` (a ``SurfaceError``, an :class:`InputError`).

    Delegates to ``driver.surfaces.load_profile`` (``rubberfriction surface analyse``)."""
    from rubberfriction.driver.surfaces import load_profile as load

    return load(path, **options)


def default_profile() -> Profile:
    """The road profile shipped with the package: the CAPTIF chipseal laser scan (station 0,
    0.0375 mm spacing, MIT licence), read and cleaned by :func:`load_profile`.  It is the
    measured part of the default road.

    Delegates to ``driver.surfaces.find_station0`` and ``load_profile``."""
    from rubberfriction.driver.surfaces import find_station0

    return load_profile(find_station0()[0])


def default_road() -> MultiScaleSurface:
    """The default four-scale road (edges 20-3-0.3-0.04-0.003 mm): the measured CAPTIF scan
    for the scales it resolves and a generated self-affine extension below;
    ``.scales[i].profile`` is scale i's band profile, ``.describe()`` says which is which.

    Delegates to ``driver.surfaces.default_road``."""
    from rubberfriction.driver.surfaces import default_road as road

    return road()


def split_bands(profile: Profile, edges: Sequence[float], **options: Any) -> list[Profile]:
    """Split a profile into band profiles between descending wavelength edges in mm, eq.
    (6.10): ``[20, 3, 0.3]`` gives the bands 20-3 and 3-0.3 mm, on the profile's x; their sum
    is the profile band-limited to 20-0.3 mm.  ``options``: ``filter`` (``"ideal"``,
    ``"cosine"``), ``transition``, ``allow_unresolved``.

    Delegates to ``driver.surfaces.band_split``."""
    from rubberfriction.driver.surfaces import band_split

    return band_split(profile, edges, **options)


def psd(profile: Profile, *, window: str | None = "hann", detrend: str | None = "mean"
        ) -> tuple[np.ndarray, np.ndarray]:
    """One-dimensional PSD ``(q, C1D)`` of a profile: q in 1/mm (2 pi k / L, k = 1 .. N/2),
    C1D in mm^3, Persson's two-sided convention, so h_rms^2 = 2 Int_0^inf C1D dq; with
    ``window=None`` exactly ``2 * sum(C1D) * q[0] == mean(h^2)`` of the detrended heights
    (Parseval).  ``window="hann"`` (default) suppresses leakage of non-periodic records.

    Delegates to ``driver.surfaces.psd_1d``."""
    from rubberfriction.driver.surfaces import psd_1d

    return psd_1d(profile, window=window, detrend=detrend)


def hdc(profile: Profile, **options: Any) -> tuple[np.ndarray, np.ndarray]:
    """Height-difference correlation, eq. (2.4): ``(lambda, C_HDC)``, lags lambda in mm and
    C_HDC = <(h(x + lambda) - h(x))^2> in mm^2 at about 60 log-spaced lags up to half the
    record.  ``options``: ``lags`` (integer sample lags), ``n_lags``, ``max_lag_fraction``,
    ``periodic``.

    Delegates to ``driver.surfaces.hdc``."""
    from rubberfriction.driver.surfaces import hdc as correlation

    return correlation(profile, **options)


def fit_hdc(lam: np.ndarray, c_hdc: np.ndarray,
            fit_range: tuple[float, float] | None = None) -> HDCFit:
    """Fit eq. (2.5) to an HDC (from :func:`hdc`): Hurst exponent ``.H``, correlation lengths
    ``.xi_par`` (mm, along the road) and ``.xi_perp`` (mm, height); ``fit_range`` (mm) limits
    the lags used.

    Delegates to ``driver.surfaces.fit_hdc``."""
    from rubberfriction.driver.surfaces import fit_hdc as fit

    return fit(lam, c_hdc, fit_range)


# ------------------------------------------------------------------------------- compounds


def load_compound(name: str | Path) -> Compound:
    """A rubber compound: a shipped name (``"tread_default"``, ``"A"``, ``"m1"``, ...) or a
    compound TOML file (format ``forms/data/README.md``).  ``.complex_modulus(omega, T)``
    gives E* in MPa at omega in rad/s and T in K; ``.summary()`` describes it.

    Delegates to ``forms.material_files.load_compound``."""
    from rubberfriction.forms.material_files import load_compound as load

    return load(name)


def fit_compound(dma: str | Path, *, base: str = "tread_default", terms: int | None = None,
                 freq_unit: str = "Hz", columns: Sequence[str | int] = ("f", "E_stor", "E_loss"),
                 T: float | None = None, fix_E_inf: bool = False,
                 name: str | None = None) -> tuple[Compound, PronyFit]:
    """Fit a Prony series (eq. 3.34, non-negative least squares on E' and E'') to a DMA master
    curve (pyvisco CSV: header row, optional units row, frequency, E', E'' in MPa unless the
    units row says otherwise) and make a compound of it, as ``rubberfriction material fit``
    does: Mooney-Rivlin, WLF and thermal data of ``base``, relaxation times shifted to base's
    WLF reference temperature from ``T`` (K, the master curve's temperature; None: already
    there).  ``terms``: number of Prony terms (default one per decade); ``fix_E_inf``: fix
    E_inf to base's Mooney-Rivlin value.  Returns ``(compound, fit)``; ``fit.report()``
    gives the relative errors.  For a scene, write a compound TOML with ``[prony] fit_from``.

    Delegates to ``forms.prony.read_dma_csv``, ``fit_prony`` and ``series_at_reference``."""
    from rubberfriction.forms import prony

    base_compound = load_compound(base)
    omega, e1, e2 = prony.read_dma_csv(dma, freq_unit=freq_unit, columns=tuple(columns))
    fit = prony.fit_prony(omega, e1, e2, n_terms=terms,
                          E_inf=base_compound.E_inf if fix_E_inf else None)
    series, note = prony.series_at_reference(fit, base_compound, T)
    label = name or Path(dma).stem
    compound = replace(base_compound, name=label, prony=series,
                       description=f"Prony series fitted to {Path(dma).name}; equilibrium, WLF "
                                   f"and thermal data of {base_compound.name}",
                       source=f"Prony: fit to {Path(dma).name}"
                              + (f" ({note})" if note else "")
                              + f"; Mooney-Rivlin/WLF/thermal: {base_compound.name}")
    return compound, fit


# ---------------------------------------------------------------------------------- theory


def theory(scene: Scene | str | Path | None = None, **request: Any) -> TheoryResult:
    """The analytical mu(v) baselines (Persson line roughness and isotropic eq. 2.10,
    Kluppel-Heinrich eq. 2.9), as ``rubberfriction theory`` computes them.  ``scene`` (a
    ``Scene``, file or shipped name) gives surface, first compound and pressure, speeds, T0;
    ``request`` overrides: ``compound``, ``pressure`` (MPa), ``velocities`` (mm/s), ``T0``
    (K), ``surface`` (``"default"``, ``"four_scale"`` or a profile file), ``lambda_max``,
    ``lambda_min`` (mm), ``models``, ``gamma``, ``nu``, ``flash``, ``adhesion`` (a
    ``BellLaw``).  Without a scene: the default road, tread_default, 0.3 MPa, 50 speeds.

    Returns a ``TheoryResult``: ``.curves`` (``.model``, ``.v`` mm/s, ``.mu``, ``.area``
    A/A0) and ``.info``.  Delegates to ``driver.multiscale.baseline`` (``TheoryRequest``,
    ``request_from_scene``, ``evaluate``)."""
    from rubberfriction.driver.multiscale import baseline

    allowed = [f.name for f in fields(baseline.TheoryRequest)]
    for key in request:
        if key not in allowed:
            close = difflib.get_close_matches(key, allowed, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise InputError(f"theory({key}=...): not a theory input{hint} (expected one of "
                             f"{', '.join(allowed)})")
    if "velocities" in request:
        request["velocities"] = tuple(float(v) for v in np.atleast_1d(request["velocities"]))
    if scene is None:
        req = baseline.TheoryRequest(**request)
    else:
        loaded = scene if not isinstance(scene, (str, Path)) else load_scene(scene)
        req = baseline.request_from_scene(loaded, **request)
    return baseline.evaluate(req)


def theory_curves(q: np.ndarray, c1d: np.ndarray, compound: str | Path, pressure: float,
                  velocities: Sequence[float], *, T0: float | None = None,
                  models: Sequence[str] = ("persson-1d", "persson-2d", "kluppel-heinrich"),
                  qmin: float | None = None, qmax: float | None = None) -> list[TheoryCurve]:
    """mu(v) of the analytical models from a profile PSD you computed (:func:`psd`): q in
    1/mm, C1D in mm^3, ``compound`` a name or TOML file, ``pressure`` in MPa, ``velocities``
    in mm/s, ``T0`` in K (None: the WLF reference), ``qmin``/``qmax`` the wavenumber range
    (1/mm; default the PSD's).  Returns one ``TheoryCurve`` per model (``.v``, ``.mu``,
    ``.area``).

    Delegates to ``driver.multiscale.baseline.load_rubber`` and
    ``driver.theory.theory_curves``."""
    from rubberfriction.driver.multiscale.baseline import load_rubber
    from rubberfriction.driver.theory import theory_curves as curves

    rubber, _ = load_rubber(str(compound))
    return curves(np.asarray(q, dtype=float), np.asarray(c1d, dtype=float), rubber,
                  float(pressure), np.atleast_1d(np.asarray(velocities, dtype=float)), T0=T0,
                  models=tuple(models), qmin=qmin, qmax=qmax)


# ---------------------------------------------------------------------------- verification


def verification_cases() -> dict[str, str]:
    """The analytical verification cases, name -> what they check (``hertz``,
    ``westergaard``, ``patch``, ``sliding-block``, ...); any of them runs with :func:`verify`.

    Delegates to ``driver.verification.CASES``."""
    from rubberfriction.driver.verification import CASES

    return {name: text for name, (_, text) in CASES.items()}


def verify(case: str, **parameters: Any) -> dict[str, Any]:
    """Run a verification case against its closed form, as ``rubberfriction verify CASE``
    does; ``parameters`` are the case's options with underscores (``R=10.0`` mm, ``E=6.0``
    MPa, ``elements_per_a=(8, 16)``, ...; see ``rubberfriction verify CASE --help``), every
    other option at its default.  Returns the result dict: ``"parameters"``, ``"checks"``
    (each with ``quantity``, ``computed``, ``analytical``, ``rel_error``, ``tolerance``,
    ``passed``) and ``"notes"``.  An unknown case or parameter raises an
    :class:`InputError`; a solve that does not converge a ``SolverFailure``.

    Delegates to the case module's ``add_arguments`` and ``run``
    (``driver.verification.CASES``)."""
    import argparse
    import importlib

    cases = verification_cases()
    if case not in cases:
        close = difflib.get_close_matches(case, list(cases), n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise InputError(f"verify({case!r}): no such case{hint} (cases: {', '.join(cases)})")
    _mpi()
    from rubberfriction.driver.verification import CASES
    from rubberfriction.driver.verification.parameters import check_parameters

    module = importlib.import_module(CASES[case][0])
    parser = argparse.ArgumentParser(prog=f"rubberfriction verify {case}")
    module.add_arguments(parser)  # the options of the command; their defaults
    args = parser.parse_args([])
    known = [a.dest for a in parser._actions if a.dest != "help"]
    for key, value in parameters.items():
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise InputError(f"verify({case!r}, {key}=...): not a parameter of the case{hint} "
                             f"(parameters: {', '.join(known)})")
        setattr(args, key, list(value) if isinstance(value, tuple) else value)
    args.case, args.json = case, None
    check_parameters(parser, args)  # an impossible value: one InputError naming the option
    return module.run(args)


def study_trends(*, quick: bool = False, output: str | Path | None = None,
                 quiet: bool = False, fresh: bool = False, **settings: Any) -> Any:
    """Run (or resume) the thesis' trend study, as ``rubberfriction study trends`` does
    (``docs/trends.md``): ``quick`` for its smaller variant, ``output`` the folder (default
    ``rf-results/trends`` or ``rf-results/trends-quick``), ``settings`` any field of
    ``driver.study.cases.TrendSettings`` (``cutoff=0.3`` mm, ``flash_cutoff=0.04`` mm,
    ``friction_samples=3``, ``flash=False``, ...).  Returns a ``StudyResult`` (``.rows``: one
    ``TrendRow`` per trend with ``.verdict``, ``.comparisons`` (each ``.ratio``, ``.sign``) and
    ``.why``; ``.files``) on rank 0, None elsewhere.  An unknown setting raises an
    :class:`InputError`.

    Delegates to ``driver.study.run.run_trends``."""
    from rubberfriction.driver.study.cases import TrendSettings, quick_settings

    base = quick_settings() if quick else TrendSettings()
    known = [f.name for f in fields(base)]
    for key in settings:
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise InputError(f"study_trends({key}=...): not a setting{hint} (settings: "
                             f"{', '.join(known)})")
    _mpi()
    from rubberfriction.driver.study.run import run_trends

    folder = output if output is not None else (
        "rf-results/trends-quick" if quick else "rf-results/trends")
    return run_trends(replace(base, **settings), folder, quiet=quiet, fresh=fresh)
