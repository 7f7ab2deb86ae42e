"""Power spectral density of a profile in Persson's convention, and its isotropic 2D form.

Convention (CONTRIBUTING.md; Persson et al. 2005, thesis eq. (2.6) in 1D):

    C1D(q) = (2 pi)^-1 Int <h(x) h(0)> exp(-i q x) dx,   q = 2 pi / lambda  (1/mm),

two-sided, so h_rms^2 = Int_-inf^inf C1D dq = 2 Int_0^inf C1D dq.  Units mm^3.

Discrete estimator.  For N samples at spacing dx (record length L = N dx) and the DFT
H_k = sum_n h_n w_n exp(-2 pi i k n / N), the estimate at q_k = 2 pi k / L is

    C1D(q_k) = dx / (2 pi N) * |H_k|^2 / <w^2>,

with window w (all ones for ``window=None``; <w^2> its mean square, which keeps the power of
broadband data).  Only q_k > 0 is returned (k = 1 .. N/2); for even N the Nyquist bin, which
is its own mirror image, is halved so that the two-sided identity holds bin by bin.  Hence, for
``window=None`` and any detrended record, exactly

    2 * sum_k C1D(q_k) * dq = mean(h^2),   dq = 2 pi / L         (Parseval),

and a sampled sine of amplitude A at q_k puts C1D(q_k) dq = A^2 / 4 in its bin, i.e. A^2/4 of
``C/L`` in the SurfaceTopography convention C_ST = 2 pi C1D (background notes 2.1, 3.4).  With a
window, the sine's A^2/4 is spread over the window's main lobe (for the periodic Hann window:
over k-1, k, k+1) and Parseval holds in expectation, not exactly.

Windowing: ``"hann"`` (default; periodic Hann) suppresses leakage of non-periodic records;
``None`` is right for exactly periodic data.  Detrending before the window is explicit:
``"mean"`` or ``"linear"``.

Isotropic 2D PSD (thesis eq. (2.6), Persson's 2D convention h_rms^2 = 2 pi Int q C dq) from the
1D one, for isotropic surfaces: C1D(q_x) = Int dq_y C(sqrt(q_x^2 + q_y^2)) (background 2.1).
:func:`psd_iso_from_1d` inverts it either

* exactly, by the Abel transform  C(q) = -(1/pi) Int_q^inf C1D'(q') / sqrt(q'^2 - q^2) dq'
  (``H=None``), or
* for a self-affine profile with Hurst exponent H, by C(q) = C1D(q)/q * Gamma(H+1) /
  (sqrt(pi) Gamma(H+1/2)) (``H`` given; 0.5 at H = 0.5, 2/pi at H = 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from scipy.special import gammaln

from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.profile import Profile, detrend

__all__ = [
    "psd_1d",
    "psd_iso_from_1d",
    "log_bin",
    "self_affine_iso_factor",
    "fit_psd_power_law",
    "PowerLawFit",
    "rms_from_psd",
    "rms_slope_from_psd",
    "to_surface_topography",
    "from_surface_topography",
]


def _window(name: str | None, n: int) -> np.ndarray | None:
    if name is None or name == "none":
        return None
    if name == "hann":
        # periodic Hann: exact sum rules over the main lobe for on-bin sines
        return 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(n) / n)
    raise SurfaceError(f"unknown window {name!r}; use 'hann' or None")


def psd_1d(
    profile: Profile,
    *,
    window: str | None = "hann",
    detrend: str | None = "mean",  # noqa: A002 - the public keyword name
) -> tuple[np.ndarray, np.ndarray]:
    """One-dimensional PSD ``(q, C1D)`` of a uniform, gap-free profile (Persson convention).

    q in 1/mm (q_k = 2 pi k / L, k = 1 .. N//2), C1D in mm^3, two-sided (see module docstring
    for the exact normalisation and its Parseval identity).  A raw profile with NaN or
    non-uniform spacing is refused: clean it first
    (:func:`~rubberfriction.driver.surfaces.defects.clean_profile`).
    """
    _check_uniform(profile)
    p = _detrend(profile, detrend)
    n = p.n
    h = p.h
    w = _window(window, n)
    norm = 1.0
    if w is not None:
        h = h * w
        norm = float(np.mean(w**2))
    spec = sfft.rfft(h)
    dx = profile.dx
    c = dx / (2.0 * np.pi * n) * (spec.real**2 + spec.imag**2) / norm
    c = c[1:]
    if n % 2 == 0:
        c[-1] *= 0.5  # Nyquist bin is shared by +q and -q
    q = 2.0 * np.pi * np.arange(1, n // 2 + 1) / (n * dx)
    return q, c


def _detrend(profile: Profile, kind: str | None) -> Profile:
    return detrend(profile, kind)


def _check_uniform(profile: Profile) -> None:
    if profile.n < 4:
        raise SurfaceError(f"need at least 4 points for a spectrum, got {profile.n}")
    if not np.all(np.isfinite(profile.h)):
        raise SurfaceError("profile contains NaN/inf heights; clean it first (clean_profile)")
    if not profile.is_uniform():
        raise SurfaceError("profile spacing is not uniform; resample it first (clean_profile)")


def rms_from_psd(q: np.ndarray, c1d: np.ndarray) -> float:
    """h_rms = sqrt(2 * sum C1D dq) for the uniform q grid of :func:`psd_1d`."""
    dq = q[0]
    return float(np.sqrt(2.0 * np.sum(c1d) * dq))


def rms_slope_from_psd(q: np.ndarray, c1d: np.ndarray) -> float:
    """Spectral rms slope sqrt(2 * sum q^2 C1D dq) (1D: h'_rms^2 = Int q^2 C1D dq over all q)."""
    dq = q[0]
    return float(np.sqrt(2.0 * np.sum(q**2 * c1d) * dq))


def to_surface_topography(c1d_persson: np.ndarray) -> np.ndarray:
    """Persson C1D -> SurfaceTopography convention C_ST = 2 pi C1D (background notes 2.1)."""
    return 2.0 * np.pi * np.asarray(c1d_persson)


def from_surface_topography(c1d_st: np.ndarray) -> np.ndarray:
    """SurfaceTopography C_ST -> Persson C1D = C_ST / (2 pi)."""
    return np.asarray(c1d_st) / (2.0 * np.pi)


def log_bin(
    q: np.ndarray, c: np.ndarray, *, bins_per_decade: int = 10
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Average a spectrum in logarithmically spaced q bins.

    Returns ``(q_centre, c_mean, count)``: q_centre is the geometric mean of the q in the bin,
    c_mean the arithmetic mean of C (an unbiased estimate of the mean density in the bin),
    count the number of raw values averaged.  Empty bins are dropped.
    """
    q = np.asarray(q, dtype=float)
    c = np.asarray(c, dtype=float)
    ok = (q > 0) & np.isfinite(c)
    q, c = q[ok], c[ok]
    if q.size == 0:
        raise SurfaceError("no positive wavenumbers to bin")
    lo, hi = np.log10(q.min()), np.log10(q.max())
    nb = max(1, int(np.ceil((hi - lo) * bins_per_decade + 1e-9)))
    edges = np.linspace(lo, hi + 1e-12, nb + 1)
    idx = np.clip(np.searchsorted(edges, np.log10(q), side="right") - 1, 0, nb - 1)
    count = np.bincount(idx, minlength=nb)
    sum_c = np.bincount(idx, weights=c, minlength=nb)
    sum_lq = np.bincount(idx, weights=np.log(q), minlength=nb)
    keep = count > 0
    return np.exp(sum_lq[keep] / count[keep]), sum_c[keep] / count[keep], count[keep]


def self_affine_iso_factor(H: float) -> float:
    """Gamma(H+1) / (sqrt(pi) Gamma(H+1/2)): C(q) = factor * C1D(q) / q for a self-affine
    isotropic surface (Persson conventions; 0.5 at H = 0.5, 2/pi at H = 1)."""
    if not H > -0.5:
        raise SurfaceError(f"Hurst exponent must exceed -0.5, got {H}")
    return float(np.exp(gammaln(H + 1.0) - gammaln(H + 0.5)) / np.sqrt(np.pi))


def psd_iso_from_1d(
    q: np.ndarray,
    c1d: np.ndarray,
    H: float | None = None,
    *,
    tail: str = "powerlaw",
    n_nodes: int = 96,
) -> np.ndarray:
    """Isotropic 2D PSD C(q) (mm^4, Persson convention) from the 1D PSD of a profile.

    ``H`` given: the self-affine relation C = C1D/q * Gamma(H+1)/(sqrt(pi) Gamma(H+1/2)).

    ``H=None``: the exact inverse Abel transform C(q) = -(1/pi) Int_q^inf C1D'(q') dq' /
    sqrt(q'^2 - q^2).  C1D is interpolated as a piecewise power law between the given points
    (log-log linear), the substitution q' = q cosh t removes the square-root singularity, and
    the integral is done by Gauss-Legendre quadrature on each interval.  Beyond the last q the
    spectrum is continued as the power law of the last interval (``tail="powerlaw"``) or taken
    as zero (``tail="zero"``: then C near q_max is underestimated).  Give smooth input (e.g.
    from :func:`log_bin`); C1D must be positive.
    """
    q = np.asarray(q, dtype=float)
    c1d = np.asarray(c1d, dtype=float)
    if H is not None:
        return self_affine_iso_factor(H) * c1d / q
    if q.ndim != 1 or q.size < 2 or q.shape != c1d.shape:
        raise SurfaceError("q and C1D must be 1D arrays of equal length >= 2")
    if np.any(np.diff(q) <= 0) or np.any(q <= 0) or np.any(c1d <= 0):
        raise SurfaceError("the Abel route needs increasing q > 0 and C1D > 0")
    lq, lc = np.log(q), np.log(c1d)
    slope = np.diff(lc) / np.diff(lq)  # local exponent: C1D ~ q^slope on each interval
    xg, wg = np.polynomial.legendre.leggauss(n_nodes)
    xg, wg = 0.5 * (xg + 1.0), 0.5 * wg

    def dc(qp: np.ndarray) -> np.ndarray:
        """dC1D/dq of the piecewise power law (tail beyond q[-1])."""
        j = np.clip(np.searchsorted(q, qp, side="right") - 1, 0, q.size - 2)
        s = slope[j]
        val = np.exp(lc[j] + s * (np.log(qp) - lq[j]))
        return s * val / qp

    out = np.empty_like(q)
    for i, qi in enumerate(q):  # loop over output wavenumbers (a few hundred), not points
        total = 0.0
        # intervals [q_j, q_j+1] with q_j >= qi, in t = arccosh(q'/qi)
        bounds = q[i:]
        tb = np.arccosh(np.clip(bounds / qi, 1.0, None))
        if tb.size > 1:
            a, b = tb[:-1, None], tb[1:, None]
            t = a + (b - a) * xg[None, :]
            total += np.sum((b - a) * wg[None, :] * dc(qi * np.cosh(t)))
        if tail == "powerlaw":
            s = slope[-1]
            if s >= 0:
                raise SurfaceError("power-law tail needs a decaying C1D at the largest q")
            # Int_T^inf dC1D(qi cosh t) dt, with the map t = T + u/(1-u) on u in [0, 1)
            T = tb[-1]
            u = xg
            t = np.minimum(T + u / (1.0 - u), 600.0)  # beyond, the integrand is below 1e-250
            jac = 1.0 / (1.0 - u) ** 2
            qp = qi * np.cosh(t)
            vals = s * np.exp(lc[-1] + s * (np.log(qp) - lq[-1])) / qp
            total += float(np.sum(wg * jac * vals))
        elif tail != "zero":
            raise SurfaceError(f"tail must be 'powerlaw' or 'zero', got {tail!r}")
        out[i] = -total / np.pi
    return out


@dataclass
class PowerLawFit:
    """Least-squares fit C1D = K q^-(1+2H) in log-log over ``q_range`` (1/mm)."""

    H: float
    K: float
    q_range: tuple[float, float]
    n_points: int
    rms_log_residual: float

    def __call__(self, q: np.ndarray) -> np.ndarray:
        return self.K * np.asarray(q, dtype=float) ** (-(1.0 + 2.0 * self.H))

    @property
    def lambda_range(self) -> tuple[float, float]:
        """The fit range as wavelengths (mm), long to short."""
        return 2 * np.pi / self.q_range[0], 2 * np.pi / self.q_range[1]


def fit_psd_power_law(
    q: np.ndarray,
    c1d: np.ndarray,
    q_range: tuple[float, float] | None = None,
    *,
    bins_per_decade: int = 10,
) -> PowerLawFit:
    """Fit the self-affine power law C1D = K q^-(1+2H) to a spectrum.

    The raw periodogram is first averaged in log bins (:func:`log_bin`), so that every decade
    has equal weight, then a straight line is fitted to log C vs log q inside ``q_range``
    (default: the whole spectrum).  H = -(slope + 1) / 2.
    """
    q = np.asarray(q, dtype=float)
    c1d = np.asarray(c1d, dtype=float)
    if q_range is None:
        q_range = (float(q[q > 0].min()), float(q.max()))
    lo, hi = sorted(q_range)
    m = (q >= lo) & (q <= hi)
    if np.count_nonzero(m) < 3:
        raise SurfaceError(f"fewer than 3 spectral points in q range {lo:.4g}..{hi:.4g} 1/mm")
    qb, cb, _ = log_bin(q[m], c1d[m], bins_per_decade=bins_per_decade)
    if qb.size < 2:
        qb, cb = q[m], c1d[m]
    lq, lc = np.log(qb), np.log(cb)
    slope, icpt = np.polyfit(lq, lc, 1)
    res = lc - (icpt + slope * lq)
    return PowerLawFit(
        H=float(-(slope + 1.0) / 2.0),
        K=float(np.exp(icpt)),
        q_range=(float(lo), float(hi)),
        n_points=int(qb.size),
        rms_log_residual=float(np.sqrt(np.mean(res**2))),
    )
