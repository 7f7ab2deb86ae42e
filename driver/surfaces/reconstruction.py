"""The decomposition alternatives the thesis compares in fig. 6.5 (ch. 6.1 and 6.3.1).

1. HDC-based approximation by one sinusoid per scale (Reinelt 2008, Wriggers & Reinelt 2009):
   :func:`hdc_sinusoids`.  The HDC of a sine A sin(2 pi x / lambda_i) is
   2 A^2 sin^2(pi d / lambda_i); Reinelt idealises it by its plateau 2 A^2 beyond
   d = lambda_i / 2 and approximates the surface HDC by the sum of the idealised single HDCs.
   Here the amplitudes are the non-negative least-squares solution of that sum matched to the
   measured HDC at the lags d_j = lambda_j / 2 (one equation per scale).  The thesis names the
   method, not a recipe; this is our concrete, documented realisation of it.
2. PSD-based reconstruction with random phases, eq. (6.9) (Wagner et al. 2015):
   :func:`psd_reconstruction` and :func:`psd_reconstruction_bands`,

       z(x) = sum_i 2 sqrt(2 pi C(q_i) / X) sin(q_i x + phi_i),   q_i = 2 pi i / X,

   read with the square root over 2 pi C / X: with the 1D Persson PSD each term then carries
   exactly the power 2 C(q_i) dq of its +-q bins (a sine of amplitude a has mean square a^2/2),
   so the reconstruction has the rms of the PSD.  Splitting the sum at the split wavenumbers
   gives the scales.
3. Direct filtering of the measurement, eq. (6.10):
   :func:`~rubberfriction.driver.surfaces.bands.band_split`.

:func:`compare_decompositions` runs all three on one profile so that fig. 6.5 can be redrawn
(:func:`~rubberfriction.driver.surfaces.plots.plot_decompositions`).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import scipy.fft as sfft
from scipy.optimize import nnls

from rubberfriction.driver.surfaces.bands import band_split, check_edges
from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.hdc import hdc
from rubberfriction.driver.surfaces.profile import Profile
from rubberfriction.driver.surfaces.psd import log_bin, psd_1d

__all__ = [
    "psd_reconstruction",
    "psd_reconstruction_bands",
    "hdc_sinusoids",
    "sine_hdc_idealised",
    "compare_decompositions",
]


def psd_reconstruction(
    q: np.ndarray,
    c1d: np.ndarray,
    length: float,
    dx: float,
    *,
    seed: int | None = 0,
    q_range: tuple[float, float] | None = None,
) -> Profile:
    """Eq. (6.9): a periodic profile of length X = ``length`` from a 1D PSD with random phases.

    C(q_i) at q_i = 2 pi i / X is interpolated log-log from the given (q, C1D) points (e.g. a
    log-binned PSD) and set to zero outside their range and outside ``q_range``.  Evaluated
    with one inverse FFT, which equals the explicit sum of sines (the tests check this).
    """
    q = np.asarray(q, dtype=float)
    c1d = np.asarray(c1d, dtype=float)
    if q.size < 2 or q.shape != c1d.shape or np.any(np.diff(q) <= 0) or np.any(c1d <= 0):
        raise SurfaceError("need increasing q and positive C1D (>= 2 points) to reconstruct")
    n = int(round(length / dx))
    if n < 4:
        raise SurfaceError("reconstruction grid too short")
    X = n * dx
    k = np.arange(n // 2 + 1)
    qi = 2.0 * np.pi * k / X
    lo, hi = q[0], q[-1]
    if q_range is not None:
        lo, hi = max(q[0], min(q_range)), min(q[-1], max(q_range))
    inside = (qi >= lo * (1 - 1e-12)) & (qi <= hi * (1 + 1e-12)) & (k > 0)
    if n % 2 == 0:
        inside[-1] = False
    ci = np.zeros_like(qi)
    ci[inside] = np.exp(np.interp(np.log(qi[inside]), np.log(q), np.log(c1d)))
    amp = 2.0 * np.sqrt(2.0 * np.pi * ci / X)  # eq. (6.9)
    rng = np.random.default_rng(seed)
    phi = 2.0 * np.pi * rng.random(k.size)
    # a sin(q x + phi) = a cos(q x + phi - pi/2)  <->  rfft coefficient n a / 2 e^{i(phi - pi/2)}
    coef = 0.5 * n * amp * np.exp(1j * (phi - 0.5 * np.pi))
    h = sfft.irfft(coef, n=n)
    prov = {"kind": "generated", "model": "PSD reconstruction, eq. (6.9)", "seed": seed,
            "length_mm": X, "dx_mm": dx, "q_range": [float(lo), float(hi)]}
    meta = {"periodic": True, "provenance": prov, "phases": phi[inside], "q_modes": qi[inside],
            "amplitudes": amp[inside]}
    return Profile(dx * np.arange(n), h, "mm",
                   f"generated: PSD reconstruction eq. (6.9), seed={seed}", meta)


def psd_reconstruction_bands(
    profile: Profile,
    edges_mm: Sequence[float],
    *,
    seed: int | None = 0,
    length: float | None = None,
    bins_per_decade: int = 20,
) -> list[Profile]:
    """Approach 2 of fig. 6.5: PSD of the measurement -> eq. (6.9) -> split at the edges.

    The PSD is the Hann-windowed, linearly detrended :func:`psd_1d` of the profile, log-binned;
    the reconstruction covers lambda_max .. lambda_min on a grid of the profile's spacing and
    ``length`` (default: the profile length), with one set of random phases for all scales.
    """
    e = check_edges(edges_mm)
    q, c = psd_1d(profile, window="hann", detrend="linear")
    qb, cb, _ = log_bin(q, c, bins_per_decade=bins_per_decade)
    keep = cb > 0
    rec = psd_reconstruction(qb[keep], cb[keep], length or profile.length, profile.dx, seed=seed,
                             q_range=(2 * np.pi / e[0], 2 * np.pi / e[-1]))
    return band_split(rec, e, allow_unresolved=True)


def sine_hdc_idealised(d: np.ndarray, amplitude: float, wavelength: float) -> np.ndarray:
    """Reinelt's idealised HDC of A sin(2 pi x / lambda): 2 A^2 sin^2(pi d / lambda) up to
    d = lambda / 2, then the plateau 2 A^2."""
    d = np.asarray(d, dtype=float)
    s = np.sin(np.pi * np.minimum(d, 0.5 * wavelength) / wavelength)
    return 2.0 * amplitude**2 * s * s


def hdc_sinusoids(
    profile: Profile,
    edges_mm: Sequence[float],
    *,
    wavelengths: Sequence[float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Approach 1 of fig. 6.5: one sine per scale fitted to the profile's HDC.

    Returns ``(amplitudes, wavelengths)`` (mm).  Wavelengths default to the long edge of each
    band; the amplitudes solve sum_i C_i(d_j) = C_HDC(d_j), d_j = lambda_j / 2, in the
    non-negative least-squares sense (see module docstring).
    """
    e = check_edges(edges_mm)
    lam = np.asarray(wavelengths if wavelengths is not None else e[:-1], dtype=float)
    if lam.size != e.size - 1:
        raise SurfaceError("one wavelength per band is needed")
    lags = np.maximum(1, np.rint(0.5 * lam / profile.dx)).astype(np.int64)
    if np.any(lags >= profile.n):
        raise SurfaceError("profile too short for the HDC at half the longest wavelength")
    d, c = hdc(profile, lags)
    # A[j, i] = idealised HDC of a unit sine i at lag d_j; unknowns A_i^2
    M = np.stack([sine_hdc_idealised(d, 1.0, li) for li in lam], axis=1)
    a2, _ = nnls(M, c)
    return np.sqrt(a2), lam


def compare_decompositions(
    profile: Profile,
    edges_mm: Sequence[float],
    *,
    seed: int | None = 0,
) -> dict[str, list[Profile]]:
    """The three decompositions of fig. 6.5 on the profile's grid, one list of scales each:
    ``"hdc_sinusoids"``, ``"psd_reconstruction"``, ``"filtering"``."""
    e = check_edges(edges_mm)
    filt = band_split(profile, e, allow_unresolved=True)
    amps, lam = hdc_sinusoids(profile, e)
    x = profile.x - profile.x[0]
    sines = []
    for i, (a, li) in enumerate(zip(amps, lam)):
        meta = {"band": (float(e[i]), float(e[i + 1])), "band_index": i, "periodic": False,
                "provenance": {"kind": "generated", "model": "HDC-based sinusoid (approach 1)",
                               "amplitude_mm": float(a), "wavelength_mm": float(li)}}
        sines.append(Profile(profile.x, a * np.sin(2 * np.pi * x / li), "mm",
                             f"HDC sinusoid {a:.3g} sin(2 pi x / {li:g})", meta))
    rec = psd_reconstruction_bands(profile, e, seed=seed)
    # same length and spacing as the profile, so the same number of points: put it on its x
    rec = [Profile(profile.x, r.h, "mm", r.source, r.meta) for r in rec]
    return {"hdc_sinusoids": sines, "psd_reconstruction": rec, "filtering": filt}
