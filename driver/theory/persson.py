r"""Persson's theory of hysteretic rubber friction, thesis eq. (2.10), in two variants.

Both variants are fed with the same surface PSD and the same Prony/WLF material as the FE and
are vectorised over wavenumber, the angle integral and the sliding speed.

Isotropic (2D) roughness: eq. (2.10) (Persson 2001, 2006, 2014)
-----------------------------------------------------------------
::

    mu = 1/2 Int_{q0}^{q1} dq q^3 C(q) P(q) S(q) Int_0^{2 pi} dphi cos(phi)
             Im E(q v cos phi, T_q) / ((1 - nu^2) sigma0)
    P(q) = erf( 1 / (2 sqrt(G(q))) )
    G(q) = 1/8 Int_{q0}^{q} dq' q'^3 C(q') Int_0^{2 pi} dphi
             |E(q' v cos phi, T_q') / ((1 - nu^2) sigma0)|^2
    S(q) = gamma + (1 - gamma) P(q)^2

* ``E/(1 - nu^2)`` is the contact modulus of the half-space: a height mode ``h_q`` pressed fully
  into the rubber needs the pressure ``p_q = |q| E(q v cos phi)/(2 (1 - nu^2)) h_q``.
* ``P(q)`` is the relative contact area ``A(q)/A0`` seen at magnification ``q/q0``: the
  pressure distribution broadens diffusively with the variance ``<p^2> = 2 G sigma0^2``
  accumulated from the modes up to q, and the contact area is the probability mass that stays at
  p > 0 with an absorbing boundary at p = 0, ``erf(sigma0 / sqrt(2 <p^2>))`` (Persson 2001).
  ``G`` uses ``|E|``, not E' (the stress amplitude of a full-contact mode) and no S factor
  (Persson 2006).
* ``S(q)`` corrects the friction for the elastic coupling between asperity contacts (Persson
  2006; Yang & Persson 2008): ``S -> 1`` in full contact, ``S -> gamma`` when ``P -> 0``.  We
  use ``gamma = 0.5`` by default: it is the value of Persson's friction papers from 2006 on and
  the upper end of the 0.42-0.5 range fitted to the elastic energy of GFMD contacts; gamma
  scales mu linearly in the small-contact regime, so 0.45 would give ~10 % less.  Set
  ``gamma = 1`` for Persson's 2001 theory without correction.
* The thesis prints ``E*`` in the angle integral; the real part drops out
  (``E'(-omega) = E'(omega)`` while ``cos(phi)`` changes sign under ``phi -> pi - phi``), so
  this is Persson's ``Im E``.
* The angle integral: ``E*(-omega) = conj(E*(omega))`` makes ``cos(phi) Im E(q v cos phi)`` and
  ``|E|^2`` symmetric under ``phi -> pi - phi`` and ``phi -> -phi``, so
  ``Int_0^{2 pi} = 4 Int_0^{pi/2}``, computed with ``n_phi``-point Gauss-Legendre (default
  32; checked against adaptive quadrature in the tests).  Only ``omega >= 0`` is evaluated.
* Node rule: with spectrum masses ``m_i = Int_bin C dq`` (see :mod:`.spectrum`), G is summed
  bin by bin; each bin contributes its mass times the average of ``P S`` over the G-interval it
  spans (Gauss rule in sqrt(G), see ``_bin_averages``), which converges at second order in the
  node count even where P ~ G^(-1/2).  The area is reported at the bin upper edges;
  ``A/A0 = P(q1)``.

1D (line) roughness: plane strain, the fair comparison with the 2D FE
--------------------------------------------------------------------
The FE is plane strain in the x-z plane: the road is a profile h(x), constant across the
width.  The same theory for line roughness h(x) on a viscoelastic half-space replaces the
isotropic 2D PSD by the profile PSD C1D (two-sided, Persson convention) and drops the angle
integral (all wavevectors point along the sliding direction, cos phi = 1)::

    mu   = 1/((1 - nu^2) sigma0) Int_{q0}^{q1} dq q^2 C1D(q) P(q) S(q) E''(q v, T_q)
    G(q) = 1/4 Int_{q0}^{q} dq' q'^2 C1D(q') |E(q' v, T_q') / ((1 - nu^2) sigma0)|^2

Both follow from the 2D formulas for a surface that is rough in x only, ``C(q) = C1D(q_x)
delta(q_y)``, or directly: the full-contact pressure variance of the profile is
``<p^2> = Int_{-inf}^{inf} dq C1D q^2 |E(q v)|^2 / (4 (1 - nu^2)^2)`` (same half-plane
stiffness), ``G = <p^2>/(2 sigma0^2)``, and the friction stress is the sum over modes of the
single-mode result below (two-sided C1D: the modes +q and -q together give the factor 2 that
turns ``1/2 Int_{-inf}^{inf}`` into ``Int_0^inf``).  S(q) was calibrated for 2D contacts; we keep
the same form and gamma for line roughness (no 1D calibration exists); S = 1 in full contact,
so the exact limit is unaffected (``gamma = 1`` removes it).

Derivation of the full-contact limit (P = S = 1), exact in linear viscoelasticity: a rigid
profile ``h(x') = h0 cos(k x')`` slides at speed v over the rubber half-plane; in the rubber
frame the surface ``h(x - v t) = Re[h0 exp(i(omega t - k x))]`` excites ``omega = k v``.  For
this displacement the half-plane (plane strain) responds with the surface pressure
``p = p0 + Re[p_k exp(i(omega t - k x))]``, ``p_k = |k| E*(k v)/(2 (1 - nu^2)) h0``, i.e.
``p = p0 + A (E' cos th - E'' sin th)``, ``A = k h0/(2 (1 - nu^2))``, ``th = omega t - k x``.
Frictionless contact pushes along the surface normal ``(-h', 1)``, so the tangential force on
the rubber per length is ``-p dh/dx``; with ``dh/dx = k h0 sin th``,
``<-p h'> = A k h0 E''/2`` (the E' part is out of phase and averages out).  Hence::

    mu = <-p h'> / p0 = (k h0)^2 E''(k v) / (4 (1 - nu^2) p0),

valid while the contact stays closed, ``p0 >= (k h0/2) |E*(k v)|/(1 - nu^2)``.  The line
spectrum of the cosine is ``C1D = (h0^2/4)[delta(q - k) + delta(q + k)]``; the 1D formula above
with P = S = 1 reproduces mu exactly, and modes add.  It scales with ``Im E*(k v)``: the E'
part stores and returns energy.  Persson's P(q) tends to 1 only asymptotically
(``1 - P = erfc(p0/sqrt(2<p^2>))``), so the theory reproduces the exact result when p0 is a few
times the full-contact threshold (tested to 1e-9).

The small-pressure contact area is the same in both variants: ``A/A0 -> sqrt(8/pi)
sigma0/(E_eff h'_rms)`` with ``E_eff = |E|/(1 - nu^2)`` (elastic, or the high-speed or
low-speed limit of a viscoelastic rubber), ``h'_rms`` the rms slope (1D) or rms gradient (2D).

Flash temperature: :mod:`.flash` (opt-in; needs WLF and thermal data).  Adhesion, eq. (2.11):
:mod:`.adhesion`, evaluated with ``A/A0 = P(q1)`` of this theory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.special import erf

from rubberfriction.driver.theory.adhesion import BellLaw, mu_adhesion
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.flash import FlashOptions, scale_kernels
from rubberfriction.driver.theory.rubber import Rubber
from rubberfriction.driver.theory.spectrum import Spectrum

#: Default correction-factor constant gamma of S(q) (see module docstring).
GAMMA_DEFAULT = 0.5
#: sqrt(8/pi): low-pressure slope of A/A0 versus sigma0/(E_eff h'_rms).
AREA_CONSTANT = math.sqrt(8.0 / math.pi)


@dataclass(frozen=True)
class PerssonOptions:
    """Conventions of eq. (2.10).

    gamma:
        constant of ``S(q) = gamma + (1 - gamma) P^2``; 1 switches the correction off.
    n_phi:
        Gauss-Legendre points for the angle integral on ``[0, pi/2]`` (2D variant only).
    """

    gamma: float = GAMMA_DEFAULT
    n_phi: int = 32

    def __post_init__(self) -> None:
        if not (0.0 <= self.gamma <= 1.0):
            raise TheoryInputError(f"gamma = {self.gamma}; expected 0 <= gamma <= 1")
        if not (isinstance(self.n_phi, int) and self.n_phi >= 2):
            raise TheoryInputError(f"n_phi = {self.n_phi!r}; expected an integer >= 2")


@dataclass
class PerssonResult:
    """mu(v) and the scale-resolved quantities of Persson's theory.

    Arrays indexed ``[iv]`` run over ``v``; ``[iv, iq]`` over ``v`` and the spectrum nodes ``q``.
    """

    variant: str                      #: "1d" (line roughness, plane strain) or "2d" (isotropic)
    v: np.ndarray                     #: sliding speeds (mm/s)
    pressure: float                   #: nominal pressure sigma0 (MPa)
    T0: float | None                  #: background temperature (K); None = reference temperature
    q: np.ndarray                     #: spectrum nodes (1/mm)
    mu: np.ndarray                    #: hysteretic mu_visc(v), eq. (2.10)
    area: np.ndarray                  #: A/A0 = P(q1) at each speed
    mu_q: np.ndarray                  #: per-node contributions to mu, [iv, iq] (sum = mu)
    area_q: np.ndarray                #: A/A0(q) at the node upper edges, [iv, iq]
    G: np.ndarray                     #: G(q) at the node upper edges, [iv, iq]
    temperature_q: np.ndarray | None = None   #: T_q (K), [iv, iq], with flash temperature
    converged: np.ndarray | None = None       #: flash iteration converged, [iv]
    iterations: int = 0
    mu_adhesion: np.ndarray | None = None     #: alpha-free adhesive mu_A(v), eq. (2.11)
    alpha: float = 1.0                        #: adhesion share of eq. (7.3)
    options: PerssonOptions = field(default_factory=PerssonOptions)

    @property
    def mu_total(self) -> np.ndarray:
        """``mu_H + alpha mu_A`` (thesis eq. 7.3); mu_H alone without an adhesion law."""
        if self.mu_adhesion is None:
            return self.mu.copy()
        return self.mu + self.alpha * self.mu_adhesion

    @property
    def flash_temperature(self) -> np.ndarray | None:
        """Temperature rise of the finest scale, ``T_q1 - T0`` (K), per speed."""
        if self.temperature_q is None:
            return None
        base = self.T0 if self.T0 is not None else 0.0
        return self.temperature_q[:, -1] - base


def full_contact_pressure_sinusoid(k: float, h0: float, E: complex, nu: float = 0.5) -> float:
    """Smallest pressure (MPa) keeping ``h0 cos(kx)`` in full contact: ``k h0 |E|/(2(1-nu^2))``."""
    return abs(k * h0) * abs(E) / (2.0 * (1.0 - nu**2))


def mu_full_contact_sinusoid(k: float, h0: float, E: complex, p0: float, nu: float = 0.5) -> float:
    """Exact linear viscoelastic mu of a sinusoid in full contact (see module docstring).

    ``mu = (k h0)^2 E''(k v)/(4 (1 - nu^2) p0)``; pass ``E = E*(k v)`` (MPa).  Raises if p0 is
    below the full-contact pressure, where the formula does not apply.
    """
    if p0 <= 0:
        raise TheoryInputError(f"pressure p0 = {p0} MPa must be > 0")
    p_full = full_contact_pressure_sinusoid(k, h0, E, nu)
    if p0 < p_full:
        raise TheoryInputError(
            f"p0 = {p0:g} MPa is below the full-contact pressure {p_full:g} MPa: partial contact"
        )
    return (k * h0) ** 2 * complex(E).imag / (4.0 * (1.0 - nu**2) * p0)


def contact_area_elastic(pressure: np.ndarray | float, E_eff: float,
                         slope_rms: float) -> np.ndarray:
    """Persson's elastic contact area ``A/A0 = erf(sqrt(2) p/(E_eff h'_rms))`` (both variants).

    ``E_eff = E/(1 - nu^2)`` (MPa), ``slope_rms`` = rms slope (1D) or rms gradient (2D).  It is
    ``erf(p/sqrt(2 V))`` with the full-contact pressure variance ``V = E_eff^2 h'_rms^2/4``.
    """
    p = np.asarray(pressure, dtype=float)
    return erf(math.sqrt(2.0) * p / (E_eff * slope_rms))


def _check_conditions(pressure: float, v: np.ndarray) -> np.ndarray:
    if not (isinstance(pressure, (int, float, np.floating)) and math.isfinite(pressure)
            and pressure > 0):
        raise TheoryInputError(f"nominal pressure = {pressure!r} MPa; expected a number > 0")
    v = np.atleast_1d(np.asarray(v, dtype=float))
    if v.ndim != 1 or v.size == 0:
        raise TheoryInputError("velocities must be a non-empty 1D list (mm/s)")
    if not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise TheoryInputError(f"sliding velocities must be finite and > 0 mm/s; got {v}")
    return v


class _Evaluator:
    """Evaluates the integrands of eq. (2.10) on (v, q[, phi]) for given scale temperatures."""

    def __init__(self, spectrum: Spectrum, rubber: Rubber, pressure: float, v: np.ndarray,
                 options: PerssonOptions) -> None:
        self.spec = spectrum
        self.rubber = rubber
        self.v = v
        self.opts = options
        self.fac = 1.0 / ((1.0 - rubber.nu**2) * pressure)
        q, m = spectrum.q, spectrum.mass
        if spectrum.dim == 1:
            self.omega = v[:, None] * q[None, :]
            self.w_g = 0.25 * q**2 * m * self.fac**2
            self.w_mu = q**2 * m * self.fac
        else:
            x, w = np.polynomial.legendre.leggauss(options.n_phi)
            phi = 0.25 * math.pi * (x + 1.0)
            self.cphi = np.cos(phi)
            self.wphi = 0.25 * math.pi * w
            self.omega = v[:, None, None] * q[None, :, None] * self.cphi[None, None, :]
            # 1/8 * 4 Int_0^{pi/2} |E|^2 ; 1/2 * 4 Int_0^{pi/2} cos E''
            self.w_g = 0.5 * q**3 * m * self.fac**2
            self.w_mu = 2.0 * q**3 * m * self.fac

    def __call__(self, T: np.ndarray | None) -> tuple[np.ndarray, ...]:
        """Per-node mu contributions, bin-averaged P, and P and G at the bin upper edges."""
        if self.spec.dim == 1:
            E = self.rubber.E(self.omega, T)
            E2 = np.abs(E) ** 2
            loss = E.imag
        else:
            E = self.rubber.E(self.omega, None if T is None else T[:, :, None])
            E2 = np.abs(E) ** 2 @ self.wphi
            loss = E.imag @ (self.wphi * self.cphi)
        g = self.w_g * E2
        G_end = np.cumsum(g, axis=1)
        G_start = G_end - g
        P_bin, PS_bin = _bin_averages(G_start, G_end, self.opts.gamma)
        P_end = erf(0.5 / np.sqrt(G_end))
        mu_q = self.w_mu * loss * PS_bin
        return mu_q, P_bin, P_end, G_end


#: Gauss-Legendre rule on [0, 1] used for the bin averages over sqrt(G).
_GL_X, _GL_W = np.polynomial.legendre.leggauss(4)
_GL_X = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W


def _bin_averages(G_a: np.ndarray, G_b: np.ndarray, gamma: float) -> tuple[np.ndarray, np.ndarray]:
    """Averages of P and P S over G in ``[G_a, G_b]`` (one spectrum bin).

    Within a bin, G grows with the bin's mass while the friction integrand grows with the same
    mass (``dG / dmu`` is ``|E|^2/E''`` up to constants, nearly constant across a narrow bin), so
    a bin contributes its mass times the G-average of ``P S``.  The average is taken with a
    4-point Gauss rule in ``s = sqrt(G)`` (``dG = 2 s ds``), which is smooth even for the first
    bin, where G starts at 0 and P ~ G^(-1/2); a midpoint rule in G would make that bin's error
    O(1) and the convergence in the node count first order.
    """
    s_a = np.sqrt(G_a)[..., None]
    s_b = np.sqrt(G_b)[..., None]
    s = s_a + (s_b - s_a) * _GL_X
    P = erf(0.5 / np.maximum(s, 1e-300))
    w = _GL_W * 2.0 * s / (s_a + s_b)          # sums to 1: exact average of a constant
    P_avg = np.sum(w * P, axis=-1)
    PS_avg = np.sum(w * P * (gamma + (1.0 - gamma) * P * P), axis=-1)
    return P_avg, PS_avg


def persson_friction(
    spectrum: Spectrum,
    rubber: Rubber,
    pressure: float,
    velocities: np.ndarray | list[float] | float,
    T0: float | None = None,
    options: PerssonOptions | None = None,
    flash: FlashOptions | bool | None = None,
    adhesion: BellLaw | None = None,
    alpha: float = 1.0,
) -> PerssonResult:
    """mu(v) from Persson's theory, eq. (2.10); variant by ``spectrum.dim`` (1: line, 2: isotropic).

    Parameters
    ----------
    spectrum:
        PSD nodes from :func:`.spectrum.spectrum_from_psd` or :func:`.spectrum.line_spectrum`.
    rubber:
        Complex modulus, Poisson ratio and (for T0 / flash) WLF shift and thermal data.
    pressure:
        Nominal pressure sigma0 (MPa).
    velocities:
        Sliding speeds (mm/s).
    T0:
        Background temperature (K); None evaluates the modulus at its reference temperature.
    flash:
        ``True`` or :class:`.flash.FlashOptions` to compute the scale temperatures T_q
        self-consistently (Persson 2006; see :mod:`.flash`).
    adhesion, alpha:
        Bell law eq. (7.6) and share alpha of eq. (7.3): adds ``mu_A = tau_A(v) P(q1)/sigma0``
        (eq. 2.11) to the result; with flash, its heat is released at the surface of the real
        contact area.
    """
    v = _check_conditions(pressure, velocities)
    opts = options if options is not None else PerssonOptions()
    if not isinstance(spectrum, Spectrum):
        raise TheoryInputError("spectrum must be a Spectrum (use spectrum_from_psd or "
                               "line_spectrum)")
    if not isinstance(rubber, Rubber):
        raise TheoryInputError("rubber must be a Rubber (use Rubber(modulus, nu) or "
                               "rubber_from_compound)")
    if not (0.0 <= alpha <= 1.0):
        raise TheoryInputError(f"adhesion share alpha = {alpha}; expected 0 <= alpha <= 1 "
                               "(eq. 7.3)")
    if T0 is not None:
        if not (math.isfinite(T0) and T0 > 0):
            raise TheoryInputError(f"temperature T0 = {T0!r} K; expected > 0 K")
        at_ref = rubber.T_ref is not None and abs(T0 - rubber.T_ref) < 1e-9
        if rubber.log10_aT is None and not at_ref:
            raise TheoryInputError(
                f"T0 = {T0} K given but the rubber has no WLF shift: the modulus is only known at "
                "its reference temperature"
            )
    fopts: FlashOptions | None
    if flash is True:
        fopts = FlashOptions()
    elif flash is False or flash is None:
        fopts = None
    else:
        fopts = flash
    if fopts is not None:
        if rubber.log10_aT is None:
            raise TheoryInputError("flash temperature needs the WLF shift log10_aT of the rubber")
        if not rubber.has_thermal:
            raise TheoryInputError("flash temperature needs thermal data rho, c, k of the rubber")
        if T0 is None:
            if rubber.T_ref is None:
                raise TheoryInputError("flash temperature needs the background temperature T0 (K)")
            T0 = rubber.T_ref

    ev = _Evaluator(spectrum, rubber, float(pressure), v, opts)
    nv, nq = v.size, spectrum.q.size
    T = None if T0 is None else np.full((nv, nq), float(T0))
    tau_A = adhesion.tau(v) if adhesion is not None else None

    iterations = 0
    converged = None
    if fopts is not None:
        D, k = rubber.diffusivity, float(rubber.k)
        lower = np.tril(np.ones((nq, nq), dtype=bool))
        K_low = np.empty((nv, nq, nq))
        K_up = np.empty((nv, nq, nq))
        K_surf = np.empty((nv, nq))
        for i, vi in enumerate(v):
            K, s = scale_kernels(spectrum.q, float(vi), D, k)
            K_low[i] = np.where(lower, K, 0.0)
            K_up[i] = np.where(lower, 0.0, K)
            K_surf[i] = s
        converged = np.zeros(nv, dtype=bool)
        kappa = fopts.heat_fraction
        power = kappa * float(pressure) * v          # mW/mm^2 per unit mu
        relax = np.full(nv, fopts.relax)
        prev_change = np.full(nv, np.inf)
        prev_step = np.zeros((nv, nq))
        # 2D: iterate on a half-size angle rule until the temperatures are within 100 tol, then
        # on the full rule, so the fixed point is the full rule's (cheaper: docs/performance.md)
        ev_iter = ev
        if spectrum.dim == 2 and opts.n_phi >= 16:
            half = PerssonOptions(gamma=opts.gamma, n_phi=opts.n_phi // 2)
            ev_iter = _Evaluator(spectrum, rubber, float(pressure), v, half)
        for iterations in range(1, fopts.max_iter + 1):
            mu_q, P_bin, P_end, _ = ev_iter(T)
            w = power[:, None] * mu_q                # heat per node, mW/mm^2 (nominal)
            dT = (np.einsum("vij,vj->vi", K_low, w / P_bin)
                  + np.einsum("vij,vj->vi", K_up, w) / P_bin)
            if tau_A is not None and alpha > 0:
                # adhesive heat kappa alpha tau_A v on the real area P(q1), spread over patch i
                flux = kappa * alpha * tau_A * v * P_end[:, -1]
                dT += K_surf * flux[:, None] / P_bin
            T_new = T0 + dT
            change = np.max(np.abs(T_new - T), axis=1)
            converged = change < fopts.tol
            if ev_iter is not ev and np.max(change) < 100.0 * fopts.tol:
                ev_iter = ev
                converged[:] = False
            if np.all(converged):
                T = T_new
                break
            # per-speed under-relaxation, halved when the update flips sign and shrinks by less than
            # 20 % (an oscillating, hardly contracting iteration)
            step = T_new - T
            osc = (np.sum(step * prev_step, axis=1) < 0) & (change > 0.8 * prev_change)
            relax = np.maximum(np.where(osc, 0.5 * relax, relax), 1e-3)
            prev_change, prev_step = change, step
            T = T + relax[:, None] * step

    mu_q, _, P_end, G_end = ev(T)
    area = P_end[:, -1].copy()
    mu_adh = None
    if adhesion is not None:
        mu_adh = mu_adhesion(adhesion, v, float(pressure), area)
    return PerssonResult(
        variant="1d" if spectrum.dim == 1 else "2d",
        v=v,
        pressure=float(pressure),
        T0=None if T0 is None else float(T0),
        q=spectrum.q.copy(),
        mu=np.sum(mu_q, axis=1),
        area=area,
        mu_q=mu_q,
        area_q=P_end,
        G=G_end,
        temperature_q=T if fopts is not None else None,
        converged=converged,
        iterations=iterations,
        mu_adhesion=mu_adh,
        alpha=float(alpha),
        options=opts,
    )
