"""Prony-series identification from DMA master curves (thesis ch. 3.3.1, eqs. 3.34-3.36).

The complex modulus of n Maxwell elements in parallel with an equilibrium spring (eq. 3.34),

    E'(w)  = E_inf + sum_k E_k (w tau_k)^2 / (1 + (w tau_k)^2),
    E''(w) =         sum_k E_k  w tau_k    / (1 + (w tau_k)^2),

is linear in the unknowns (E_inf, E_1 .. E_n) once the relaxation times are fixed.
:func:`fit_prony` solves the non-negative least-squares problem on E' and E'' together
(scipy.optimize.nnls), by default with relative weights (each residual divided by the measured
value), so that the glassy and the rubbery ends of a master curve count alike.  Relaxation times
are log-spaced over the data range unless given.

A DMA master curve that violates the Kramers-Kronig relations cannot be matched by ANY Prony series
(any linear viscoelastic solid); :func:`minimax_rel_error_bound` computes the smallest possible
maximum relative error on a given tau grid by linear programming, so a poor fit can be told apart
from poor data.  Units: omega in rad/s, moduli in MPa, tau in s.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from scipy.optimize import linprog, nnls

from rubberfriction import validation as V
from rubberfriction.forms.compound import WLF, ZERO_CELSIUS, Compound, PronySeries

FREQ_UNITS = {"Hz": 2.0 * math.pi, "rad/s": 1.0}
MODULUS_UNITS = {"Pa": 1e-6, "kPa": 1e-3, "MPa": 1.0, "GPa": 1e3}
WEIGHTS = ("relative", "absolute")


# --------------------------------------------------------------------------------------------
# data validation and reading
# --------------------------------------------------------------------------------------------


def _data_array(name: str, value: Any) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        raise ValueError(f"DMA data {name}: expected a 1-D array of numbers") from None
    if arr.ndim != 1:
        raise ValueError(f"DMA data {name}: expected a 1-D array, got shape {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"DMA data {name}[{i}] = {arr[i]!r}: expected finite values")
    return arr


def validate_dma(omega: Any, E_storage: Any, E_loss: Any, *, sort: bool = False,
                 positive_loss: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Check DMA data (omega rad/s, E', E'' MPa); return float copies.

    Errors (ValueError naming the field): non-finite values, unequal lengths, fewer than two
    points, omega <= 0, negative moduli (E' must be > 0; E'' > 0 when ``positive_loss``, as the
    relative weights divide by it), duplicated frequencies, and frequencies not strictly
    increasing.  Unsorted data are sorted only when asked (``sort=True``), never silently.
    """
    named = (("omega", omega), ("E_storage", E_storage), ("E_loss", E_loss))
    w, E1, E2 = (_data_array(n, v) for n, v in named)
    if not w.size == E1.size == E2.size:
        raise ValueError(f"DMA data: omega, E_storage, E_loss have {w.size}, {E1.size}, {E2.size} "
                         "points; expected equal lengths")
    if w.size < 2:
        raise ValueError(f"DMA data omega: {w.size} point(s); expected at least 2")
    loss_check = ((E2 <= 0, "> 0 MPa (relative weights)") if positive_loss
                  else (E2 < 0, ">= 0 MPa"))
    checks = (("omega", w, w <= 0, "> 0 rad/s"), ("E_storage", E1, E1 <= 0, "> 0 MPa"),
              ("E_loss", E2) + loss_check)
    for name, arr, cond, expect in checks:
        if cond.any():
            i = int(np.argmax(cond))
            raise ValueError(f"DMA data {name}[{i}] = {arr[i]!r}: expected {expect}")
    if sort:
        order = np.argsort(w, kind="stable")
        w, E1, E2 = w[order], E1[order], E2[order]
    step = np.diff(w)
    if (step == 0).any():
        i = int(np.argmax(step == 0))
        raise ValueError(f"DMA data omega[{i + 1}] = {w[i + 1]!r} repeats omega[{i}]; expected "
                         "distinct frequencies")
    if (step < 0).any():
        i = int(np.argmax(step < 0))
        raise ValueError(f"DMA data omega is not sorted: omega[{i}] = {w[i]!r} > omega[{i + 1}] = "
                         f"{w[i + 1]!r}; expected increasing frequencies (sort explicitly, e.g. "
                         "sort=True)")
    return w, E1, E2


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_rows(path: Path) -> list[list[str]]:
    with path.open(newline="", encoding="utf-8-sig") as fh:
        rows = [[c.strip() for c in row] for row in csv.reader(fh)]
    return [r for r in rows if r and any(r) and not r[0].startswith("#")]


def _column_index(header: list[str], col: str | int, path: Path) -> int:
    if isinstance(col, int):
        if not 0 <= col < len(header):
            raise ValueError(f"{path}: column index {col} out of range (file has {len(header)} "
                             "columns)")
        return col
    if col not in header:
        raise ValueError(f"{path}: column {col!r} not found; header is {header}")
    return header.index(col)


def _read_table(path: Path, columns: Sequence[str | int], header: str = "column names"
                ) -> tuple[list[str] | None, list[int], np.ndarray]:
    """The table of a pyvisco-style CSV: a header row, an optional units row (no number in the
    selected columns), then numbers.  Returns (units row or None,
    indices of ``columns``, data of those columns); one clear error for each malformed part."""
    rows = _read_rows(path)
    if len(rows) < 3 or all(_is_number(c) for c in rows[0]):
        raise V.InputError(f"{path}: expected a header row of {header} and data rows")
    names, rows = rows[0], rows[1:]
    idx = [_column_index(names, c, path) for c in columns]
    numeric = [_is_number(rows[0][i]) for i in idx if i < len(rows[0])]
    units = rows.pop(0) if not any(numeric) else None
    try:
        data = np.array([[float(r[i]) for i in idx] for r in rows])
    except (ValueError, IndexError) as err:
        raise V.InputError(f"{path}: non-numeric or missing value in the data rows "
                           f"({err})") from None
    return units, idx, data


def read_dma_csv(path: str | Path, freq_unit: str = "Hz",
                 columns: Sequence[str | int] = ("f", "E_stor", "E_loss"),
                 modulus_unit: str | None = None,
                 sort: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a DMA master curve in the pyvisco CSV format; return (omega rad/s, E' MPa, E'' MPa).

    Format (pyvisco ``freq_user_master.csv``): a header row of column names (``f, E_stor,
    E_loss``), optionally a second row of units (``Hz, MPa, MPa``), then numbers.  ``columns``
    selects frequency, storage and loss modulus by name or index.  The frequency unit is
    ``freq_unit`` ("Hz" or "rad/s"); a units row must agree with it.  Moduli are converted to MPa
    from the units row or from ``modulus_unit`` (Pa, kPa, MPa, GPa; default MPa).  Lines starting
    with ``#`` are ignored.  The data are validated by :func:`validate_dma`.
    """
    path = Path(path)
    if freq_unit not in FREQ_UNITS:
        raise ValueError(f"read_dma_csv.freq_unit = {freq_unit!r}: expected one of "
                         f"{list(FREQ_UNITS)}")
    if len(columns) != 3:
        raise ValueError(f"read_dma_csv.columns = {columns!r}: expected three (frequency, E', E'')")
    units, idx, data = _read_table(path, columns)
    scale_f, scale_E = _units_scales(path, units, idx, freq_unit, modulus_unit)
    return validate_dma(data[:, 0] * scale_f, data[:, 1] * scale_E, data[:, 2] * scale_E, sort=sort)


def _units_scales(path: Path, units: list[str] | None, idx: list[int], freq_unit: str,
                  modulus_unit: str | None) -> tuple[float, float]:
    if units is None:
        mod = modulus_unit or "MPa"
    else:
        fu, m1, m2 = (units[i] if i < len(units) else "" for i in idx)
        if fu != freq_unit:
            raise ValueError(f"{path}: the units row gives frequency in {fu!r} but freq_unit = "
                             f"{freq_unit!r}")
        if m1 != m2 or (modulus_unit is not None and m1 != modulus_unit):
            raise ValueError(f"{path}: modulus units {m1!r}, {m2!r} (units row) vs modulus_unit = "
                             f"{modulus_unit!r}")
        mod = m1
    if mod not in MODULUS_UNITS:
        raise ValueError(f"{path}: modulus unit {mod!r}: expected one of {list(MODULUS_UNITS)}")
    return FREQ_UNITS[freq_unit], MODULUS_UNITS[mod]


# --------------------------------------------------------------------------------------------
# the fit
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ErrorStats:
    """Maximum and root-mean-square relative error over the data points."""

    max: float
    rms: float

    @classmethod
    def of(cls, fitted: np.ndarray, data: np.ndarray) -> ErrorStats:
        rel = np.abs(fitted / data - 1.0)
        return cls(max=float(rel.max()), rms=float(np.sqrt(np.mean(rel**2))))


@dataclass(frozen=True)
class PronyFit:
    """Result of :func:`fit_prony`: the series, the (fitted or given) E_inf and the errors."""

    series: PronySeries
    E_inf: float
    rel_error_storage: ErrorStats
    rel_error_loss: ErrorStats
    n_data: int
    E_inf_fitted: bool

    @property
    def E0(self) -> float:
        return self.series.E0(self.E_inf)

    def report(self) -> str:
        s, nz = self.series, int((self.series.gamma > 0).sum())
        lines = [f"Prony fit (eq. 3.34) to {self.n_data} points of E' and E'': "
                 f"{len(s)} relaxation times "
                 f"{s.tau.min():.3g} .. {s.tau.max():.3g} s, {nz} non-zero terms",
                 f"  E_inf = {self.E_inf:.6g} MPa ({'fitted' if self.E_inf_fitted else 'given'}), "
                 f"E0 = {self.E0:.6g} MPa, gamma_inf = {s.gamma_inf:.6g}",
                 f"  relative error E':  max {self.rel_error_storage.max:.3%}, rms "
                 f"{self.rel_error_storage.rms:.3%}",
                 f"  relative error E'': max {self.rel_error_loss.max:.3%}, rms "
                 f"{self.rel_error_loss.rms:.3%}"]
        if max(self.rel_error_storage.max, self.rel_error_loss.max) > 0.05:
            lines.append("  note: errors above 5 %; if a denser tau grid does not help, the data "
                         "may be inconsistent with any linear viscoelastic model (check "
                         "minimax_rel_error_bound)")
        return "\n".join(lines)


def default_tau(omega: np.ndarray, n_terms: int | None = None) -> np.ndarray:
    """Relaxation times for a fit over ``omega`` (rad/s).

    Without ``n_terms``: one per decade at integer powers of ten, from 10^floor(log10(1/w_max)) to
    10^ceil(log10(1/w_min)) (the data range rounded outwards, as pyvisco's 'round' window).
    With ``n_terms``: log-spaced exactly over 1/w_max .. 1/w_min.
    """
    lo, hi = 1.0 / float(np.max(omega)), 1.0 / float(np.min(omega))
    if n_terms is None:
        e0, e1 = math.floor(math.log10(lo) + 1e-9), math.ceil(math.log10(hi) - 1e-9)
        return np.logspace(e0, e1, e1 - e0 + 1)
    if isinstance(n_terms, bool) or not isinstance(n_terms, (int, np.integer)) or n_terms < 1:
        raise ValueError(f"fit_prony.n_terms = {n_terms!r}: expected a positive integer")
    return np.geomspace(lo, hi, int(n_terms)) if n_terms > 1 else np.array([math.sqrt(lo * hi)])


def _design(omega: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Columns (E_inf, E_1 .. E_n) of E' and E'' in eq. (3.34)."""
    wt = np.outer(omega, tau)
    A1 = np.hstack([np.ones((omega.size, 1)), wt**2 / (1 + wt**2)])
    A2 = np.hstack([np.zeros((omega.size, 1)), wt / (1 + wt**2)])
    return A1, A2


def _check_tau(tau: Any) -> np.ndarray:
    t = np.array(tau, dtype=float, ndmin=1)
    if t.ndim != 1 or t.size == 0 or not np.isfinite(t).all() or (t <= 0).any():
        raise ValueError(f"fit_prony.tau = {tau!r}: expected a non-empty 1-D array of finite "
                         "times > 0 s")
    if np.unique(t).size != t.size:
        raise ValueError(f"fit_prony.tau = {tau!r}: expected distinct relaxation times")
    return t


def fit_prony(omega: Any, E_storage: Any, E_loss: Any, n_terms: int | None = None, tau: Any = None,
              E_inf: float | None = None, weights: str = "relative") -> PronyFit:
    """Fit a Prony series (eq. 3.34) to E'(omega) and E''(omega) at once.

    omega in rad/s (strictly increasing, > 0), moduli in MPa.  Unknowns E_inf >= 0 and E_k >= 0
    (non-negative least squares, scipy.optimize.nnls); ``E_inf`` given fixes the long-term modulus.
    ``weights="relative"`` minimises sum((E'_fit/E' - 1)^2 + (E''_fit/E'' - 1)^2), ``"absolute"``
    the plain squared residuals.  Relaxation times: ``tau`` if given, else :func:`default_tau`
    (``n_terms`` log-spaced over the data range, or one per decade).  The result's series is
    gamma_k = E_k / E0 (eq. 3.36) with all terms (zeros included, see ``PronySeries.pruned``).
    """
    if weights not in WEIGHTS:
        raise ValueError(f"fit_prony.weights = {weights!r}: expected one of {WEIGHTS}")
    w, E1, E2 = validate_dma(omega, E_storage, E_loss, positive_loss=(weights == "relative"))
    if tau is not None and n_terms is not None:
        raise ValueError("fit_prony: give either n_terms or tau, not both")
    tau = default_tau(w, n_terms) if tau is None else _check_tau(tau)
    A1, A2 = _design(w, tau)
    b1 = E1.copy()
    if E_inf is not None:
        E_inf = _given_E_inf(E_inf)
        A1, A2, b1 = A1[:, 1:], A2[:, 1:], E1 - E_inf
    x = _solve_nnls(A1, A2, b1, E2, (E1, E2) if weights == "relative" else None)
    E_inf_value = float(E_inf) if E_inf is not None else float(x[0])
    E_k = x if E_inf is not None else x[1:]
    if E_inf_value <= 0:
        raise ValueError("fit_prony: the fitted E_inf is 0 (a fluid-like fit, no equilibrium "
                         "spring); give E_inf or relaxation times tau not beyond the lowest data "
                         "frequency")
    series = PronySeries.from_moduli(E_inf_value, E_k, tau)
    return PronyFit(series=series, E_inf=E_inf_value,
                    rel_error_storage=ErrorStats.of(series.storage(w, E_inf_value), E1),
                    rel_error_loss=ErrorStats.of(series.loss(w, E_inf_value), E2),
                    n_data=int(w.size), E_inf_fitted=E_inf is None)


def series_at_reference(fit: Any, base: Compound, T: float | None = None,
                        wlf: WLF | None = None) -> tuple[PronySeries, str]:
    """The fitted series (zero terms pruned) as a compound uses it: relaxation times at its WLF
    reference temperature, tau_ref = tau(T) / a(T) (eq. 3.37) for a master curve referenced to
    ``T`` (K; None: already at T_ref, not shifted).  The WLF is ``wlf`` (e.g. fitted to the
    data's own shift factors) or else base's.  ``fit`` is any result with a ``series`` (a
    :class:`PronyFit`, :class:`PronyTimeFit`).  Returns the series and a one-line note of the
    shift ("" when no temperature was given)."""
    series = fit.series.pruned()
    if T is None:
        return series, ""
    T_C = T - ZERO_CELSIUS
    wlf = base.wlf if wlf is None else wlf
    if wlf is None:
        return series, f"master curve at {T_C:g} degC: {base.name} has no WLF, not shifted"
    if abs(T - wlf.T_ref) < 1e-9:
        return series, f"master curve at {T_C:g} degC = the WLF T_ref: tau not shifted"
    aT = float(wlf.aT(T))
    note = (f"tau shifted from the master curve's {T_C:g} degC to T_ref = "
            f"{wlf.T_ref - ZERO_CELSIUS:g} degC by 1/a(T) = {1 / aT:.6g} (eq. 3.37)")
    return series.shifted(1.0 / aT), note


def _given_E_inf(E_inf: Any) -> float:
    try:
        value = float(E_inf)
    except (TypeError, ValueError):
        value = math.nan
    if isinstance(E_inf, bool) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"fit_prony.E_inf = {E_inf!r}: expected a finite value > 0 MPa (or None "
                         "to fit it)")
    return value


def _solve_nnls(A1: np.ndarray, A2: np.ndarray, b1: np.ndarray, b2: np.ndarray,
                scale: tuple[np.ndarray, np.ndarray] | None) -> np.ndarray:
    if scale is not None:
        A1, b1 = A1 / scale[0][:, None], b1 / scale[0]
        A2, b2 = A2 / scale[1][:, None], b2 / scale[1]
    A, b = np.vstack([A1, A2]), np.concatenate([b1, b2])
    norm = np.linalg.norm(A, axis=0)
    norm[norm == 0] = 1.0
    x, _ = nnls(A / norm, b, maxiter=50 * A.shape[1] + 1000)
    return x / norm


def minimax_rel_error_bound(omega: Any, E_storage: Any, E_loss: Any, tau: Any,
                            curves: str = "both") -> float:
    """Smallest achievable max relative error of any Prony series on the grid ``tau``.

    Linear programme: minimise t subject to |E'_fit/E' - 1| <= t and/or |E''_fit/E'' - 1| <= t
    (``curves`` = "both", "storage" or "loss"), E_inf >= 0, E_k >= 0.  With a dense grid
    extending beyond the data this approximates the bound over all linear viscoelastic solids:
    data violating the Kramers-Kronig relations give a large value for "both" whatever the fit.
    """
    w, E1, E2 = validate_dma(omega, E_storage, E_loss)
    A1, A2 = _design(w, _check_tau(tau))
    blocks = {"both": [A1 / E1[:, None], A2 / E2[:, None]], "storage": [A1 / E1[:, None]],
              "loss": [A2 / E2[:, None]]}
    if curves not in blocks:
        raise ValueError(f"minimax_rel_error_bound.curves = {curves!r}: expected one of "
                         f"{list(blocks)}")
    A = np.vstack(blocks[curves])
    n, m = A.shape[1], A.shape[0]
    ones = np.ones((m, 1))
    res = linprog(np.r_[np.zeros(n), 1.0], A_ub=np.block([[A, -ones], [-A, -ones]]),
                  b_ub=np.r_[np.ones(m), -np.ones(m)], bounds=[(0, None)] * (n + 1), method="highs")
    if res.status != 0:
        raise RuntimeError(f"minimax_rel_error_bound: linear programme failed: {res.message}")
    return float(res.fun)


# --------------------------------------------------------------------------------------------
# the master curve's temperature: shift-factor tables and the WLF fit (eq. 3.33)
# --------------------------------------------------------------------------------------------

TEMPERATURE_UNITS = {"C": ZERO_CELSIUS, "degC": ZERO_CELSIUS, "°C": ZERO_CELSIUS, "K": 0.0}


def read_shift_factors(path: str | Path, columns: Sequence[str | int] = ("T", "log_aT"),
                       T_unit: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a shift-factor table (pyvisco ``shift_factors.csv``); return (T in K, log10 aT).

    Format: a header row (``T, log_aT``), a units row (``C, -``) or ``T_unit`` ("C", "degC" or
    "K"), then one row per temperature.  The temperature unit must be stated by one of the two:
    a table of bare numbers is refused, not read as degC.  log10 aT is the decimal logarithm of
    the shift factor that moved the curve measured at T onto the master curve (0 at the
    reference temperature).  Rows are sorted by temperature; repeated temperatures are refused.
    """
    path = Path(path)
    units, idx, data = _read_table(path, columns, header="(T, log_aT)")
    unit = units[idx[0]] if units is not None else T_unit
    if units is not None and T_unit is not None and unit != T_unit:
        raise V.InputError(f"{path}: the units row gives T in {unit!r} but T_unit = {T_unit!r}")
    if unit not in TEMPERATURE_UNITS:
        raise V.InputError(f"{path}: temperature unit {unit!r}: expected a units row or T_unit "
                           f"of {' or '.join(map(repr, TEMPERATURE_UNITS))}")
    if len(data) < 3 or not np.isfinite(data).all():
        raise V.InputError(f"{path}: expected at least 3 rows of finite numbers")
    T, log_aT = data[:, 0] + TEMPERATURE_UNITS[unit], data[:, 1]
    order = np.argsort(T, kind="stable")
    T, log_aT = T[order], log_aT[order]
    if (np.diff(T) == 0).any():
        raise V.InputError(f"{path}: temperature {T[np.argmax(np.diff(T) == 0)] - ZERO_CELSIUS:g}"
                           " degC repeats; expected one shift factor per temperature")
    if (T <= 0).any():
        raise V.InputError(f"{path}: temperature {T.min():g} K: expected > 0 K")
    return T, log_aT


def reference_temperature(T: np.ndarray, log_aT: np.ndarray) -> float:
    """The temperature (K) where log10 aT = 0: a row of the table, or the linear interpolation
    between the two rows where log10 aT changes sign.  A table without a zero is refused."""
    T, log_aT = np.asarray(T, float), np.asarray(log_aT, float)
    zero = np.flatnonzero(log_aT == 0.0)
    if zero.size == 1:
        return float(T[zero[0]])
    change = np.flatnonzero(np.sign(log_aT[:-1]) * np.sign(log_aT[1:]) < 0)
    if zero.size > 1 or change.size != 1:
        raise V.InputError(f"shift factors: log10 aT is 0 at {zero.size} temperature(s) and "
                           f"changes sign {change.size} time(s); expected one reference "
                           "temperature (give it with --T-ref-C)")
    i = int(change[0])
    return float(T[i] - log_aT[i] * (T[i + 1] - T[i]) / (log_aT[i + 1] - log_aT[i]))


@dataclass(frozen=True)
class WLFFit:
    """Result of :func:`fit_wlf`: the WLF law and the residual of log10 aT (data - law)."""

    wlf: WLF
    rms_residual: float
    max_residual: float
    n_data: int
    T_range: tuple[float, float]  # K

    def report(self) -> str:
        w = self.wlf
        lo, hi = (t - ZERO_CELSIUS for t in self.T_range)
        return (f"WLF fit (eq. 3.33) to {self.n_data} shift factors, {lo:g} .. {hi:g} degC: "
                f"c1 = {w.c1:.6g}, c2 = {w.c2:.6g} K, T_ref = {w.T_ref - ZERO_CELSIUS:g} degC; "
                f"residual of log10 aT: rms {self.rms_residual:.3g}, max {self.max_residual:.3g}")


def fit_wlf(T: Any, log_aT: Any, T_ref: float | None = None) -> WLFFit:
    """Fit WLF c1, c2 (eq. 3.33, log10 aT = -c1 (T - T_ref) / (c2 + T - T_ref)) to a shift-factor
    table by least squares on log10 aT.

    T in K; ``T_ref`` (K) defaults to :func:`reference_temperature` of the table.  Start: the
    linearised form -(T - T_ref) / log10 aT = c2/c1 + (T - T_ref)/c1, a straight line through the
    rows with T != T_ref; then scipy.optimize.least_squares on log10 aT itself (exact data give
    c1, c2 to rounding).  Impossible results (c1 or c2 <= 0, or the WLF singularity T_ref - c2 at
    or above a tabulated temperature) raise an InputError.
    """
    from scipy.optimize import least_squares

    TT, la = np.asarray(T, float), np.asarray(log_aT, float)
    if TT.shape != la.shape or TT.ndim != 1 or TT.size < 3:
        raise V.InputError(f"fit_wlf: {TT.size} temperatures and {la.size} shift factors; "
                           "expected at least 3 pairs")
    T_ref = reference_temperature(TT, la) if T_ref is None else float(T_ref)
    dT = TT - T_ref
    use = np.abs(dT) > 1e-9 * max(1.0, abs(T_ref))
    if use.sum() < 2 or (la[use] == 0).any():
        raise V.InputError("fit_wlf: log10 aT = 0 away from T_ref; expected a WLF-shaped table")
    slope, intercept = np.polyfit(dT[use], -dT[use] / la[use], 1)
    c1, c2 = (1.0 / slope, intercept / slope) if slope > 0 else (10.0, 50.0)

    def resid(x: np.ndarray) -> np.ndarray:
        return -x[0] * dT / (x[1] + dT) - la

    lower = max(1e-9, float(-dT.min()) * (1 + 1e-9))  # c2 + dT > 0 at every row
    x0 = np.array([max(c1, 1e-6), max(c2, lower * 1.01)])
    sol = least_squares(resid, x0, bounds=([1e-9, lower], [np.inf, np.inf]), xtol=1e-15,
                        ftol=1e-15, gtol=1e-15, x_scale="jac")
    c1, c2 = (float(v) for v in sol.x)
    if not (c1 > 1e-6 and c2 > 0):  # c1 at its bound: log10 aT does not fall with T
        raise V.InputError(f"fit_wlf: c1 = {c1:g}, c2 = {c2:g} K: expected both > 0 (log10 aT "
                           "must fall with temperature; the table is not WLF-shaped)")
    if T_ref - c2 >= TT.min() * (1 - 1e-6):
        raise V.InputError(f"fit_wlf: the WLF singularity T_ref - c2 = {T_ref - c2:g} K is at or "
                           f"above the table's lowest temperature {TT.min():g} K")
    r = resid(sol.x)
    return WLFFit(WLF(c1, c2, T_ref), float(np.sqrt(np.mean(r**2))), float(np.abs(r).max()),
                  int(TT.size), (float(TT.min()), float(TT.max())))


# --------------------------------------------------------------------------------------------
# time domain: relaxation curves E(t) and published Prony terms
# --------------------------------------------------------------------------------------------

TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}


def read_relaxation_csv(path: str | Path, columns: Sequence[str | int] = ("t", "E_relax"),
                        modulus_unit: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a relaxation master curve E(t) (pyvisco ``time_user_master.csv``); return (t in s,
    E in MPa).  A header row (``t, E_relax``), optionally a units row (``s, MPa``), then numbers;
    times > 0 strictly increasing, moduli > 0."""
    path = Path(path)
    if len(columns) != 2:
        raise V.InputError(f"read_relaxation_csv.columns = {columns!r}: expected two (time, E)")
    units, idx, data = _read_table(path, columns)
    tu, mu = (units[idx[0]], units[idx[1]]) if units is not None else ("s", modulus_unit or "MPa")
    if tu not in TIME_UNITS or mu not in MODULUS_UNITS:
        raise V.InputError(f"{path}: units {tu!r}, {mu!r}: expected time in {list(TIME_UNITS)} "
                           f"and modulus in {list(MODULUS_UNITS)}")
    t, E = data[:, 0] * TIME_UNITS[tu], data[:, 1] * MODULUS_UNITS[mu]
    _check_relaxation(t, E, str(path))
    return t, E


def _check_relaxation(t: np.ndarray, E: np.ndarray, where: str) -> None:
    for name, arr in (("t", t), ("E", E)):
        bad = ~np.isfinite(arr) | (arr <= 0)
        if bad.any():
            i = int(np.argmax(bad))
            raise V.InputError(f"{where}: {name}[{i}] = {arr[i]!r}: expected a finite value > 0")
    if t.size < 2 or (np.diff(t) <= 0).any():
        raise V.InputError(f"{where}: expected at least 2 strictly increasing times")


@dataclass(frozen=True)
class PronyTimeFit:
    """Result of :func:`fit_prony_time` (or the terms read by :func:`read_prony_csv`, with
    ``n_data = 0``): series, E_inf (MPa) and the relative error of E(t)."""

    series: PronySeries
    E_inf: float
    rel_error: ErrorStats | None
    n_data: int
    E_inf_fitted: bool
    source: str = "fit"

    @property
    def E0(self) -> float:
        return self.series.E0(self.E_inf)

    def report(self) -> str:
        s, nz = self.series, int((self.series.gamma > 0).sum())
        head = (f"Prony terms read from {self.source}" if self.n_data == 0 else
                f"Prony fit to {self.n_data} points of E(t) = E_inf + sum E_k exp(-t/tau_k)")
        lines = [f"{head}: {len(s)} relaxation times {s.tau.min():.3g} .. {s.tau.max():.3g} s, "
                 f"{nz} non-zero terms",
                 f"  E_inf = {self.E_inf:.6g} MPa ({'fitted' if self.E_inf_fitted else 'given'}), "
                 f"E0 = {self.E0:.6g} MPa, gamma_inf = {s.gamma_inf:.6g}"]
        if self.rel_error is not None:
            lines.append(f"  relative error E(t): max {self.rel_error.max:.3%}, rms "
                         f"{self.rel_error.rms:.3%}")
        return "\n".join(lines)


def default_tau_time(t: np.ndarray, per_decade: int = 1) -> np.ndarray:
    """Relaxation times for a fit of E(t) over t: ``per_decade`` per decade at powers of ten from
    10^floor(log10 t_min) to 10^ceil(log10 t_max) (the data range rounded outwards)."""
    e0 = math.floor(math.log10(float(np.min(t))) + 1e-9)
    e1 = math.ceil(math.log10(float(np.max(t))) - 1e-9)
    return np.logspace(e0, e1, (e1 - e0) * int(per_decade) + 1)


def fit_prony_time(t: Any, E: Any, tau: Any = None, per_decade: int = 1,
                   E_inf: float | None = None, weights: str = "relative") -> PronyTimeFit:
    """Fit E(t) = E_inf + sum_k E_k exp(-t / tau_k) (the relaxation form of eq. 3.34) to a
    relaxation curve: non-negative least squares (scipy.optimize.nnls) on a log-spaced tau grid
    (:func:`default_tau_time` unless ``tau`` is given), relative weights by default.  t in s,
    E in MPa; ``E_inf`` given fixes the long-term modulus."""
    if weights not in WEIGHTS:
        raise V.InputError(f"fit_prony_time.weights = {weights!r}: expected one of {WEIGHTS}")
    tt, EE = (np.array(a, dtype=float, ndmin=1) for a in (t, E))
    if tt.shape != EE.shape or tt.ndim != 1:
        raise V.InputError(f"fit_prony_time: t has {tt.size} values and E {EE.size}; expected "
                           "equal lengths")
    _check_relaxation(tt, EE, "fit_prony_time")
    if isinstance(per_decade, bool) or not isinstance(per_decade, (int, np.integer)) \
            or per_decade < 1:
        raise V.InputError(f"fit_prony_time.per_decade = {per_decade!r}: expected an integer "
                           ">= 1")
    tau = default_tau_time(tt, per_decade) if tau is None else _check_tau(tau)
    A = np.hstack([np.ones((tt.size, 1)), np.exp(-np.divide.outer(tt, tau))])
    b = EE.copy()
    if E_inf is not None:
        E_inf = _given_E_inf(E_inf)
        A, b = A[:, 1:], EE - E_inf
    if weights == "relative":
        A, b = A / EE[:, None], b / EE
    norm = np.linalg.norm(A, axis=0)
    norm[norm == 0] = 1.0
    x, _ = nnls(A / norm, b, maxiter=50 * A.shape[1] + 1000)
    x = x / norm
    E_inf_value = float(E_inf) if E_inf is not None else float(x[0])
    E_k = x if E_inf is not None else x[1:]
    if E_inf_value <= 0:
        raise V.InputError("fit_prony_time: the fitted E_inf is 0 (no equilibrium spring); give "
                           "E_inf or relaxation times not beyond the longest data time")
    series = PronySeries.from_moduli(E_inf_value, E_k, tau)
    return PronyTimeFit(series, E_inf_value, ErrorStats.of(series.relaxation(tt, E_inf_value), EE),
                        int(tt.size), E_inf is None)


def read_prony_csv(path: str | Path, E0: float | None = None) -> PronyTimeFit:
    """Read published Prony terms (pyvisco ``prony_terms``): a comment ``# E0 = <value> MPa``
    (or ``E0`` given), then rows ``rel_mod, rel_time`` (gamma_k = E_k / E0, tau_k in s).  The
    terms are taken as given (no fit): E_inf = E0 gamma_inf (eq. 3.35, 3.36).  Negative moduli,
    sum(gamma) >= 1 or non-positive times raise an InputError."""
    path = Path(path)
    E0_file = None
    rows = []
    with path.open(newline="", encoding="utf-8-sig") as fh:
        for line in fh:
            text = line.strip()
            if text.startswith("#"):
                key, _, value = text.lstrip("#").partition("=")
                if key.strip() == "E0":
                    unit = (value.split() + ["MPa", "MPa"])[1]
                    if unit not in MODULUS_UNITS:
                        raise V.InputError(f"{path}: E0 unit {unit!r}: expected one of "
                                           f"{list(MODULUS_UNITS)}")
                    E0_file = float(value.split()[0]) * MODULUS_UNITS[unit]
                continue
            cells = [c.strip() for c in text.split(",")]
            if text and all(_is_number(c) for c in cells[:2]) and len(cells) >= 2:
                rows.append((float(cells[0]), float(cells[1])))
            elif text and rows:
                raise V.InputError(f"{path}: non-numeric row {text!r} among the terms")
    if E0 is None and E0_file is None:
        raise V.InputError(f"{path}: no '# E0 = <value> MPa' line; give E0 (the instantaneous "
                           "modulus the relative moduli refer to)")
    E0_value = V.positive(f"{path}: E0", E0 if E0 is not None else E0_file, "MPa")
    if not rows:
        raise V.InputError(f"{path}: no rows of terms (rel_mod, rel_time)")
    gamma, tau = np.array(rows).T
    if (gamma < 0).any():
        i = int(np.argmax(gamma < 0))
        raise V.InputError(f"{path}: rel_mod[{i}] = {gamma[i]!r}: a negative modulus; expected "
                           ">= 0")
    if gamma.sum() >= 1.0:
        raise V.InputError(f"{path}: sum(rel_mod) = {gamma.sum():.6g}: expected < 1 (the "
                           "equilibrium modulus E_inf = E0 (1 - sum) must stay > 0)")
    try:
        series = PronySeries(gamma, tau)
    except ValueError as err:
        raise V.InputError(f"{path}: {err}") from None
    return PronyTimeFit(series, E0_value * series.gamma_inf, None, 0, False, source=path.name)


# --------------------------------------------------------------------------------------------
# plausibility at fit time
# --------------------------------------------------------------------------------------------


def plausibility_warnings(series: PronySeries, E_inf: float,
                          omega_range: tuple[float, float] | None, K: float | None = None
                          ) -> list[str]:
    """One line per implausible property of a fitted (or read) series, checked at fit time:

    * the instantaneous Poisson ratio nu0 = (3K - E0) / (6K) with the bulk modulus K of the
      compound it goes into (``K`` given) negative or above 0.5;
    * the loss tangent's peak (E''/E' of eq. 3.34, on a grid two decades beyond the terms)
      outside the data's frequency range;
    * relaxation times (non-zero terms) more than a decade outside the data's time range
      1/omega_max .. 1/omega_min.
    Impossible results (negative moduli, E_inf <= 0) never reach here: the series refuses them.
    ``omega_range`` in rad/s (for a relaxation curve E(t) over t1 .. t2: 1/t2 .. 1/t1; None for
    terms read without data: the two data checks are skipped).
    """
    out: list[str] = []
    s = series.pruned() if (series.gamma > 0).any() else series
    E0 = series.E0(E_inf)
    if K is not None:
        nu0 = (3.0 * K - E0) / (6.0 * K)
        if not 0.0 <= nu0 <= 0.5:
            out.append(f"instantaneous Poisson ratio nu0 = (3K - E0)/(6K) = {nu0:.4f} outside "
                       f"0 .. 0.5: the glassy E0 = {E0:.4g} MPa against the compound's bulk "
                       f"modulus K = {K:.4g} MPa (the FE model keeps K elastic, eq. 3.77)")
    if omega_range is not None and (s.gamma > 0).any():
        w_lo, w_hi = (float(v) for v in omega_range)
        lo, hi = math.log10(1 / s.tau.max()) - 2, math.log10(1 / s.tau.min()) + 2
        w = np.logspace(lo, hi, int((hi - lo) * 50) + 1)
        E = s.complex_modulus(w, E_inf)
        w_peak = float(w[np.argmax(E.imag / E.real)])
        if not w_lo <= w_peak <= w_hi:
            out.append(f"loss tangent peak at {w_peak / (2 * math.pi):.3g} Hz, outside the data "
                       f"({w_lo / (2 * math.pi):.3g} .. {w_hi / (2 * math.pi):.3g} Hz): the "
                       "series extrapolates its maximum damping")
        t_lo, t_hi = 1.0 / w_hi, 1.0 / w_lo
        far = (s.tau < t_lo / 10.0) | (s.tau > t_hi * 10.0)
        if far.any():
            more = " ..." if far.sum() > 4 else ""
            listed = ", ".join(f"{x:.3g}" for x in s.tau[far][:4]) + more
            out.append(f"{int(far.sum())} relaxation time(s) ({listed} s) more than a decade "
                       f"outside the data's time range {t_lo:.3g} .. {t_hi:.3g} s")
    return out


# --------------------------------------------------------------------------------------------
# smooth target spectra (used for the illustrative default compound)
# --------------------------------------------------------------------------------------------


def havriliak_negami(omega: Any, E_inf: float, E_glassy: float, tau0: float, alpha: float,
                     beta: float) -> np.ndarray:
    """Havriliak-Negami modulus E*(w) = E_glassy - (E_glassy - E_inf) / (1 + (i w tau0)^alpha)^beta.

    E*(0) = E_inf, E*(inf) = E_glassy; E'' rises as w^alpha below the peak and falls as
    w^(-alpha beta) above it (0 < alpha, beta <= 1).  omega in rad/s, moduli in MPa.
    """
    w = np.asarray(omega, dtype=float)
    return E_glassy - (E_glassy - E_inf) / (1.0 + (1j * w * tau0) ** alpha) ** beta


def hn_loss_peak_omega(tau0: float, alpha: float, beta: float) -> float:
    """Angular frequency of the E'' maximum of :func:`havriliak_negami` (closed form).

    w_max = (1/tau0) [sin(alpha pi / (2 beta + 2)) / sin(alpha beta pi / (2 beta + 2))]^(1/alpha).
    """
    x = math.pi / (2 * beta + 2)
    ratio = math.sin(alpha * x) / math.sin(alpha * beta * x)
    return ratio ** (1.0 / alpha) / tau0


def loss_peak_omega(series: PronySeries, E_inf: float, points_per_decade: int = 200) -> float:
    """Angular frequency of the E'' maximum of a Prony series (dense grid search), rad/s."""
    lo, hi = math.log10(1 / series.tau.max()) - 2, math.log10(1 / series.tau.min()) + 2
    w = np.logspace(lo, hi, int((hi - lo) * points_per_decade) + 1)
    return float(w[np.argmax(series.loss(w, E_inf))])


# --------------------------------------------------------------------------------------------
# output
# --------------------------------------------------------------------------------------------


def _toml_list(values: np.ndarray) -> str:
    return "[\n" + "".join(f"    {float(v)!r},\n" for v in values) + "]"


def prony_toml(series: PronySeries) -> str:
    """``gamma = [...]`` and ``tau = [...]`` lines (full precision) for a [prony] table."""
    return f"gamma = {_toml_list(series.gamma)}\ntau = {_toml_list(series.tau)}\n"


def plot_fit(fit: PronyFit, omega: Any, E1: Any, E2: Any, path: str | Path) -> Path:
    """Plot data vs fit (log-log E', E'' over frequency in Hz) and the relative errors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w, E1, E2 = validate_dma(omega, E1, E2, positive_loss=False)
    f = w / (2 * np.pi)
    wd = np.logspace(np.log10(w.min()), np.log10(w.max()), 400)
    fig, (ax, ax_err) = plt.subplots(2, 1, figsize=(7, 7), sharex=True,
                                     gridspec_kw={"height_ratios": [3, 1.3]})
    ax.loglog(f, E1, "o", ms=3, color="C0", label="E' data")
    ax.loglog(f, E2, "s", ms=3, color="C1", label="E'' data")
    fd = wd / (2 * np.pi)
    ax.loglog(fd, fit.series.storage(wd, fit.E_inf), "-", color="C0", label="E' Prony")
    ax.loglog(fd, fit.series.loss(wd, fit.E_inf), "-", color="C1", label="E'' Prony")
    ax.set_ylabel("modulus (MPa)")
    n_terms = int((fit.series.gamma > 0).sum())
    ax.set_title(f"Prony fit: {n_terms} terms, E_inf = {fit.E_inf:.4g} MPa")
    ax.legend()
    err1 = 100 * (fit.series.storage(w, fit.E_inf) / E1 - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        err2 = 100 * (fit.series.loss(w, fit.E_inf) / E2 - 1)
    ax_err.semilogx(f, err1, ".-", color="C0", label="E'")
    ax_err.semilogx(f, err2, ".-", color="C1", label="E''")
    ax_err.axhline(0, color="k", lw=0.5)
    ax_err.set_xlabel("frequency (Hz)")
    ax_err.set_ylabel("rel. error (%)")
    ax_err.legend()
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
