"""The Python API (``import rubberfriction as rf``, docs/api.md): the tutorial runs and its numbers
agree with closed forms, every API name resolves with a docstring, and importing the package
loads neither DOLFINx nor PETSc nor MPI."""

from __future__ import annotations

import csv
import inspect
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

import rubberfriction as rf

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial.py"
FLOAT = r"([-+0-9.eE]+)"


def _run_tutorial(cwd: Path) -> str:
    env = {**os.environ, "OMP_NUM_THREADS": "1"}  # PYTHONPATH passed through (a shim, if any)
    out = subprocess.run([sys.executable, str(TUTORIAL)], cwd=cwd, env=env, capture_output=True,
                         text=True, timeout=900)
    assert out.returncode == 0, out.stdout[-2000:] + out.stderr[-4000:]
    return out.stdout


def test_tutorial_runs_and_its_numbers_hold(tmp_path: Path) -> None:
    """docs/tutorial.py end to end (about 20 s): its mu table is the campaign's results.csv; the
    PSD integral of the shipped profile is the profile's variance (Parseval, exact for the
    unwindowed estimator: 2 sum C1D dq = mean((h - mean h)^2), CONTRIBUTING convention
    h_rms^2 = 2 Int_0^inf C1D dq; rel. 1e-9); the Hertz half-width and peak pressure agree with
    the plane-strain closed form a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a),
    E* = E / (1 - nu^2) within the 2 % the hertz case states."""
    text = _run_tutorial(tmp_path)

    # mu: what the script prints is what the campaign wrote (read here with csv, not the API)
    printed = {m[0]: float(m[1]) for m in re.findall(rf"mu at (\S+): {FLOAT}  \(ok\)", text)}
    with open(tmp_path / "rf-results" / "first_script" / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(printed) == 2
    for row in rows:
        p, v = float(row["pressure_MPa"]), float(row["velocity_mm_s"])
        point = f"{row['compound']}/p={p:g}/v={v:g}"
        assert row["status"] == "ok"
        assert math.isclose(printed[point], float(row["mu"]), rel_tol=1e-5)  # printed to 6 digits
        assert 0.0 < float(row["mu"]) < 1.0

    # PSD: Parseval against the variance computed here from the shipped profile
    psd_sum, psd_var = map(float, re.search(
        rf"2 sum\(C1D\) dq = {FLOAT} mm\^2; variance of the profile = {FLOAT}", text).groups())
    h = rf.default_profile().h
    variance = float(np.mean((h - h.mean()) ** 2))
    assert math.isclose(psd_sum, variance, rel_tol=1e-9)
    assert math.isclose(psd_var, variance, rel_tol=1e-12)

    # Hertz: the closed form evaluated here at the printed load
    R, E, nu, P = map(float, re.search(
        rf"Hertz: R = {FLOAT} mm, E = {FLOAT} MPa, nu = {FLOAT}, P = {FLOAT} N/mm", text).groups())
    e_star = E / (1.0 - nu * nu)
    a = math.sqrt(4.0 * P * R / (math.pi * e_star))
    exact = {"half-width a": a, "peak pressure p0": 2.0 * P / (math.pi * a)}
    tolerance = 0.02  # the hertz case's stated tolerance (driver/verification/hertz.py)
    for quantity, value in exact.items():
        computed, tol = map(float, re.search(
            rf"Hertz {quantity}: computed {FLOAT}, closed form \S+, relative error \S+ "
            rf"\(tolerance {FLOAT}\)", text).groups())
        assert tol == tolerance
        # the case brings the load within 0.5 % of P: a moves by at most 0.25 % of it
        assert abs(computed / value - 1.0) <= tolerance, (quantity, computed, value)


def test_every_api_name_resolves_with_a_docstring() -> None:
    from rubberfriction import api

    assert rf.__all__ == api.__all__
    assert set(rf.__all__) <= set(dir(rf))
    for name in rf.__all__:
        obj = getattr(rf, name)
        assert obj is getattr(api, name)
        doc = inspect.getdoc(obj)
        assert doc and len(doc.split()) >= 5, f"rf.{name}: no docstring"
        if inspect.isfunction(obj):
            hints = inspect.signature(obj)
            assert hints.return_annotation is not inspect.Signature.empty, f"rf.{name}: no type"
    documented = set(re.findall(r"^## `rf\.(\w+)", (ROOT / "docs" / "api.md").read_text(), re.M))
    assert documented == set(rf.__all__), set(rf.__all__) ^ documented


def test_unknown_names_stay_attribute_errors() -> None:
    """The lazy look-up answers API names only (a submodule import still works)."""
    try:
        rf.no_such_name  # noqa: B018
    except AttributeError as err:
        assert "no_such_name" in str(err)
    else:
        raise AssertionError("rf.no_such_name resolved")


def test_import_is_cheap() -> None:
    """``import rubberfriction`` (the command's first line) loads neither DOLFINx, PETSc, MPI nor
    the API module; neither do the surface functions of the API."""
    heavy = ["dolfinx", "petsc4py", "mpi4py", "ufl", "basix"]
    code = ("import json, sys, rubberfriction as rf; a = sorted(set(sys.modules) & set({h!r})); "
            "api = 'rubberfriction.api' in sys.modules; "
            "p = rf.default_profile(); q, c = rf.psd(p); rf.hdc(p); rf.load_compound('A'); "
            "b = sorted(set(sys.modules) & set({h!r})); print(json.dumps([a, api, b]))"
            ).format(h=heavy)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd="/", env={**os.environ, "OMP_NUM_THREADS": "1"})
    at_import, api_loaded, after_surfaces = json.loads(out.stdout)
    assert at_import == [] and not api_loaded
    assert after_surfaces == []


def test_verify_names_a_bad_case_or_parameter() -> None:
    """An unknown case or parameter, and an impossible value (the command line's checks,
    ``driver.verification.parameters``), each raise one InputError naming it."""
    for call, expected in (((lambda: rf.verify("herz")), "did you mean 'hertz'"),
                           ((lambda: rf.verify("hertz", radius=1.0)), "radius"),
                           ((lambda: rf.verify("hertz", R=-1.0)), "--R -1")):
        try:
            call()
        except rf.InputError as err:
            assert expected in str(err)
        else:
            raise AssertionError(expected)


def test_fit_compound_recovers_a_prony_series(tmp_path: Path) -> None:
    """A master curve computed from a known Prony series on the fit's own tau grid (one per
    decade, eq. 3.34) is matched to round-off (rel. 1e-6), and the compound keeps the base's
    Mooney-Rivlin data."""
    base = rf.load_compound("tread_default")
    f = np.logspace(-2, 4, 25)  # Hz
    omega = 2 * np.pi * f
    tau = np.logspace(-5, 2, 8)
    e_inf, e_k = 2.0, np.array([0.5, 1.0, 3.0, 2.0, 1.5, 0.8, 0.4, 0.2])
    wt = np.outer(omega, tau)
    e1 = e_inf + (e_k * wt**2 / (1 + wt**2)).sum(axis=1)
    e2 = (e_k * wt / (1 + wt**2)).sum(axis=1)
    dma = tmp_path / "dma.csv"
    dma.write_text("f,E_stor,E_loss\nHz,MPa,MPa\n"
                   + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in zip(f, e1, e2)))
    compound, fit = rf.fit_compound(dma)
    assert fit.rel_error_storage.max < 1e-6 and fit.rel_error_loss.max < 1e-6
    assert math.isclose(fit.E_inf, e_inf, rel_tol=1e-6)
    assert compound.name == "dma" and compound.hyperelastic == base.hyperelastic
    assert compound.wlf == base.wlf
