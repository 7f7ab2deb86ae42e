"""Height-difference correlation, thesis eq. (2.4), and the self-affine fit of eq. (2.5).

    C_HDC(lambda) = < (z(x + lambda) - z(x))^2 >                                  (2.4)
    C_HDC(lambda) = xi_perp^2 (lambda / xi_par)^(2H)   for lambda < xi_par,        (2.5)

with a plateau C_HDC = xi_perp^2 beyond the lateral cut-off xi_par (thesis ch. 2.3.1; for a
stationary profile the plateau is 2 h_rms^2).  Note that SurfaceTopography's
``autocorrelation_from_profile`` returns half of this quantity (background notes 2.1).

Links to the PSD (Persson convention, background notes 2.1 and 3.7):

    C_HDC(lambda) = 4 Int_0^inf C1D(q) (1 - cos q lambda) dq,
    C1D = K q^-(1+2H)  =>  C_HDC(lambda) = 2 pi K lambda^(2H) / (Gamma(1+2H) sin(pi H)).

For periodic data the circular HDC equals the discrete form of the first line exactly
(:func:`hdc_from_psd`), which pins the two normalisations against each other.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from scipy.optimize import least_squares
from scipy.special import gamma

from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.profile import Profile

__all__ = ["hdc", "hdc_from_psd", "hdc_power_law", "fit_hdc", "HDCFit", "log_lags"]


def log_lags(n: int, n_lags: int = 60, max_lag: int | None = None) -> np.ndarray:
    """About ``n_lags`` distinct integer lags, logarithmically spaced from 1 to ``max_lag``."""
    max_lag = n // 2 if max_lag is None else int(max_lag)
    if max_lag < 1:
        raise SurfaceError("profile too short for a height-difference correlation")
    return np.unique(np.rint(np.logspace(0.0, np.log10(max_lag), n_lags)).astype(np.int64))


def hdc(
    profile: Profile,
    lags: np.ndarray | None = None,
    *,
    n_lags: int = 60,
    max_lag_fraction: float = 0.5,
    periodic: bool | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Height-difference correlation eq. (2.4) of a uniform profile: ``(lambda_mm, C_HDC_mm2)``.

    ``lags`` are integer sample lags (default: ``n_lags`` log-spaced lags up to
    ``max_lag_fraction`` of the record).  Each value is the mean over all pairs the record
    holds, (N - k) pairs for lag k; ``periodic=True`` (default for profiles flagged periodic)
    wraps around instead, N pairs per lag.
    """
    if not np.all(np.isfinite(profile.h)):
        raise SurfaceError("profile contains NaN/inf heights; clean it first")
    if not profile.is_uniform():
        raise SurfaceError("profile spacing is not uniform; resample it first")
    n = profile.n
    if periodic is None:
        periodic = profile.periodic
    if lags is None:
        lags = log_lags(n, n_lags, int(max_lag_fraction * n))
    lags = np.asarray(lags, dtype=np.int64)
    if np.any(lags < 1) or np.any(lags >= n):
        raise SurfaceError(f"lags must lie in 1 .. {n - 1}")
    h = profile.h - profile.h.mean()
    out = np.empty(lags.size)
    for i, k in enumerate(lags):  # loop over lags; each lag is one vectorised pass
        if periodic:
            d = np.roll(h, -int(k)) - h
        else:
            d = h[k:] - h[:-k]
        out[i] = np.dot(d, d) / d.size
    return lags * profile.dx, out


def hdc_from_psd(q: np.ndarray, c1d: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """C_HDC(lambda) = 4 sum_k C1D(q_k) (1 - cos q_k lambda) dq on the uniform grid of psd_1d."""
    q = np.asarray(q, dtype=float)
    lam = np.atleast_1d(np.asarray(lam, dtype=float))
    dq = q[0]
    return 4.0 * dq * ((1.0 - np.cos(np.outer(lam, q))) @ np.asarray(c1d, dtype=float))


def hdc_power_law(lam: np.ndarray, K: float, H: float) -> np.ndarray:
    """Closed form C_HDC = 2 pi K lambda^(2H) / (Gamma(1+2H) sin(pi H)) for C1D = K q^-(1+2H),
    0 < H < 1 (background notes 3.7)."""
    if not 0.0 < H < 1.0:
        raise SurfaceError(f"the power-law HDC needs 0 < H < 1, got {H}")
    lam = np.asarray(lam, dtype=float)
    return 2.0 * np.pi * K * lam ** (2 * H) / (gamma(1 + 2 * H) * np.sin(np.pi * H))


@dataclass
class HDCFit:
    """Result of :func:`fit_hdc`: eq. (2.5) parameters and where they were fitted."""

    H: float  #: Hurst exponent (slope / 2 in log-log)
    xi_par: float  #: lateral cut-off xi_parallel (mm)
    xi_perp: float  #: vertical cut-off xi_perp (mm); plateau = xi_perp^2
    fit_range: tuple[float, float]  #: lag range (mm) that entered the fit
    power_law_range: tuple[float, float]  #: part fitted by the power law (mm)
    plateau_found: bool  #: False if no plateau lies inside fit_range (xi_par is then a bound)
    n_points: int
    rms_log_residual: float

    def __call__(self, lam: np.ndarray) -> np.ndarray:
        lam = np.asarray(lam, dtype=float)
        return self.xi_perp**2 * np.minimum(lam / self.xi_par, 1.0) ** (2 * self.H)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def fit_hdc(
    lam: np.ndarray,
    c: np.ndarray,
    fit_range: tuple[float, float] | None = None,
    *,
    min_points: int = 3,
) -> HDCFit:
    """Fit eq. (2.5) with its plateau to an HDC: H, xi_par, xi_perp and the fit range.

    The model, log C = min(log xi_perp^2 + 2H log(lambda / xi_par), log xi_perp^2), is fitted in
    log-log by least squares.  The breakpoint is first located by trying every lag as the start
    of the plateau (a straight line left of it, a constant right of it), then all three
    parameters are refined together.  If the best fit has no plateau inside ``fit_range`` (at
    least two points), only the power law is fitted, ``plateau_found`` is False and ``xi_par``
    is the upper end of the range (a lower bound).
    """
    lam = np.asarray(lam, dtype=float)
    c = np.asarray(c, dtype=float)
    if fit_range is None:
        fit_range = (float(lam.min()), float(lam.max()))
    lo, hi = fit_range
    m = (lam >= lo) & (lam <= hi) & (c > 0)
    if np.count_nonzero(m) < min_points:
        raise SurfaceError(f"fewer than {min_points} HDC points in {lo:.4g}..{hi:.4g} mm")
    x, y = np.log(lam[m]), np.log(c[m])
    n = x.size

    def line(xs: np.ndarray, ys: np.ndarray) -> tuple[float, float, float]:
        s, a = np.polyfit(xs, ys, 1)
        r = ys - (a + s * xs)
        return float(a), float(s), float(r @ r)

    a0, s0, sse0 = line(x, y)
    best = (sse0, n, a0, s0, np.nan)
    for j in range(min_points, n - 1):  # breakpoint candidates: loop over HDC points
        a, s, sse_l = line(x[:j], y[:j])
        p = float(y[j:].mean())
        sse = sse_l + float(((y[j:] - p) ** 2).sum())
        if s > 0 and sse < best[0]:
            best = (sse, j, a, s, p)
    _, j, a, s, p = best
    if j >= n - 1 or not np.isfinite(p):
        H = s / 2
        xi_par = float(np.exp(x[-1]))
        xi_perp = float(np.sqrt(np.exp(a + s * x[-1])))
        res = y - (a + s * x)
        return HDCFit(H, xi_par, xi_perp, (float(lo), float(hi)), (float(lam[m][0]), xi_par),
                      False, n, float(np.sqrt(np.mean(res**2))))

    def model(th: np.ndarray) -> np.ndarray:
        return np.minimum(th[0] + th[1] * x, th[2]) - y

    sol = least_squares(model, np.array([a, s, p]), method="lm")
    a, s, p = sol.x
    H = s / 2.0
    xi_par = float(np.exp((p - a) / s))
    xi_perp = float(np.exp(p / 2.0))
    res = model(sol.x)
    return HDCFit(float(H), xi_par, xi_perp, (float(lo), float(hi)),
                  (float(lam[m][0]), min(xi_par, float(hi))), True, n,
                  float(np.sqrt(np.mean(res**2))))
