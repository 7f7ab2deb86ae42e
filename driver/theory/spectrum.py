"""Roughness spectra as quadrature nodes for the analytical theories.

The theories of thesis ch. 2.3.2 are integrals over wavenumber of the surface power spectral
density times a material and contact factor, e.g. eq. (2.10)
``mu = 1/2 Int dq q^3 C(q) P(q) S(q) Int dphi cos(phi) Im E(q v cos phi) / ((1-nu^2) sigma0)``.
This module turns a tabulated PSD into a small set of nodes ``q_i`` with *masses*
``m_i = Int_{bin i} C(q) dq`` so that every theory integral becomes ``sum_i f(q_i) m_i``.

Conventions (CONTRIBUTING.md, Persson; units mm, so q in 1/mm):

* 1D profile PSD ``C1D(q) = (2 pi)^-1 Int <h(x) h(0)> exp(-iqx) dx``, two-sided, units mm^3:
  ``h_rms^2 = 2 Int_0^inf C1D dq`` and ``h'_rms^2 = 2 Int_0^inf q^2 C1D dq``.  A ``dim=1``
  spectrum stores the masses of C1D over q > 0 only (mm^3).
* 2D isotropic PSD ``C(q) = (2 pi)^-2 Int <h(x) h(0)> exp(-i q.x) d^2x`` (thesis eq. 2.6),
  units mm^4: ``h_rms^2 = 2 pi Int q C dq`` and ``|grad h|_rms^2 = 2 pi Int q^3 C dq``.
  A ``dim=2`` spectrum stores ``m_i = Int C dq`` (mm^3).

Tabulated PSDs are integrated exactly for an interpolant between the given points: linear by
default, which is unbiased for raw FFT periodograms (whose scatter is exponential: a log-log
interpolant between noisy neighbours takes their logarithmic mean and underestimates the power
by ~15 % for exponentially distributed periodogram values), or
piecewise power law (log-log linear, ``interpolation="powerlaw"``), which is exact for smooth
self-affine model spectra on coarse grids.  The nodes sit on a logarithmic grid
(``n_nodes`` bins between ``qmin`` and ``qmax``); each node is placed at the moment centroid
``q_i = (Int q^m C / Int C)^(1/m)`` with m = 2 (1D) or 3 (2D), so that the rms slope, which
weights the theories, is integrated exactly (of the interpolant); ``h_rms`` is exact in 1D (the
masses) and second-order accurate in 2D (the q^1 moment).  Line spectra (a sinusoid, a
ring) are represented exactly by :func:`line_spectrum`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rubberfriction.driver.theory.errors import TheoryInputError

#: Default number of logarithmic nodes for a tabulated PSD (about 50 per decade over 4 decades).
DEFAULT_NODES = 200


@dataclass(frozen=True)
class Spectrum:
    """A roughness spectrum as quadrature nodes.

    Attributes
    ----------
    q:
        Node wavenumbers (1/mm), strictly increasing, positive.
    mass:
        ``Int_{bin} C dq`` per node (mm^3): C1D over q > 0 for ``dim=1``, the isotropic 2D PSD
        for ``dim=2``.
    dim:
        1 for line roughness h(x) (plane-strain comparison with the 2D FE), 2 for an isotropic
        areal surface h(x, y).
    edges:
        Bin edges (1/mm), ``len(q) + 1`` values, or None for line spectra.
    source:
        Free text: where the spectrum comes from.
    """

    q: np.ndarray
    mass: np.ndarray
    dim: int
    edges: np.ndarray | None = None
    source: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        q = np.asarray(self.q, dtype=float)
        m = np.asarray(self.mass, dtype=float)
        if self.dim not in (1, 2):
            raise TheoryInputError(f"Spectrum.dim = {self.dim!r}; expected 1 (profile) or 2 "
                                   "(areal)")
        if q.ndim != 1 or q.shape != m.shape or q.size == 0:
            raise TheoryInputError(
                f"Spectrum q and mass must be 1D arrays of equal, non-zero length; got shapes "
                f"{q.shape} and {m.shape}"
            )
        if not (np.all(np.isfinite(q)) and np.all(q > 0)):
            raise TheoryInputError("Spectrum q must be finite and > 0 (1/mm)")
        if np.any(np.diff(q) <= 0):
            raise TheoryInputError("Spectrum q must be strictly increasing")
        if not (np.all(np.isfinite(m)) and np.all(m >= 0)) or not np.any(m > 0):
            raise TheoryInputError("Spectrum masses must be finite, >= 0 and not all zero (mm^3)")
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "mass", m)

    @property
    def h_rms(self) -> float:
        """Root-mean-square height (mm) of the represented surface."""
        if self.dim == 1:
            return math.sqrt(2.0 * float(np.sum(self.mass)))
        return math.sqrt(2.0 * math.pi * float(np.sum(self.q * self.mass)))

    @property
    def slope_rms(self) -> float:
        """Root-mean-square slope: ``h'_rms`` (1D) or ``|grad h|_rms`` (2D), dimensionless."""
        if self.dim == 1:
            return math.sqrt(2.0 * float(np.sum(self.q**2 * self.mass)))
        return math.sqrt(2.0 * math.pi * float(np.sum(self.q**3 * self.mass)))

    @property
    def q_min(self) -> float:
        """Smallest wavenumber covered (1/mm): the lower bin edge or the first line."""
        return float(self.edges[0]) if self.edges is not None else float(self.q[0])

    @property
    def q_max(self) -> float:
        """Largest wavenumber covered (1/mm): the upper bin edge or the last line."""
        return float(self.edges[-1]) if self.edges is not None else float(self.q[-1])


def line_spectrum(k: float | np.ndarray, h_rms: float | np.ndarray, dim: int = 1) -> Spectrum:
    """Exact spectrum of one or several single-wavelength components.

    ``dim=1``: each component is ``h0 cos(k x + phase)`` with ``h_rms = h0/sqrt(2)``; in the
    two-sided Persson convention ``C1D = (h0^2/4)[delta(q-k) + delta(q+k)]``, so the node mass on
    q > 0 is ``h0^2/4 = h_rms^2/2``.

    ``dim=2``: an isotropic ring ``C(q) = m delta(q - k)`` with ``h_rms^2 = 2 pi k m``, so
    ``m = h_rms^2/(2 pi k)``.
    """
    k_arr = np.atleast_1d(np.asarray(k, dtype=float))
    h_arr = np.broadcast_to(np.atleast_1d(np.asarray(h_rms, dtype=float)), k_arr.shape)
    if np.any(~np.isfinite(k_arr)) or np.any(k_arr <= 0):
        raise TheoryInputError(f"line_spectrum: wavenumbers k must be > 0 (1/mm); got {k_arr}")
    if np.any(~np.isfinite(h_arr)) or np.any(h_arr < 0):
        raise TheoryInputError(f"line_spectrum: h_rms must be >= 0 (mm); got {h_arr}")
    order = np.argsort(k_arr)
    k_arr, h_arr = k_arr[order], h_arr[order]
    if dim == 1:
        mass = 0.5 * h_arr**2
    elif dim == 2:
        mass = h_arr**2 / (2.0 * math.pi * k_arr)
    else:
        raise TheoryInputError(f"line_spectrum: dim = {dim!r}; expected 1 or 2")
    return Spectrum(q=k_arr, mass=mass, dim=dim, edges=None, source="line spectrum")


def sinusoid_spectrum(k: float, h0: float) -> Spectrum:
    """1D spectrum of the profile ``h(x) = h0 cos(k x)`` (k in 1/mm, h0 in mm)."""
    return line_spectrum(k, abs(h0) / math.sqrt(2.0), dim=1)


def _expm1_ratio(t: np.ndarray, L: np.ndarray) -> np.ndarray:
    """``(exp(t L) - 1)/t`` with the limit ``L`` for ``t -> 0``."""
    tl = t * L
    small = np.abs(tl) < 1e-10
    safe_t = np.where(small, 1.0, t)
    return np.where(small, L * (1.0 + 0.5 * tl), np.expm1(tl) / safe_t)


def cumulative_integral(q: np.ndarray, f: np.ndarray, x: np.ndarray, moment: int = 0,
                        interpolation: str = "powerlaw") -> np.ndarray:
    """``Int_{q[0]}^{x} q'^moment f(q') dq'`` of an interpolant of the tabulated f.

    ``"powerlaw"``: intervals with both end values > 0 use ``f = f_i (q/q_i)^s`` (exact for power
    laws), an interval with a zero end the linear interpolant; ``"linear"``: linear everywhere.
    ``x`` must lie in ``[q[0], q[-1]]``.
    """
    if interpolation not in ("powerlaw", "linear"):
        raise TheoryInputError(f"interpolation = {interpolation!r}; expected 'linear' or "
                               "'powerlaw'")
    q = np.asarray(q, dtype=float)
    f = np.asarray(f, dtype=float)
    x = np.asarray(x, dtype=float)
    m = float(moment)

    def piece(i: np.ndarray, upper: np.ndarray) -> np.ndarray:
        qa, qb, fa, fb = q[i], q[i + 1], f[i], f[i + 1]
        pos = (fa > 0) & (fb > 0) & (interpolation == "powerlaw")
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(pos, fb, 1.0) / np.where(pos, fa, 1.0)
            s = np.where(pos, np.log(ratio) / np.log(qb / qa), 0.0)
        L = np.log(upper / qa)
        power = fa * qa ** (m + 1.0) * _expm1_ratio(s + m + 1.0, L)
        # linear interpolant f = fa + beta (q - qa), integrated against q^m exactly
        beta = (fb - fa) / (qb - qa)
        c0 = fa - beta * qa

        def lin(z: np.ndarray) -> np.ndarray:
            return c0 * z ** (m + 1.0) / (m + 1.0) + beta * z ** (m + 2.0) / (m + 2.0)

        linear = lin(upper) - lin(qa)
        return np.where(pos, power, linear)

    n = q.size
    idx_all = np.arange(n - 1)
    full = piece(idx_all, q[1:])
    cum = np.concatenate(([0.0], np.cumsum(full)))
    j = np.clip(np.searchsorted(q, x, side="right") - 1, 0, n - 2)
    return cum[j] + piece(j, x)


def spectrum_from_psd(
    q: np.ndarray,
    C: np.ndarray,
    dim: int,
    qmin: float | None = None,
    qmax: float | None = None,
    n_nodes: int = DEFAULT_NODES,
    source: str = "",
    interpolation: str = "linear",
) -> Spectrum:
    """Nodes of a tabulated PSD between ``qmin`` and ``qmax`` (1/mm).

    Parameters
    ----------
    q, C:
        Wavenumbers (1/mm, increasing) and PSD values: C1D (mm^3) for ``dim=1`` or the isotropic
        2D PSD (mm^4) for ``dim=2``, both in Persson's normalisation.  Entries with q = 0 (the DC
        bin of an FFT) are dropped: a detrended profile carries no roughness there.
    qmin, qmax:
        Integration limits (thesis eq. 2.10 ``q_min``, ``q_max``).  Default: the tabulated range.
        The theories' result depends strongly on ``qmax`` (the shortest wavelength included),
        so give the same cut-off as the FE scales when comparing.
    n_nodes:
        Number of logarithmic bins.
    interpolation:
        ``"linear"`` (default; raw periodograms) or ``"powerlaw"`` (smooth model spectra), see
        the module docstring.
    """
    q = np.asarray(q, dtype=float).ravel()
    C = np.asarray(C, dtype=float).ravel()
    if q.shape != C.shape:
        raise TheoryInputError(f"PSD arrays q and C differ in length: {q.size} vs {C.size}")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(C))):
        raise TheoryInputError("PSD arrays q and C must be finite (no NaN/inf)")
    if np.any(q < 0):
        raise TheoryInputError(f"PSD wavenumbers must be >= 0 (1/mm); smallest is {q.min():g}")
    if np.any(C < 0):
        raise TheoryInputError(f"PSD values must be >= 0; smallest is {C.min():g}")
    keep = q > 0
    q, C = q[keep], C[keep]
    if q.size < 2:
        raise TheoryInputError("a tabulated PSD needs at least 2 points with q > 0; "
                               "use line_spectrum() for a single wavelength")
    if np.any(np.diff(q) <= 0):
        raise TheoryInputError("PSD wavenumbers q must be strictly increasing")
    lo = q[0] if qmin is None else float(qmin)
    hi = q[-1] if qmax is None else float(qmax)
    if not (q[0] * (1 - 1e-12) <= lo < hi <= q[-1] * (1 + 1e-12)):
        raise TheoryInputError(
            f"integration range qmin={lo:g}..qmax={hi:g} 1/mm must be increasing and inside the "
            f"tabulated PSD range {q[0]:g}..{q[-1]:g} 1/mm"
        )
    lo, hi = max(lo, q[0]), min(hi, q[-1])
    if int(n_nodes) < 1:
        raise TheoryInputError(f"n_nodes must be >= 1; got {n_nodes}")
    edges = np.geomspace(lo, hi, int(n_nodes) + 1)
    mom = 2 if dim == 1 else 3
    if dim not in (1, 2):
        raise TheoryInputError(f"dim = {dim!r}; expected 1 (profile PSD) or 2 (isotropic PSD)")
    mass = np.diff(cumulative_integral(q, C, edges, 0, interpolation))
    mmom = np.diff(cumulative_integral(q, C, edges, mom, interpolation))
    mass = np.maximum(mass, 0.0)
    ok = mass > 0
    if not np.any(ok):
        raise TheoryInputError(f"the PSD is zero everywhere between {lo:g} and {hi:g} 1/mm")
    centroid = np.where(ok, (np.maximum(mmom, 0.0) / np.where(ok, mass, 1.0)) ** (1.0 / mom), 0.0)
    # the centroid of a bin lies inside it; clip against round-off
    centroid = np.clip(centroid, edges[:-1], edges[1:])
    nodes = centroid[ok]
    # keep edges of the retained bins for reporting the covered range
    return Spectrum(q=nodes, mass=mass[ok], dim=dim, edges=edges, source=source,
                    meta={"n_bins": int(n_nodes), "qmin": lo, "qmax": hi})
