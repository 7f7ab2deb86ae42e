"""Fit of the bell law to friction measurements, thesis 7.3-7.5 (eqs. 7.3-7.8).

The adhesive coefficient of friction, eqs. (7.6), (7.7)::

    mu_A(v) = tau_A(v) A_r(v) / p,    tau_A(v) = tau0 exp(-c [log10(v / v0)]^2)

is fitted to the measured difference mu_diff(v) by least squares
(``scipy.optimize.least_squares``, trust-region reflective with bounds, analytic Jacobian):

* **original approach** (7.3, 7.4; thesis fig. 7.6 bottom): ``mu_diff = mu_dry - mu_soap``, both
  measured; soap-water is taken as pure hysteresis (alpha = 0), its values interpolated onto the
  dry speeds linearly in log10 v;
* **modified approach** (7.5; fig. 7.8 a, b): ``mu_diff = mu_dry - mu_H`` with the simulated
  hysteresis mu_H(v) of the campaign;
* A_r(v) of the campaign (eq. 7.5) is interpolated onto the speeds linearly in (log10 v, log10 A_r).

Several compounds are fitted together with shared c and v0 and one tau0 each (as the thesis and
Lorenz et al. 2015: c = 0.18, v0 = 0.02 m/s, tau0 = 2.9 / 2.5 / 2.0 MPa original; c = 0.12,
v0 = 0.11 m/s, tau0 = 5 / 4 / 3 MPa modified).  v0 is fitted as log10 v0 (the bell is a
function of log v; v0 spans decades).

Uncertainty: the covariance of the parameters is ``s^2 (J^T J)^-1`` with the Jacobian J at the
optimum and the residual variance ``s^2 = sum r^2 / (n - m)`` (n points, m parameters); 95 %
intervals are ``+- t_0.975(n - m) se``; the v0 interval is that of log10 v0 mapped back, its
standard error the delta-method ``ln(10) v0 se(log10 v0)``.  A parameter at a bound has no
meaningful interval (reported as ``at_bound``).

The share alpha of eq. (7.8), ``mu = mu_H + alpha mu_A`` with alpha in [0, 1], is fitted to a
third curve (water, or soap-water in the modified approach) as a one-parameter linear least
squares over all compounds (one alpha per surface condition, as the thesis' 0.3), or given.

Speeds outside the range of the A_r, mu_H or soap-water data are an error unless
``extrapolate=True`` (then the end segments are extended linearly in the same coordinates).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from scipy import optimize, stats

from rubberfriction.driver.adhesion.errors import AdhesionInputError
from rubberfriction.driver.adhesion.measurements import SpeedCurve
from rubberfriction.driver.theory.adhesion import BellLaw

APPROACHES = ("original", "modified")


def on_speeds(curve: SpeedCurve, v: np.ndarray, *, log_values: bool = False,
              extrapolate: bool = False, what: str = "") -> np.ndarray:
    """``curve`` at speeds ``v`` (mm/s), linear in log10 v (and in log10 of the values when
    ``log_values``); speeds outside the curve's range raise unless ``extrapolate``."""
    v = np.asarray(v, dtype=float)
    lo, hi = curve.range
    out = (v < lo * (1 - 1e-12)) | (v > hi * (1 + 1e-12))
    if out.any() and not extrapolate:
        bad = ", ".join(f"{x:g}" for x in v[out])
        raise AdhesionInputError(f"{what or curve.source}: speeds {bad} mm/s lie outside its "
                                 f"range {lo:g} .. {hi:g} mm/s: expected speeds inside it, or "
                                 "allow extrapolation explicitly (extrapolate=True, "
                                 "--extrapolate)")
    x, lx = np.log10(curve.v), np.log10(v)
    y = np.log10(curve.values) if log_values else curve.values
    val = np.interp(lx, x, y)
    for m, i, j in ((lx < x[0], 0, 1), (lx > x[-1], -2, -1)):  # linear end segments
        if m.any():
            slope = (y[j] - y[i]) / (x[j] - x[i])
            val[m] = y[i] + slope * (lx[m] - x[i])
    return 10.0 ** val if log_values else val


@dataclass(frozen=True)
class CompoundData:
    """What one compound contributes to the fit: speeds (mm/s), mu_diff and A_r at them."""

    name: str
    v: np.ndarray
    mu_diff: np.ndarray
    area_ratio: np.ndarray

    def __post_init__(self) -> None:
        arrs = [np.asarray(a, dtype=float) for a in (self.v, self.mu_diff, self.area_ratio)]
        if len({a.shape for a in arrs}) != 1 or arrs[0].ndim != 1 or arrs[0].size < 1:
            raise AdhesionInputError(f"compound {self.name!r}: v, mu_diff and A_r must be "
                                     "equally long 1-D arrays")
        if not all(np.isfinite(a).all() for a in arrs):
            raise AdhesionInputError(f"compound {self.name!r}: non-finite v, mu_diff or A_r")
        if np.any(arrs[0] <= 0):
            raise AdhesionInputError(f"compound {self.name!r}: speeds must be > 0 mm/s")
        if np.any(arrs[2] <= 0) or np.any(arrs[2] > 1):
            raise AdhesionInputError(f"compound {self.name!r}: A_r must lie in (0, 1]")
        for name, a in zip(("v", "mu_diff", "area_ratio"), arrs):
            object.__setattr__(self, name, a)


def mu_diff_original(dry: SpeedCurve, soap: SpeedCurve, *, extrapolate: bool = False
                     ) -> SpeedCurve:
    """``mu_dry - mu_soap`` at the dry speeds (soap interpolated in log10 v), eq. (7.3), (7.4).
    The result may be negative at single speeds (measurement scatter); it is not clipped."""
    soap_v = on_speeds(soap, dry.v, extrapolate=extrapolate,
                       what=f"soap-water measurement {soap.source}")
    return _diff(dry, dry.values - soap_v, f"{dry.source} - {soap.source}")


def mu_diff_modified(dry: SpeedCurve, hysteresis: SpeedCurve, *, extrapolate: bool = False
                     ) -> SpeedCurve:
    """``mu_dry - mu_H`` at the dry speeds (mu_H interpolated in log10 v), thesis 7.5."""
    mu_h = on_speeds(hysteresis, dry.v, extrapolate=extrapolate,
                     what=f"hysteresis mu_H {hysteresis.source}")
    return _diff(dry, dry.values - mu_h, f"{dry.source} - {hysteresis.source}")


def _diff(dry: SpeedCurve, values: np.ndarray, source: str) -> SpeedCurve:
    # a difference may be negative: build it without the mu >= 0 check of measurements
    curve = object.__new__(SpeedCurve)
    for k, val in (("v", dry.v.copy()), ("values", np.asarray(values, float)),
                   ("quantity", "mu_diff"), ("source", source), ("unit", "mm/s"), ("notes", ())):
        object.__setattr__(curve, k, val)
    return curve


@dataclass(frozen=True)
class Bounds:
    """Bounds of the fit parameters: tau0 (MPa), c (-), v0 (mm/s)."""

    tau0: tuple[float, float] = (1e-6, 1e3)
    c: tuple[float, float] = (1e-4, 10.0)
    v0: tuple[float, float] = (1e-8, 1e10)

    def __post_init__(self) -> None:
        for name in ("tau0", "c", "v0"):
            lo, hi = getattr(self, name)
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
                raise AdhesionInputError(f"bounds {name} = {(lo, hi)!r}: expected 0 < low < high")


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter: value, standard error, 95 % interval, unit, whether at a bound."""

    name: str
    value: float
    se: float
    low: float
    high: float
    unit: str = ""
    at_bound: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "unit": self.unit, "standard_error": self.se,
                "ci95": [self.low, self.high], "at_bound": self.at_bound}


@dataclass(frozen=True)
class BellFit:
    """The fitted bell law of one or several compounds (shared c, v0; one tau0 each)."""

    approach: str  # "original" | "modified"
    pressure: float  # MPa
    compounds: tuple[str, ...]
    tau0: tuple[Parameter, ...]  # per compound, MPa
    c: Parameter
    v0: Parameter  # mm/s
    log10_v0: Parameter  # the fitted coordinate (v0 in mm/s)
    residual_rms: float  # sqrt(sum r^2 / n) of mu_A - mu_diff
    residual_max: float
    n_points: int
    dof: int
    data: tuple[CompoundData, ...]
    residuals: tuple[np.ndarray, ...]
    notes: tuple[str, ...] = ()

    def law(self, compound: str, alpha: float = 1.0) -> BellLaw:
        """The fitted :class:`BellLaw` of ``compound`` (eq. 7.6) with share ``alpha``."""
        if compound not in self.compounds:
            raise AdhesionInputError(f"compound = {compound!r}: expected one of "
                                     f"{list(self.compounds)}")
        k = self.compounds.index(compound)
        return BellLaw(tau0=self.tau0[k].value, c=self.c.value, v0=self.v0.value, alpha=alpha)

    def mu_adhesion(self, compound: str, v: np.ndarray, area_ratio: np.ndarray) -> np.ndarray:
        """Fitted mu_A(v) = tau_A(v) A_r(v) / p of ``compound``, eq. (7.7)."""
        return self.law(compound).tau(v) * np.asarray(area_ratio, float) / self.pressure

    def to_dict(self) -> dict[str, Any]:
        return {"approach": self.approach, "pressure_MPa": self.pressure,
                "law": "tau_A(v) = tau0 exp(-c log10(v/v0)^2), mu_A = tau_A A_r / p "
                       "(thesis eqs. 7.6, 7.7)",
                "tau0": {n: t.to_dict() for n, t in zip(self.compounds, self.tau0)},
                "c": self.c.to_dict(), "v0": self.v0.to_dict(),
                "log10_v0": self.log10_v0.to_dict(),
                "residual": {"rms": self.residual_rms, "max_abs": self.residual_max,
                             "n_points": self.n_points, "dof": self.dof,
                             "per_compound_rms": {n: float(np.sqrt(np.mean(r ** 2))) for n, r in
                                                  zip(self.compounds, self.residuals)}},
                "notes": list(self.notes)}


def _model(theta: np.ndarray, data: Sequence[CompoundData], pressure: float
           ) -> tuple[np.ndarray, np.ndarray]:
    """mu_A at all points and the Jacobian d mu_A / d (tau0_1..tau0_m, c, log10 v0)."""
    m = len(data)
    c, lg0 = theta[m], theta[m + 1]
    mus, rows = [], []
    for k, d in enumerate(data):
        x = np.log10(d.v) - lg0
        mu = theta[k] * np.exp(-c * x ** 2) * d.area_ratio / pressure  # eqs. (7.6), (7.7)
        jac = np.zeros((d.v.size, m + 2))
        jac[:, k] = mu / theta[k]
        jac[:, m] = -x ** 2 * mu
        jac[:, m + 1] = 2.0 * c * x * mu
        mus.append(mu)
        rows.append(jac)
    return np.concatenate(mus), np.vstack(rows)


def fit_bell(data: Sequence[CompoundData], pressure: float, *, approach: str,
             bounds: Bounds = Bounds()) -> BellFit:
    """Least-squares fit of tau0 (one per compound), c and v0 (shared) of eq. (7.6), (7.7) to
    the ``mu_diff`` of ``data`` (module docstring), with standard errors and 95 % intervals."""
    if approach not in APPROACHES:
        raise AdhesionInputError(f"approach = {approach!r}: expected one of {APPROACHES}")
    if not (isinstance(pressure, (int, float)) and math.isfinite(pressure) and pressure > 0):
        raise AdhesionInputError(f"pressure = {pressure!r}: expected a value > 0 in MPa")
    data = list(data)
    names = [d.name for d in data]
    if not data or len(set(names)) != len(names):
        raise AdhesionInputError(f"compounds = {names!r}: expected one or more distinct names")
    m = len(data)
    n = sum(d.v.size for d in data)
    if n <= m + 2:
        raise AdhesionInputError(f"{n} points for {m + 2} parameters (tau0 per compound, c, "
                                 "v0): expected more points than parameters")
    y = np.concatenate([d.mu_diff for d in data])
    lo = np.array([bounds.tau0[0]] * m + [bounds.c[0], math.log10(bounds.v0[0])])
    hi = np.array([bounds.tau0[1]] * m + [bounds.c[1], math.log10(bounds.v0[1])])

    def resid(theta: np.ndarray) -> np.ndarray:
        return _model(theta, data, pressure)[0] - y

    def jac(theta: np.ndarray) -> np.ndarray:
        return _model(theta, data, pressure)[1]

    best = None
    for theta0 in _starts(data, pressure, lo, hi):
        sol = optimize.least_squares(resid, theta0, jac=jac, bounds=(lo, hi), method="trf",
                                     x_scale="jac", xtol=1e-14, ftol=1e-14, gtol=1e-14,
                                     max_nfev=2000)
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None
    theta, r, J = best.x, best.fun, best.jac
    dof = n - (m + 2)
    s2 = float(r @ r) / dof
    notes: list[str] = []
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
        se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        se = np.full(theta.size, math.nan)
        notes.append("J^T J is singular: the data do not determine all parameters (no standard "
                     "errors)")
    t = float(stats.t.ppf(0.975, dof))
    active = best.active_mask != 0
    if active.any():
        notes.append("parameters at a bound (their intervals are not meaningful): "
                     + ", ".join(_param_names(names)[i] for i in np.flatnonzero(active)))
    params = [Parameter(_param_names(names)[i], float(theta[i]), float(se[i]),
                        float(theta[i] - t * se[i]), float(theta[i] + t * se[i]),
                        unit, bool(active[i]))
              for i, unit in zip(range(m + 2), ["MPa"] * m + ["", "log10(mm/s)"])]
    lg = params[m + 1]
    v0 = Parameter("v0", 10.0 ** lg.value, math.log(10.0) * 10.0 ** lg.value * lg.se,
                   10.0 ** lg.low, 10.0 ** lg.high, "mm/s", lg.at_bound)
    splits = np.cumsum([d.v.size for d in data])[:-1]
    return BellFit(approach, float(pressure), tuple(names), tuple(params[:m]), params[m], v0, lg,
                   float(np.sqrt(np.mean(r ** 2))), float(np.max(np.abs(r))), n, dof,
                   tuple(data), tuple(np.split(r, splits)), tuple(notes))


def _param_names(compounds: Sequence[str]) -> list[str]:
    return [f"tau0[{c}]" for c in compounds] + ["c", "log10_v0"]


def _starts(data: Sequence[CompoundData], pressure: float, lo: np.ndarray, hi: np.ndarray
            ) -> list[np.ndarray]:
    """Start points: the peak speed of mu_diff p / A_r (tau_A estimate) and the data ends for
    v0, three widths c, tau0 from the peak of the estimate (clipped into the bounds)."""
    m = len(data)
    lv = np.concatenate([np.log10(d.v) for d in data])
    est = [d.mu_diff * pressure / d.area_ratio for d in data]
    peak = float(np.mean([np.log10(d.v[int(np.argmax(e))]) for d, e in zip(data, est)]))
    tau = [max(float(np.max(e)), 1e-3) for e in est]
    out = []
    for lg0 in (peak, float(lv.min()), float(lv.max())):
        for c in (0.05, 0.2, 1.0):
            theta = np.array(tau + [c, lg0])
            span = hi - lo
            out.append(np.clip(theta, lo + 1e-9 * span, hi - 1e-9 * span))
    assert len(out[0]) == m + 2
    return out


@dataclass(frozen=True)
class Share:
    """The share alpha of eq. (7.8) for one surface condition: fitted in [0, 1] or given."""

    condition: str  # "water" | "soap" | "given"
    alpha: float
    se: float
    low: float
    high: float
    residual_rms: float  # of mu - (mu_H + alpha mu_A) over the condition's points (NaN: none)
    n_points: int
    given: bool = False
    at_bound: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {"condition": self.condition, "alpha": self.alpha, "given": self.given,
                "standard_error": self.se, "ci95": [self.low, self.high],
                "at_bound": self.at_bound, "residual_rms": self.residual_rms,
                "n_points": self.n_points}


def fit_share(condition: str, y: Sequence[np.ndarray], mu_a: Sequence[np.ndarray],
              given: float | None = None) -> Share:
    """alpha in [0, 1] of ``y = alpha mu_A`` by least squares over all compounds, eq. (7.8),
    with ``y = mu_condition - mu_H`` per compound at its speeds (``given``: alpha fixed, only
    the residual is computed).

    One parameter, a convex quadratic: the bounded optimum is the unbounded one
    ``sum(mu_A y) / sum(mu_A^2)`` clipped to [0, 1]; se = s / sqrt(sum mu_A^2).
    """
    yy = np.concatenate([np.asarray(a, float) for a in y]) if y else np.zeros(0)
    aa = np.concatenate([np.asarray(a, float) for a in mu_a]) if mu_a else np.zeros(0)
    if given is not None:
        if not (math.isfinite(given) and 0.0 <= given <= 1.0):
            raise AdhesionInputError(f"alpha = {given!r}: expected 0 <= alpha <= 1")
        res = yy - given * aa
        rms = float(np.sqrt(np.mean(res ** 2))) if res.size else math.nan
        return Share(condition, float(given), math.nan, float(given), float(given), rms,
                     int(yy.size), given=True)
    if yy.size < 2 or float(aa @ aa) <= 0:
        raise AdhesionInputError(f"alpha from {condition}: {yy.size} point(s) with mu_A = 0 "
                                 "everywhere or fewer than 2 points: expected at least 2 points "
                                 "where the fitted mu_A > 0")
    free = float(aa @ yy / (aa @ aa))
    alpha = min(max(free, 0.0), 1.0)
    res = yy - alpha * aa
    s = math.sqrt(float(res @ res) / (yy.size - 1))
    se = s / math.sqrt(float(aa @ aa))
    t = float(stats.t.ppf(0.975, yy.size - 1))
    return Share(condition, alpha, se, max(alpha - t * se, 0.0), min(alpha + t * se, 1.0),
                 float(np.sqrt(np.mean(res ** 2))), int(yy.size), at_bound=alpha != free)


@dataclass(frozen=True)
class CompoundInput:
    """The curves of one compound: measurements (dry and optionally soap-water, water), the
    campaign's A_r(v) and optionally its hysteresis mu_H(v); speeds in mm/s."""

    name: str
    dry: SpeedCurve
    area: SpeedCurve
    soap: SpeedCurve | None = None
    hysteresis: SpeedCurve | None = None
    water: SpeedCurve | None = None


@dataclass(frozen=True)
class AdhesionFit:
    """Bell-law fit and shares of one identification (thesis 7.4 or 7.5)."""

    bell: BellFit
    shares: tuple[Share, ...]
    inputs: tuple[CompoundInput, ...]
    mu_diff: tuple[SpeedCurve, ...]
    notes: tuple[str, ...] = field(default=())

    def to_dict(self) -> dict[str, Any]:
        out = self.bell.to_dict()
        out["alpha"] = {s.condition: s.to_dict() for s in self.shares}
        out["inputs"] = {c.name: {k: getattr(c, k).source for k in
                                  ("dry", "area", "soap", "hysteresis", "water")
                                  if getattr(c, k) is not None} for c in self.inputs}
        out["units"] = {"tau0": "MPa", "c": "-", "v0": "mm/s", "pressure": "MPa",
                        "speeds": "mm/s"}
        out["notes"] = list(self.bell.notes) + list(self.notes)
        return out

    def to_json(self, extra: dict[str, Any] | None = None) -> str:
        """:meth:`to_dict` (plus ``extra``) as JSON; NaN and inf become null."""
        return json.dumps(_plain({**self.to_dict(), **(extra or {})}), indent=2) + "\n"


def _plain(obj: Any) -> Any:
    """JSON-ready copy: numpy scalars and arrays to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return _plain(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def fit_adhesion(inputs: Sequence[CompoundInput], pressure: float, *, approach: str,
                 alpha: float | None = None, extrapolate: bool = False,
                 bounds: Bounds = Bounds()) -> AdhesionFit:
    """The whole identification: mu_diff by the ``approach``, the bell-law fit (shared c, v0),
    and alpha for the third curves (module docstring).

    original: needs ``soap`` per compound; alpha is fitted to ``water`` with mu_H = mu_soap (the
    approach's assumption alpha_soap = 0).  modified: needs ``hysteresis``; alpha is fitted to
    ``soap`` and to ``water`` where given, on top of mu_H.  ``alpha`` given: not fitted; its
    residual against the third curves is reported.
    """
    if approach not in APPROACHES:
        raise AdhesionInputError(f"approach = {approach!r}: expected one of {APPROACHES}")
    if alpha is not None and not (math.isfinite(alpha) and 0.0 <= alpha <= 1.0):
        raise AdhesionInputError(f"alpha = {alpha!r}: expected 0 <= alpha <= 1")
    inputs = list(inputs)
    notes: list[str] = []
    diffs, data = [], []
    for c in inputs:
        if approach == "original":
            if c.soap is None:
                raise AdhesionInputError(f"compound {c.name!r}: the original approach (dry minus "
                                         "soap-water, eqs. 7.3, 7.4) needs a soap-water "
                                         "measurement")
            d = mu_diff_original(c.dry, c.soap, extrapolate=extrapolate)
        else:
            if c.hysteresis is None:
                raise AdhesionInputError(f"compound {c.name!r}: the modified approach (dry minus "
                                         "simulated hysteresis, thesis 7.5) needs mu_H(v)")
            d = mu_diff_modified(c.dry, c.hysteresis, extrapolate=extrapolate)
        area = _area(c, d.v, extrapolate, notes)
        diffs.append(d)
        data.append(CompoundData(c.name, d.v, d.values, area))
    bell = fit_bell(data, pressure, approach=approach, bounds=bounds)
    conditions = ["water"] if approach == "original" else ["soap", "water"]
    shares = []
    for cond in conditions:
        curves = [(c, getattr(c, cond)) for c in inputs if getattr(c, cond) is not None]
        if not curves:
            continue
        ys, mas = [], []
        for c, meas in curves:
            base = c.soap if approach == "original" else c.hysteresis
            assert base is not None
            mu_h = on_speeds(base, meas.v, extrapolate=extrapolate,
                             what=f"{'soap-water' if approach == 'original' else 'mu_H'} "
                                  f"{base.source} (base of the {cond} curve)")
            area = _area(c, meas.v, extrapolate, notes)
            ys.append(meas.values - mu_h)
            mas.append(bell.mu_adhesion(c.name, meas.v, area))
        shares.append(fit_share(cond, ys, mas, given=alpha))
    if alpha is not None and not shares:
        shares.append(Share("given", float(alpha), math.nan, float(alpha), float(alpha),
                            math.nan, 0, given=True))
    return AdhesionFit(bell, tuple(shares), tuple(inputs), tuple(diffs),
                       tuple(dict.fromkeys(notes)))


def _area(c: CompoundInput, v: np.ndarray, extrapolate: bool, notes: list[str]) -> np.ndarray:
    """A_r of ``c`` at speeds v (log-log); an extrapolated value above 1 is capped at 1 (a
    relative area cannot exceed full contact), and the notes say so."""
    area = on_speeds(c.area, v, log_values=True, extrapolate=extrapolate,
                     what=f"contact area A_r {c.area.source}")
    if np.any(area > 1.0):
        notes.append(f"{c.name}: extrapolated A_r above 1 capped at 1 (full contact) at "
                     + ", ".join(f"{x:g}" for x in v[area > 1.0]) + " mm/s")
    return np.minimum(area, 1.0)
