"""Band-pass decomposition of a profile into scales, thesis eq. (6.10) and ch. 6.5.1.

A multiscale setup with edges lambda_max > lambda_split,1 > ... > lambda_min uses one band-pass
filter per scale, F_i(lambda_i - lambda_i+1).  Adjacent bands share their split wavelength,
so the bands partition the spectrum between lambda_max and lambda_min (thesis ch. 6.3.1: "a
continuous spectrum is ensured"): the sum of all band profiles is the band-limited profile.

Filter (documented choice).  All bands are cut from one spectrum with weights w_i(q) that add
up to the weight of the whole band, so the partition holds to round-off whatever the filter:

* ``"ideal"`` (default): w_i = 1 for 2 pi/lambda_i <= q < 2 pi/lambda_i+1 (the finest band
  also includes its upper edge), else 0.  The band variance is then exactly the PSD integral
  over the band.  Sharp edges ring (Gibbs) near steep flanks.
* ``"cosine"``: raised-cosine steps of ``transition`` decades in log q centred on each edge,
  w_i = S(q; q_i) - S(q; q_i+1), which telescopes to the same partition of unity.

Non-periodic data.  A plain FFT would treat the record as periodic and the jump between its
ends would leak into every band.  For measured profiles the record is first detrended
(least-squares line; the trend has no wavelength inside any band) and then extended by its
mirror image (half-sample even extension), i.e. filtered in the cosine basis (DCT-II), whose
wavenumbers are q_k = pi k / L.  The extension is continuous, so leakage decays like q^-2
instead of q^-1, and nothing is lost at the ends.  Exactly periodic profiles
(``meta["periodic"]``, e.g. generated ones) are filtered with the plain real FFT.
"""

from __future__ import annotations

from typing import Literal, Sequence

import numpy as np
import scipy.fft as sfft

from rubberfriction.driver.surfaces.errors import BandError
from rubberfriction.driver.surfaces.profile import Profile

__all__ = [
    "check_edges",
    "band_weights",
    "band_split",
    "bandlimit",
    "lowpass",
    "resolves",
]

FilterKind = Literal["ideal", "cosine"]


def check_edges(edges_mm: Sequence[float]) -> np.ndarray:
    """Edges as a float array, verified to be positive and strictly descending (>= 2 values)."""
    e = np.asarray(edges_mm, dtype=float).ravel()
    if e.size < 2:
        raise BandError(f"need at least two band edges (lambda_max, lambda_min), got {list(e)}")
    if np.any(~np.isfinite(e)) or np.any(e <= 0):
        raise BandError(f"band edges must be positive wavelengths in mm, got {list(e)}")
    if np.any(np.diff(e) >= 0):
        raise BandError(f"band edges must be strictly descending (lambda_max first), got {list(e)}")
    return e


def _smooth_step(q: np.ndarray, q_edge: float, transition: float) -> np.ndarray:
    """0 below, 1 above q_edge; a raised cosine over ``transition`` decades centred on it."""
    with np.errstate(divide="ignore"):
        t = (np.log10(q) - np.log10(q_edge)) / transition + 0.5
    t = np.clip(np.nan_to_num(t, nan=0.0, neginf=0.0), 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * t)


def band_weights(
    q: np.ndarray,
    edges_mm: Sequence[float],
    filter: FilterKind = "ideal",  # noqa: A002
    transition: float = 0.1,
) -> list[np.ndarray]:
    """Filter weights w_i(q) of each band; their sum is the weight of the whole band."""
    e = check_edges(edges_mm)
    qe = 2.0 * np.pi / e  # ascending wavenumber edges
    q = np.asarray(q, dtype=float)
    if filter == "ideal":
        steps = [(q >= qi).astype(float) for qi in qe[:-1]] + [(q > qe[-1]).astype(float)]
    elif filter == "cosine":
        if not transition > 0:
            raise BandError("cosine filter needs a positive transition width (decades)")
        steps = [_smooth_step(q, qi, transition) for qi in qe]
    else:
        raise BandError(f"unknown filter {filter!r}; use 'ideal' or 'cosine'")
    return [steps[i] - steps[i + 1] for i in range(e.size - 1)]


def resolves(profile: Profile, lam_long: float, lam_short: float, *,
             min_periods: float = 1.0, nyquist_factor: float = 2.0) -> bool:
    """True if the profile holds ``min_periods`` of lam_long and samples lam_short at least at
    Nyquist (lam_short >= nyquist_factor * dx)."""
    return bool(profile.length >= min_periods * lam_long * (1 - 1e-9)
                and lam_short >= nyquist_factor * profile.dx * (1 - 1e-9))


def _prepare(profile: Profile) -> tuple[np.ndarray, bool]:
    if profile.n < 4:
        raise BandError(f"profile has {profile.n} points; too short to filter")
    if not np.all(np.isfinite(profile.h)):
        raise BandError("profile contains NaN/inf heights; clean it first (clean_profile)")
    if not profile.is_uniform():
        raise BandError("profile spacing is not uniform; resample it first (clean_profile)")
    if profile.periodic:
        return profile.h - profile.h.mean(), True
    x = profile.x - profile.x.mean()
    coef = np.polyfit(x, profile.h, 1)
    return profile.h - np.polyval(coef, x), False


def _filtered(profile: Profile, weight_fn, *, extension: str | None = None) -> list[np.ndarray]:
    """Apply a list of spectral weights (from ``weight_fn(q)``) to one spectrum of the profile."""
    h, periodic = _prepare(profile)
    if extension == "periodic":
        periodic = True
    elif extension == "mirror":
        periodic = False
    elif extension is not None:
        raise BandError(f"extension must be 'mirror', 'periodic' or None, got {extension!r}")
    n, dx = profile.n, profile.dx
    if periodic:
        spec = sfft.rfft(h)
        q = 2.0 * np.pi * np.arange(spec.size) / (n * dx)
        return [sfft.irfft(spec * w, n=n) for w in weight_fn(q)]
    spec = sfft.dct(h, type=2)
    q = np.pi * np.arange(n) / (n * dx)
    return [sfft.idct(spec * w, type=2) for w in weight_fn(q)]


def band_split(
    profile: Profile,
    edges_mm: Sequence[float],
    *,
    filter: FilterKind = "ideal",  # noqa: A002
    transition: float = 0.1,
    extension: str | None = None,
    min_periods: float = 1.0,
    allow_unresolved: bool = False,
) -> list[Profile]:
    """Split a profile into band profiles between descending wavelength edges (mm), eq. (6.10).

    ``edges_mm = [20, 3, 0.3, 0.04, 0.003]`` gives the four scales of thesis ch. 6.5.1.  Returns
    one profile per band on the same x; their sum is :func:`bandlimit` (lambda_max, lambda_min)
    to round-off.  Each band's ``meta`` records ``band = (lambda_long, lambda_short)``, the
    filter and the extension.

    Raises :class:`BandError` if the record is shorter than ``min_periods`` * lambda_max, or if
    the spacing cannot resolve lambda_min (lambda_min < 2 dx) unless ``allow_unresolved``: then
    bands beyond the Nyquist wavelength come out (partly) empty and are flagged.
    """
    e = check_edges(edges_mm)
    L, dx = profile.length, profile.dx
    if L < min_periods * e[0] * (1 - 1e-9):
        raise BandError(
            f"{profile.source or 'profile'} is {L:.4g} mm long: too short for the band "
            f"{e[0]:g}-{e[1]:g} mm (needs at least {min_periods:g} x {e[0]:g} mm)"
        )
    nyq = 2.0 * dx
    if e[-1] < nyq * (1 - 1e-9) and not allow_unresolved:
        raise BandError(
            f"{profile.source or 'profile'} has spacing {dx:.4g} mm and resolves wavelengths down "
            f"to {nyq:.4g} mm only; the band edge {e[-1]:g} mm needs a finer measurement (or "
            "allow_unresolved=True)"
        )
    parts = _filtered(profile, lambda q: band_weights(q, e, filter, transition),
                      extension=extension)
    out = []
    for i, hb in enumerate(parts):
        band = (float(e[i]), float(e[i + 1]))
        meta = {
            "band": band,
            "band_index": i,
            "filter": filter,
            "transition_decades": transition if filter == "cosine" else None,
            "extension": extension or ("periodic" if profile.periodic else "mirror"),
            "parent": profile.source,
            "periodic": profile.periodic,
            "resolved": bool(band[1] >= nyq * (1 - 1e-9)),
            "provenance": profile.meta.get("provenance", {}),
        }
        out.append(Profile(profile.x, hb, profile.units,
                           f"{profile.source} [band {band[0]:g}-{band[1]:g} mm]", meta,
                           profile.repaired))
    return out


def bandlimit(
    profile: Profile,
    lam_max: float,
    lam_min: float,
    *,
    filter: FilterKind = "ideal",  # noqa: A002
    transition: float = 0.1,
    extension: str | None = None,
) -> Profile:
    """The profile restricted to lambda_min..lambda_max with the same filter as band_split."""
    e = check_edges([lam_max, lam_min])
    (hb,) = _filtered(profile, lambda q: band_weights(q, e, filter, transition),
                      extension=extension)
    meta = {"band": (float(e[0]), float(e[1])), "filter": filter, "parent": profile.source,
            "periodic": profile.periodic}
    return Profile(profile.x, hb, profile.units,
                   f"{profile.source} [band {e[0]:g}-{e[1]:g} mm]", meta, profile.repaired)


def lowpass(
    profile: Profile,
    lam_cut: float,
    *,
    filter: FilterKind = "ideal",  # noqa: A002
    transition: float = 0.1,
    extension: str | None = None,
) -> Profile:
    """Wavelengths longer than ``lam_cut`` (mm) of the detrended profile, zero mean.

    The complement of all bands finer than lam_cut: for the sample selection (thesis 6.5.1) it
    is the surface a scale's rubber block rides on.
    """
    if not lam_cut > 0:
        raise BandError("low-pass cut must be a positive wavelength")
    qc = 2.0 * np.pi / lam_cut

    def weights(q: np.ndarray) -> list[np.ndarray]:
        if filter == "ideal":
            w = (q < qc).astype(float)
        else:
            w = 1.0 - _smooth_step(q, qc, transition)
        w[0] = 0.0  # zero mean
        return [w]

    (hl,) = _filtered(profile, weights, extension=extension)
    meta = {"lowpass": float(lam_cut), "filter": filter, "parent": profile.source,
            "periodic": profile.periodic}
    return Profile(profile.x, hl, profile.units, f"{profile.source} [> {lam_cut:g} mm]", meta,
                   profile.repaired)
