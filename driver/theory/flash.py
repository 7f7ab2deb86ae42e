"""Flash-temperature kernel for Persson's theory (Persson 2006, J. Phys.: Condens. Matter 18, 7789).

Thesis eq. (2.10) evaluates the modulus at ``E(q v cos phi, T_q)``: the rubber deformed by the
roughness component q is hotter than the background T0 because the friction power is dissipated
in the thin surface layers of the real contact regions and cannot diffuse away during the short
contact time (thesis ch. 8.2).  Persson's extension computes ``T_q`` scale by scale from the
heat produced at all scales; we implement that structure with a heat-conduction kernel that we
derive here in closed form.  Every modelling choice is listed; none is fitted.

Heat sources (per nominal area, mW/mm^2, units mm, s, MPa)
    The friction power ``sigma0 v mu`` is split over the spectrum nodes: node j dissipates
    ``w_j = kappa sigma0 v mu_j`` where ``mu_j`` is its share of ``mu_visc``.  ``kappa`` (default
    1) is the share of the heat that enters the rubber; the thesis (ch. 8.3.1) also sends all
    frictional heat to the rubber (kappa = 1).  The dissipation of a mode of wavenumber q sits in
    a layer of depth ~1/(2q): its strain field decays as exp(-q z) and the dissipation density as
    the square, so node j heats with the depth profile ``a e^{-a z}``, ``a = 2 q_j``.  An adhesive
    friction stress ``tau_A`` (eq. 7.6) heats the real contact area at the surface (``a -> inf``).

Where and how long the heat acts
    Scale j's heat is released in the contact regions seen at magnification q_j, which cover the
    area fraction ``P(q_j)`` (eq. 2.10; the bin average of P over node j), so the flux density
    there is ``w_j / P(q_j)``.  A contact
    region of scale q has the length ``d(q) = pi/q`` (half a wavelength: the largest patch one
    roughness wave forms), so it heats a passing rubber element for ``tau(q) = pi/(q v)``.
    The rubber deformed by scale i feels the heat of a coarser scale j (q_j <= q_i) at that
    scale's flux density ``w_j/P_j`` for the time ``tau_j`` (scale i's patches lie inside scale
    j's); the heat of a finer scale j (q_j > q_i) arrives spread over scale i's patch, i.e. with
    flux ``w_j/P_i`` for the time ``tau_i``.  Both cases: ``q_m = min(q_i, q_j)``.

Heat conduction (the kernel)
    Lateral heat flow is neglected (valid when the diffusion length ``sqrt(D tau)`` is below the
    patch size, i.e. at Peclet numbers ``v/(D q) >~ 1``; at lower speeds the estimate is an upper
    bound, and the heating is small there anyway); the rubber is a half-space z > 0 with an
    adiabatic surface (all heat enters the rubber, kappa above) and diffusivity ``D = k/(rho c)``:
    ``rho c dT/dt = k d2T/dz2 + J a e^{-a z}``.  With the cosine transform
    ``T(z, t) = (2/pi) Int_0^inf cos(wz) That(w, t) dw`` the solution is
    ``That = J a^2/(a^2 + w^2) (1 - exp(-D w^2 t))/(rho c D w^2)``.  The temperature that governs
    the modulus of scale i is the average over the depth where scale i dissipates, weight
    ``b e^{-b z}`` with ``b = 2 q_i``, and over the contact time ``[0, tau]``:

        Tbar = (J/k) (2/pi) Int_0^inf dw [1 - (1 - e^{-D w^2 tau})/(D w^2 tau)]/w^2
                    * a^2 b^2 / ((a^2 + w^2)(b^2 + w^2))
             = (J/k) sigma Phi(a sigma, b sigma),        sigma = sqrt(D tau),

    with ``Phi(x, y) = x^2 y^2 (n(x) - n(y))/(y^2 - x^2)``, ``n(x) = N(x)/x^3`` and
    ``N(x) = 4x/(3 sqrt(pi)) - 1 + (erfcx(x) - 1 + 2x/sqrt(pi))/x^2`` (partial fractions and
    ``Int_0^X 2x erfcx(x) dx = erfcx(X) - 1 + 2X/sqrt(pi)``).  Checks built into the tests:
    ``x, y -> inf`` gives ``Tbar = (4/3) J sqrt(D tau/pi)/k``, the time average of the classical
    surface temperature ``2 J sqrt(D t/pi)/k`` of a uniformly heated half-space; ``x, y -> 0``
    (no diffusion) gives ``J tau a b/(2 (a + b) rho c)``; and direct quadrature of the w-integral.

This is the structure of Persson's 2006 theory (scale-dependent T_q from the dissipation at all
scales, 1D heat diffusion into the rubber, self-consistent iteration with mu); the depth
weights, the patch length ``pi/q`` and the time average are our explicit choices, documented
above, because the paper's exact kernel was not available to us.  The patch length enters as
``sqrt(d)`` at high Peclet number: halving it lowers the flash temperature by ~30 %.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import erfcx

from rubberfriction.driver.theory.errors import TheoryInputError

_SQRT_PI = math.sqrt(math.pi)
#: Below this argument N, n and n' use their Taylor series (cancellation in the closed form).
_SERIES_X = 2.0e-2
#: Contact patch length d(q) = PATCH_LENGTH / q: half a wavelength.
PATCH_LENGTH = math.pi


@dataclass(frozen=True)
class FlashOptions:
    """Options of the flash-temperature iteration.

    heat_fraction:
        kappa, share of the friction heat that enters the rubber (thesis ch. 8.3.1: 1).
    relax:
        initial under-relaxation of the fixed-point iteration ``T <- T + relax (T_new - T)``,
        halved per speed when the update flips sign and shrinks by less than 20 %.  Friction
        falls as the rubber heats (on the rubbery side), a negative feedback whose loop gain
        exceeds 1 at high speeds, so the undamped iteration oscillates; 0.5 converges on the
        default road (docs/performance.md).
    tol:
        convergence tolerance on the scale temperatures (K).
    max_iter:
        iteration limit; non-converged velocities are flagged in the result.
    """

    heat_fraction: float = 1.0
    relax: float = 0.5
    tol: float = 1.0e-3
    max_iter: int = 300

    def __post_init__(self) -> None:
        if not (0.0 <= self.heat_fraction <= 1.0):
            raise TheoryInputError(f"heat_fraction = {self.heat_fraction}; expected 0..1")
        if not (0.0 < self.relax <= 1.0):
            raise TheoryInputError(f"relax = {self.relax}; expected 0 < relax <= 1")
        if not (self.tol > 0 and self.max_iter >= 1):
            raise TheoryInputError("tol must be > 0 and max_iter >= 1")


def _N(x: np.ndarray) -> np.ndarray:
    """``N(x) = 4x/(3 sqrt pi) - 1 + (erfcx(x) - 1 + 2x/sqrt pi)/x^2`` (see module docstring)."""
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = x < _SERIES_X
    xs = x[small]
    out[small] = (xs**2 / 2 - 8 * xs**3 / (15 * _SQRT_PI) + xs**4 / 6
                  - 16 * xs**5 / (105 * _SQRT_PI) + xs**6 / 24)
    xl = x[~small]
    out[~small] = (4.0 * xl / (3.0 * _SQRT_PI) - 1.0
                   + (erfcx(xl) - 1.0 + 2.0 * xl / _SQRT_PI) / xl**2)
    return out


def _n(x: np.ndarray) -> np.ndarray:
    """``n(x) = N(x)/x^3``."""
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = x < _SERIES_X
    xs = x[small]
    out[small] = (1 / (2 * xs) - 8 / (15 * _SQRT_PI) + xs / 6 - 16 * xs**2 / (105 * _SQRT_PI)
                  + xs**3 / 24)
    xl = x[~small]
    out[~small] = _N(xl) / xl**3
    return out


def _dn(x: np.ndarray) -> np.ndarray:
    """Derivative ``n'(x)``."""
    x = np.asarray(x, dtype=float)
    out = np.empty_like(x)
    small = x < _SERIES_X
    xs = x[small]
    out[small] = -1 / (2 * xs**2) + 1 / 6 - 32 * xs / (105 * _SQRT_PI) + xs**2 / 8
    xl = x[~small]
    ex = erfcx(xl)
    dN = 4 / (3 * _SQRT_PI) + (2 * xl**2 * ex - 2 * ex + 2 - 4 * xl / _SQRT_PI) / xl**3
    out[~small] = dN / xl**3 - 3 * _N(xl) / xl**4
    return out


def phi_kernel(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Dimensionless depth/time-averaged response ``Phi(x, y)``, x = a sigma (source), y = b sigma.

    ``Phi(x, y) = x^2 y^2 (n(x) - n(y))/(y^2 - x^2)``, with the limit ``-(x^3/2) n'(x)`` at
    ``x = y``.  Symmetric in x and y.
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    close = np.abs(y - x) <= 1e-6 * np.maximum(x, y)
    xs = np.where(close, 1.0, x)
    ys = np.where(close, 2.0, y)
    general = xs**2 * ys**2 * (_n(xs) - _n(ys)) / (ys**2 - xs**2)
    xm = np.where(close, 0.5 * (x + y), 1.0)
    diag = -0.5 * xm**3 * _dn(xm)
    return np.where(close, diag, general)


def layer_response(a: np.ndarray, b: np.ndarray, tau: np.ndarray, D: float, k: float) -> np.ndarray:
    """Mean temperature rise (K) per unit flux (mW/mm^2) of the kernel in the module docstring.

    Source depth profile ``a e^{-a z}``, observation weight ``b e^{-b z}`` (a, b in 1/mm), heating
    time ``tau`` (s), diffusivity D (mm^2/s), conductivity k (mW/(mm K)); result in K mm^2/mW.
    """
    sigma = np.sqrt(D * np.asarray(tau, dtype=float))
    return sigma * phi_kernel(np.asarray(a) * sigma, np.asarray(b) * sigma) / k


def surface_response(b: np.ndarray, tau: np.ndarray, D: float, k: float) -> np.ndarray:
    """``layer_response`` for a surface source (``a -> inf``): ``sigma N(b sigma)/(b sigma)/k``."""
    sigma = np.sqrt(D * np.asarray(tau, dtype=float))
    y = np.asarray(b) * sigma
    return sigma * _N(y) / y / k


def scale_kernels(q: np.ndarray, v: float, D: float, k: float) -> tuple[np.ndarray, np.ndarray]:
    """Kernel matrix ``K[i, j]`` (source j -> observation i) and surface vector for one speed.

    ``K[i, j] = layer_response(2 q_j, 2 q_i, tau(min(q_i, q_j)))`` with ``tau(q) = pi/(q v)``;
    the surface vector is ``surface_response(2 q_i, tau(q_i))`` (adhesive heat).  K is symmetric
    (Phi is, and tau depends on the coarser scale only), so only the lower triangle is evaluated:
    for ``q_j <= q_i``, ``sigma = sigma_j``, ``x = 2 q_j sigma_j`` and ``y = x q_i/q_j``.
    """
    q = np.asarray(q, dtype=float)
    n = q.size
    sigma = np.sqrt(D * PATCH_LENGTH / (q * v))
    x = 2.0 * q * sigma
    K = np.empty((n, n))
    ii, jj = np.tril_indices(n, -1)                   # i > j: q_j < q_i
    xj = x[jj]
    y = xj * q[ii] / q[jj]
    off = sigma[jj] * xj**2 * y**2 * (_n(x)[jj] - _n(y)) / (y**2 - xj**2) / k
    K[ii, jj] = off
    K[jj, ii] = off
    K[np.arange(n), np.arange(n)] = sigma * (-0.5 * x**3 * _dn(x)) / k
    s = sigma * _N(x) / x / k
    return K, s
