r"""Klüppel-Heinrich hysteresis friction, thesis eq. (2.9) (Klüppel & Heinrich 2000).

::

    mu_H = 1/(2 (2 pi)^2) <z_p>/(sigma0 v) Int_{w_min}^{w_max} w E''(w) S(w) dw    (w = omega)

Assumptions, as we implement them (the original paper's prefactors were not available to us;
every choice below is derived here and pinned by a test):

1. Surface: self-affine with the HDC descriptors of thesis eq. (2.5),
   ``C_HDC(lambda) = xi_perp^2 (lambda/xi_par)^(2H)`` for ``lambda < xi_par``, fractal dimension
   ``D = 3 - H``.  Its profile PSD (Persson convention, ``C_HDC = 4 Int_0^inf C1D (1 - cos q
   lambda) dq``) is the power law ``C1D(q) = K q^-(1+2H)`` with
   ``K = xi_perp^2 xi_par^(-2H) Gamma(1+2H) sin(pi H)/(2 pi)`` for
   ``2 pi/xi_par <= q <= 2 pi/lambda_min``.
2. Excitation: a rubber element sliding at v sees the height signal z(v t), frequencies
   ``omega = q v`` from ``omega_min = 2 pi v/xi_par`` to ``omega_max = 2 pi v/lambda_min``
   (``lambda_min``: the smallest wavelength in contact, the PSD's upper cut-off).
   ``S(omega) = S0 (omega/omega_min)^(-beta)`` with ``beta = 1 + 2H = 7 - 2D``, the exponent
   of Klüppel & Heinrich.
3. Dissipation: the excited rubber is a layer of thickness ``<z_p>`` (the mean penetration
   depth) under the nominal area, driven by the normalised height signal
   ``eps(t) = z(v t)/xi_perp``: the rubber that penetrates the roughness is strained by order
   one where the profile varies over its full height range xi_perp (the HDC plateau, eq. 2.5).
   Its dissipated power per nominal area, ``<z_p> Int_{-inf}^{inf} omega E'' S_eps domega`` with
   the two-sided temporal PSD ``S_eps(omega) = C1D(omega/v)/(v xi_perp^2)`` (Persson
   normalisation), equals ``F_H v`` (eq. 2.8).  Eq. (2.9) is exactly this balance if
   ``S = 16 pi^2 S_eps``, i.e. ``S0 = 4 xi_par Gamma(1+2H) sin(pi H)/((2 pi)^(2H) v)`` (unit: s),
   and then ``mu_H = 2 <z_p>/(sigma0 xi_perp^2) Int q E''(q v) C1D(q) dq``.  This normalisation
   of the strain is our assumption: the original S0 was not available to us; it makes eq. (2.9)
   dimensionless and gives the order of magnitude of published KH results (0.1-1 for tread
   compounds), but the absolute level of this baseline carries it.  (For comparison, the exact
   full-contact half-space result of :mod:`.persson` is ``Int q^2 C1D E'' dq/((1-nu^2) sigma0)``:
   a mode strains the depth ~1/q by its slope, not a fixed layer by its height.)
4. Mean penetration depth ``<z_p>``: Greenwood-Williamson contact extended to the self-affine
   surface through its spectral moments (the route of Klüppel & Heinrich; here with McCool's
   isotropic summit statistics): profile moments ``m_n = 2 Int q^n C1D dq`` of the power law,
   summit density ``eta = m4/(6 pi sqrt(3) m2)``, summit radius ``R = (3/8) sqrt(pi/m4)``,
   summit-height deviation ``sigma_s = sqrt(m0 (1 - 0.8968/alpha))``, ``alpha = m0 m4/m2^2``;
   Hertz summits ``sigma0 = eta (4/3) E_eff R^(1/2) sigma_s^(3/2) F_{3/2}(h)`` with
   ``F_n(h) = Int_h^inf (s - h)^n phi(s) ds`` (phi: standard normal) fix the separation h, and
   ``<z_p> = sigma_s F_1(h)/F_0(h)`` is the mean indentation of the summits in contact.
   ``E_eff = |E*(omega_max)|/(1 - nu^2)``: the summits are the smallest asperities and are
   deformed at the highest excitation frequency.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import erfc, gamma as gamma_fn

from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.rubber import Rubber
from rubberfriction.driver.theory.spectrum import cumulative_integral

#: Range of the dimensionless GW separation h where the model is evaluated.
_H_RANGE = (-4.0, 7.0)
_H_GRID = np.linspace(_H_RANGE[0], _H_RANGE[1], 1101)


@dataclass(frozen=True)
class HDCDescriptors:
    """Self-affine surface descriptors of eq. (2.5): xi_par, xi_perp (mm), Hurst exponent H."""

    xi_par: float
    xi_perp: float
    H: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.xi_par) and self.xi_par > 0):
            raise TheoryInputError(f"xi_par = {self.xi_par!r} mm; expected > 0")
        if not (math.isfinite(self.xi_perp) and self.xi_perp > 0):
            raise TheoryInputError(f"xi_perp = {self.xi_perp!r} mm; expected > 0")
        if not (0.0 < self.H < 1.0):
            raise TheoryInputError(f"Hurst exponent H = {self.H!r}; expected 0 < H < 1")

    @property
    def fractal_dimension(self) -> float:
        """D = 3 - H (thesis ch. 2.3.1)."""
        return 3.0 - self.H

    @property
    def beta(self) -> float:
        """Exponent of S(omega): beta = 7 - 2D = 1 + 2H."""
        return 1.0 + 2.0 * self.H

    @property
    def psd_prefactor(self) -> float:
        """K of ``C1D = K q^-(1+2H)`` (unit mm^(2-2H)), see module docstring."""
        H = self.H
        return (self.xi_perp**2 * self.xi_par ** (-2 * H) * gamma_fn(1 + 2 * H)
                * math.sin(math.pi * H) / (2 * math.pi))

    def psd(self, q: np.ndarray) -> np.ndarray:
        """The power-law profile PSD C1D(q) (mm^3) implied by the descriptors."""
        return self.psd_prefactor * np.asarray(q, dtype=float) ** (-self.beta)

    def hdc(self, lam: np.ndarray) -> np.ndarray:
        """``C_HDC(lambda) = xi_perp^2 (lambda/xi_par)^(2H)`` (mm^2), eq. (2.5)."""
        return self.xi_perp**2 * (np.asarray(lam, dtype=float) / self.xi_par) ** (2 * self.H)


def descriptors_from_psd(q: np.ndarray, C1D: np.ndarray, qmin: float | None = None,
                         qmax: float | None = None) -> HDCDescriptors:
    """(xi_par, xi_perp, H) of a tabulated profile PSD between qmin and qmax (1/mm).

    Klüppel-Heinrich's construction on the HDC (eq. 2.4/2.5), done on the PSD: the power law
    ``C1D = K q^-(1+2H)`` is fitted (least squares in log-log, equal weight per log-interval:
    the PSD is first integrated into 40 logarithmic bins, which averages FFT noise); the plateau
    of the HDC is ``xi_perp^2 = 2 h_rms^2`` (h_rms of the PSD over the range); ``xi_par`` is
    where the fitted power-law HDC ``2 pi K lambda^(2H)/(Gamma(1+2H) sin(pi H))`` reaches the
    plateau.  If that crossing lies beyond the largest wavelength ``2 pi/qmin`` of the range (no
    plateau in the data), ``xi_par = 2 pi/qmin`` and ``xi_perp^2`` is the power-law HDC there.
    """
    q = np.asarray(q, dtype=float)
    C1D = np.asarray(C1D, dtype=float)
    keep = q > 0
    q, C1D = q[keep], C1D[keep]
    if q.size < 3 or np.any(np.diff(q) <= 0) or np.any(~np.isfinite(C1D)) or np.any(C1D < 0):
        raise TheoryInputError("descriptors_from_psd needs >= 3 increasing q > 0 and C1D >= 0")
    lo = q[0] if qmin is None else float(qmin)
    hi = q[-1] if qmax is None else float(qmax)
    if not (q[0] * (1 - 1e-12) <= lo < hi <= q[-1] * (1 + 1e-12)):
        raise TheoryInputError(f"fit range {lo:g}..{hi:g} 1/mm outside the PSD range "
                               f"{q[0]:g}..{q[-1]:g}")
    edges = np.geomspace(max(lo, q[0]), min(hi, q[-1]), 41)
    mass = np.diff(cumulative_integral(q, C1D, edges, 0, "linear"))
    ok = mass > 0
    if np.count_nonzero(ok) < 3:
        raise TheoryInputError("the PSD is zero over most of the fit range")
    qc = np.sqrt(edges[:-1] * edges[1:])
    Cbar = mass / np.diff(edges)
    slope, icpt = np.polyfit(np.log(qc[ok]), np.log(Cbar[ok]), 1)
    beta = -slope
    H = 0.5 * (beta - 1.0)
    if not (0.0 < H < 1.0):
        raise TheoryInputError(
            f"the PSD slope {slope:.3f} gives H = {H:.3f}; Klüppel-Heinrich needs a self-affine "
            "surface with 0 < H < 1 (C1D ~ q^-(1+2H))"
        )
    K = math.exp(icpt)
    hdc_const = 2 * math.pi * K / (gamma_fn(1 + 2 * H) * math.sin(math.pi * H))
    plateau = 4.0 * float(np.sum(mass))           # 2 h_rms^2, h_rms^2 = 2 Int C1D dq
    lam_max = 2 * math.pi / edges[0]
    xi_par = (plateau / hdc_const) ** (1.0 / (2 * H))
    if xi_par > lam_max:
        xi_par = lam_max
        plateau = hdc_const * xi_par ** (2 * H)
    return HDCDescriptors(xi_par=xi_par, xi_perp=math.sqrt(plateau), H=H)


def _F(n: float, h: np.ndarray) -> np.ndarray:
    """``F_n(h) = Int_h^inf (s - h)^n phi(s) ds`` for the standard normal phi (vectorised)."""
    h = np.atleast_1d(np.asarray(h, dtype=float))
    if n == 0:
        return 0.5 * erfc(h / math.sqrt(2))
    if n == 1:
        return np.exp(-0.5 * h * h) / math.sqrt(2 * math.pi) - h * 0.5 * erfc(h / math.sqrt(2))
    # Gauss-Laguerre-free: substitute s = h + t, integrate t in [0, 12] with a fine Simpson rule
    t = np.linspace(0.0, 12.0 + max(0.0, -float(np.min(h))), 4001)
    f = t[None, :] ** n * np.exp(-0.5 * (h[:, None] + t[None, :]) ** 2) / math.sqrt(2 * math.pi)
    dt = t[1] - t[0]
    w = np.ones_like(t)
    w[1:-1:2] = 4.0
    w[2:-1:2] = 2.0
    return f @ w * dt / 3.0


_F32_GRID = _F(1.5, _H_GRID)


@dataclass
class GWContact:
    """Greenwood-Williamson summit statistics of a self-affine profile (assumption 4)."""

    eta: float       #: summit density (1/mm^2)
    R: float         #: summit radius (mm)
    sigma_s: float   #: summit-height standard deviation (mm)
    alpha: float     #: Nayak bandwidth parameter m0 m4/m2^2


def gw_summits(desc: HDCDescriptors, lambda_min: float) -> GWContact:
    """McCool/Nayak summit statistics of the power-law PSD, 2 pi/xi_par to 2 pi/lambda_min."""
    if not (0 < lambda_min < desc.xi_par):
        raise TheoryInputError(
            f"lambda_min = {lambda_min!r} mm must be > 0 and below xi_par = {desc.xi_par:g} mm"
        )
    K, beta = desc.psd_prefactor, desc.beta
    q0, q1 = 2 * math.pi / desc.xi_par, 2 * math.pi / lambda_min

    def moment(n: int) -> float:
        e = n + 1 - beta
        if abs(e) < 1e-12:
            return 2 * K * math.log(q1 / q0)
        return 2 * K * (q1**e - q0**e) / e

    m0, m2, m4 = moment(0), moment(2), moment(4)
    alpha = m0 * m4 / m2**2
    if alpha <= 0.8968 * 1.5:
        raise TheoryInputError(
            f"bandwidth alpha = {alpha:.3g} too small for summit statistics: widen the range "
            "xi_par / lambda_min"
        )
    eta = m4 / (6 * math.pi * math.sqrt(3) * m2)
    R = 0.375 * math.sqrt(math.pi / m4)
    sigma_s = math.sqrt(m0 * (1 - 0.8968 / alpha))
    return GWContact(eta=eta, R=R, sigma_s=sigma_s, alpha=alpha)


def penetration_depth(gw: GWContact, pressure: float, E_eff: np.ndarray) -> np.ndarray:
    """Mean penetration depth <z_p> (mm) of the contacting summits at nominal pressure (MPa).

    Solves ``pressure = eta (4/3) E_eff R^(1/2) sigma_s^(3/2) F_{3/2}(h)`` for h (vectorised over
    E_eff in MPa) and returns ``sigma_s F_1(h)/F_0(h)``.
    """
    E_eff = np.atleast_1d(np.asarray(E_eff, dtype=float))
    target = pressure / (gw.eta * (4.0 / 3.0) * E_eff * math.sqrt(gw.R) * gw.sigma_s**1.5)
    # F_{3/2} decreases monotonically in h: interpolate h(log F)
    logF = np.log(_F32_GRID)
    lt = np.log(target)
    if np.any(lt > logF[0]) or np.any(lt < logF[-1]):
        raise TheoryInputError(
            f"pressure {pressure:g} MPa is outside the Greenwood-Williamson range of this surface "
            f"and rubber (separation h outside {_H_RANGE}); near full contact use Persson's theory"
        )
    h = np.interp(-lt, -logF, _H_GRID)
    return gw.sigma_s * _F(1, h) / _F(0, h)


@dataclass
class KHResult:
    """mu(v) from eq. (2.9) and its ingredients, arrays over ``v``."""

    v: np.ndarray                #: sliding speeds (mm/s)
    pressure: float              #: sigma0 (MPa)
    mu: np.ndarray               #: mu_H(v), eq. (2.9)
    z_p: np.ndarray              #: mean penetration depth <z_p> (mm)
    S0: np.ndarray               #: S(omega_min) (s)
    omega_min: np.ndarray        #: 2 pi v / xi_par (rad/s)
    omega_max: np.ndarray        #: 2 pi v / lambda_min (rad/s)
    descriptors: HDCDescriptors
    lambda_min: float


def excitation_spectrum(desc: HDCDescriptors, v: float, omega: np.ndarray) -> np.ndarray:
    """``S(omega) = S0 (omega/omega_min)^-beta`` (s), assumption 3 of the module docstring."""
    H = desc.H
    S0 = (4 * desc.xi_par * gamma_fn(1 + 2 * H) * math.sin(math.pi * H)
          / ((2 * math.pi) ** (2 * H) * v))
    w_min = 2 * math.pi * v / desc.xi_par
    return S0 * (np.asarray(omega, dtype=float) / w_min) ** (-desc.beta)


def kluppel_heinrich_friction(
    desc: HDCDescriptors,
    lambda_min: float,
    rubber: Rubber,
    pressure: float,
    velocities: np.ndarray | list[float] | float,
    T0: float | None = None,
    z_p: float | np.ndarray | None = None,
    n_omega: int = 400,
) -> KHResult:
    """mu_H(v) of eq. (2.9) with the assumptions of the module docstring.

    ``z_p`` overrides the Greenwood-Williamson penetration depth (mm, scalar or per speed).
    ``n_omega`` log-spaced points integrate eq. (2.9) (trapezoid in log omega).
    """
    if not (isinstance(pressure, (int, float, np.floating)) and math.isfinite(pressure)
            and pressure > 0):
        raise TheoryInputError(f"nominal pressure = {pressure!r} MPa; expected > 0")
    v = np.atleast_1d(np.asarray(velocities, dtype=float))
    if v.ndim != 1 or v.size == 0 or np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise TheoryInputError(f"sliding velocities must be finite and > 0 mm/s; got {v}")
    if not (0 < lambda_min < desc.xi_par):
        raise TheoryInputError(f"lambda_min = {lambda_min!r} mm; expected 0 < lambda_min < "
                               f"xi_par = {desc.xi_par:g}")
    if T0 is not None and rubber.log10_aT is None:
        raise TheoryInputError(f"T0 = {T0} K given but the rubber has no WLF shift")
    w_min = 2 * math.pi * v / desc.xi_par
    w_max = 2 * math.pi * v / lambda_min
    x = np.linspace(0.0, 1.0, int(n_omega))
    omega = w_min[:, None] * (w_max / w_min)[:, None] ** x[None, :]
    Tarr = None if T0 is None else float(T0)
    loss = rubber.E(omega, Tarr).imag
    if z_p is None:
        E_eff = np.abs(rubber.E(w_max, Tarr)) / (1 - rubber.nu**2)
        zp = penetration_depth(gw_summits(desc, lambda_min), float(pressure), E_eff)
    else:
        zp = np.broadcast_to(np.asarray(z_p, dtype=float), v.shape).copy()
        if np.any(~np.isfinite(zp)) or np.any(zp <= 0):
            raise TheoryInputError(f"penetration depth z_p = {z_p!r} mm; expected > 0")
    mu = np.empty_like(v)
    S0 = np.empty_like(v)
    for i in range(v.size):
        S = excitation_spectrum(desc, v[i], omega[i])
        S0[i] = S[0]
        integrand = omega[i] * loss[i] * S * omega[i]           # d omega = omega d ln omega
        integral = np.trapz(integrand, np.log(omega[i]))
        mu[i] = zp[i] / (2 * (2 * math.pi) ** 2 * pressure * v[i]) * integral
    return KHResult(v=v, pressure=float(pressure), mu=mu, z_p=zp, S0=S0, omega_min=w_min,
                    omega_max=w_max, descriptors=desc, lambda_min=float(lambda_min))
