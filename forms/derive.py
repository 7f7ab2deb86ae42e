"""Compound variants derived from one measured master curve (thesis 6.5.1, table 6.1, fig. 6.18).

The thesis varies three properties of its compounds c1..c6 around a base (f0, h0, Tg0): the glass
transition temperature, the Shore A hardness and the filler content (table 6.1), and shows their
measured E'(omega), E''(omega) only as a figure (fig. 6.18).  Each function here is one documented
transformation of an absolute Prony series (:class:`Spectrum`: E_inf, E_k, tau_k at the WLF
reference temperature, with its WLF law) that moves the base the way the thesis' property moves
the compound, with an exactly stated effect (tests/test_derived_compounds.py pins each):

* :func:`shift_glass_transition`: Tg + dT, the whole temperature behaviour translated by dT
  (E*_new(omega, T) = E*_base(omega, T - dT)); at the reference temperature every tau_k is
  multiplied by a(T_ref - dT) of the base WLF, so the loss peak moves by that factor.
* :func:`scale_moduli` with :func:`hardness_factor`: Shore A hardness + dh scales the modulus
  function by Gent's E(S) ratio (E' and E'' at every frequency by the same factor).
* :func:`apply_filler`: the relaxation spectrum stretched in log tau about the loss peak by a
  stated factor (a broader, lower loss peak) and the Maxwell moduli E_k scaled by the Guth-Gold
  hydrodynamic factor (a higher dynamic modulus).

Units: MPa, s, rad/s, K.  The one complex-modulus evaluation is
:func:`rubberfriction.forms.compound.prony_complex_modulus`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np
from scipy.optimize import brentq

from rubberfriction.forms.compound import WLF, PronySeries, prony_complex_modulus


@dataclass(frozen=True)
class Spectrum:
    """An absolute Prony series (eq. 3.34) at ``wlf.T_ref``: E_inf and E_k in MPa, tau_k in s."""

    E_inf: float
    E_k: np.ndarray
    tau: np.ndarray
    wlf: WLF

    def __post_init__(self) -> None:
        E_k = np.array(self.E_k, dtype=float, ndmin=1)
        tau = np.array(self.tau, dtype=float, ndmin=1)
        if E_k.shape != tau.shape or E_k.ndim != 1:
            raise ValueError(f"Spectrum: {E_k.size} moduli but {tau.size} relaxation times")
        if not (self.E_inf > 0 and (E_k >= 0).all() and (tau > 0).all()):
            raise ValueError("Spectrum: expected E_inf > 0, E_k >= 0 and tau_k > 0")
        object.__setattr__(self, "E_inf", float(self.E_inf))
        object.__setattr__(self, "E_k", E_k)
        object.__setattr__(self, "tau", tau)

    def complex_modulus(self, omega: Any, T: float | None = None) -> np.ndarray:
        """E*(omega, T) (eq. 3.34 with the WLF shift, eq. 3.37); T in K, None = T_ref."""
        w = np.asarray(omega, dtype=float)
        if T is not None:
            w = w * self.wlf.aT(T)
        return prony_complex_modulus(w, self.E_inf, self.E_k, self.tau)

    def series(self) -> PronySeries:
        """The dimensionless series of a compound file (gamma_k = E_k / E0, eq. 3.36)."""
        return PronySeries.from_moduli(self.E_inf, self.E_k, self.tau)


# --------------------------------------------------------------------------------------------
# WLF algebra
# --------------------------------------------------------------------------------------------


def rereference_wlf(wlf: WLF, T_new: float) -> WLF:
    """The same WLF law written about another reference temperature (exact).

    log10 a(T) - log10 a(T_new) of (c1, c2, T_ref) equals the WLF of (c1', c2', T_new) with
    c2' = c2 + T_new - T_ref and c1' = c1 c2 / c2' (Ferry, Viscoelastic Properties of Polymers,
    3rd ed. 1980, eq. 11-31).  A master curve's tau_k move with it by a(T_new) (eq. 3.37).
    """
    c2 = wlf.c2 + (T_new - wlf.T_ref)
    if c2 <= 0:
        raise ValueError(f"rereference_wlf: T_new = {T_new!r} K is at or below the WLF "
                         f"singularity {wlf.T_singular!r} K")
    return WLF(wlf.c1 * wlf.c2 / c2, c2, T_new)


def to_reference(sp: Spectrum, T_new: float) -> Spectrum:
    """The same material with its series and WLF written about ``T_new`` (K): tau_k * a(T_new)."""
    return Spectrum(sp.E_inf, sp.E_k, sp.tau * float(sp.wlf.aT(T_new)),
                    rereference_wlf(sp.wlf, T_new))


# --------------------------------------------------------------------------------------------
# (a) glass transition
# --------------------------------------------------------------------------------------------


def tg_shift_factor(wlf: WLF, dT: float) -> float:
    """Factor on every tau_k at T_ref for a glass transition moved by dT (K).

    A compound whose Tg is dT higher behaves at T as the base does at T - dT (the whole WLF
    picture translated by dT; the WLF singularity T_ref - c2, about Tg - 50 K, moves with it), so
    tau_new(T_ref) = tau_base(T_ref - dT) = a(T_ref - dT) tau_base(T_ref):
    log10 F = c1 dT / (c2 - dT).  F > 1 for dT > 0: the loss peak at a fixed temperature moves to
    lower frequency by 1/F (thesis 6.5.1: a higher-Tg summer compound dissipates more at 20 degC
    in the frequency range of road roughness; table 6.1 c4/c5 have Tg0 - 20).  Equivalent form:
    the WLF reference temperature moves by dT with the same c1, c2 (see
    :func:`shift_glass_transition`).
    """
    return float(10.0 ** (wlf.c1 * dT / (wlf.c2 - dT)))


def shift_glass_transition(sp: Spectrum, dT: float) -> Spectrum:
    """The compound with its glass transition moved by dT (K), written about the same T_ref.

    E*_new(omega, T) = E*_base(omega, T - dT) at every omega and T (exact): tau_k times
    :func:`tg_shift_factor`, and the WLF of (c1, c2, T_ref + dT) re-referenced to T_ref
    (c2' = c2 - dT, c1' = c1 c2 / (c2 - dT)).  Moduli unchanged.  Inverse: dT -> -dT.
    """
    moved = WLF(sp.wlf.c1, sp.wlf.c2, sp.wlf.T_ref + dT)
    return Spectrum(sp.E_inf, sp.E_k, sp.tau * tg_shift_factor(sp.wlf, dT),
                    rereference_wlf(moved, sp.wlf.T_ref))


# --------------------------------------------------------------------------------------------
# (b) hardness
# --------------------------------------------------------------------------------------------


def gent_modulus(shore_a: float) -> float:
    """Young's modulus (MPa) of a rubber of Shore A hardness S by Gent's relation:

    E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)) MPa, 0 < S < 100 (A. N. Gent, "On
    the relation between indentation hardness and Young's modulus", Trans. Inst. Rubber Ind. 34,
    46-57, 1958; the form of ASTM D2240's spring force over the indentation of a cone).
    """
    if not 0.0 < shore_a < 100.0:
        raise ValueError(f"gent_modulus: Shore A = {shore_a!r}: expected 0 < S < 100")
    return 0.0981 * (56.0 + 7.62336 * shore_a) / (0.137505 * (254.0 - 2.54 * shore_a))


def gent_shore(E: float) -> float:
    """The inverse of :func:`gent_modulus`: Shore A hardness of a rubber of modulus E (MPa)."""
    if not E > 0:
        raise ValueError(f"gent_shore: E = {E!r} MPa: expected > 0")
    return (E * 0.137505 * 254.0 - 0.0981 * 56.0) / (0.0981 * 7.62336 + E * 0.137505 * 2.54)


def hardness_factor(h0: float, dh: float) -> float:
    """Modulus ratio E(h0 + dh) / E(h0) of Gent's relation (:func:`gent_modulus`)."""
    return gent_modulus(h0 + dh) / gent_modulus(h0)


def scale_moduli(sp: Spectrum, factor: float) -> Spectrum:
    """All moduli (E_inf and every E_k) times ``factor``: E'(omega) and E''(omega) at every
    frequency and temperature scale by exactly that factor, tan delta and tau_k unchanged.
    Thesis 6.5.1 (fig. 6.21, table 6.1 h0 vs h0 + 10 ShA): a harder compound is stiffer at all
    frequencies.  Inverse: 1/factor."""
    if not factor > 0:
        raise ValueError(f"scale_moduli: factor = {factor!r}: expected > 0")
    return replace(sp, E_inf=sp.E_inf * factor, E_k=sp.E_k * factor)


# --------------------------------------------------------------------------------------------
# (c) filler
# --------------------------------------------------------------------------------------------


def _loss(E_k: np.ndarray, tau: np.ndarray) -> Callable[[float], float]:
    return lambda lw: float(prony_complex_modulus(np.array([math.exp(lw)]), 0.0, E_k, tau)
                            .imag[0])


def loss_peak_omega(E_k: Any, tau: Any, points_per_decade: int = 50) -> float:
    """Angular frequency (rad/s) of the global E'' maximum of a Prony series, to rounding.

    A grid locates the maximum; the root of dE''/d ln omega = sum E_k x (1 - x^2) / (1 + x^2)^2
    (x = omega tau_k) between its neighbours refines it (brentq, 1e-15 in ln omega), so a series
    whose tau_k are all multiplied by F has its peak at exactly 1/F times the original's.
    """
    E_k, tau = np.asarray(E_k, float), np.asarray(tau, float)
    lo, hi = math.log(1 / tau.max()) - 5.0, math.log(1 / tau.min()) + 5.0
    lw = np.linspace(lo, hi, int((hi - lo) / math.log(10) * points_per_decade) + 1)
    i = int(np.argmax(prony_complex_modulus(np.exp(lw), 0.0, E_k, tau).imag))
    i = min(max(i, 1), lw.size - 2)

    def slope(v: float) -> float:
        x = math.exp(v) * tau
        return float(np.sum(E_k * x * (1 - x * x) / (1 + x * x) ** 2))

    return math.exp(brentq(slope, lw[i - 1], lw[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps))


def loss_half_width(E_k: Any, tau: Any) -> tuple[float, float]:
    """Angular frequencies (rad/s) where E'' first falls to half its maximum on either side of
    the peak (brentq on ln omega, to rounding); the width in decades is log10(hi / lo)."""
    E_k, tau = np.asarray(E_k, float), np.asarray(tau, float)
    loss = _loss(E_k, tau)
    lp = math.log(loss_peak_omega(E_k, tau))
    half = 0.5 * loss(lp)
    ends = []
    for step in (-0.05, 0.05):
        a = lp
        while loss(a + step) > half:
            a += step
        ends.append(brentq(lambda v: loss(v) - half, a, a + step, xtol=1e-14, rtol=1e-15))
    return math.exp(ends[0]), math.exp(ends[1])


def loss_fwhm_decades(E_k: Any, tau: Any) -> float:
    """Full width at half maximum of E''(omega) in decades of frequency."""
    lo, hi = loss_half_width(E_k, tau)
    return math.log10(hi / lo)


def stretch_spectrum(sp: Spectrum, b: float, tau_c: float | None = None) -> Spectrum:
    """The relaxation times spread by ``b`` in log tau about tau_c (default: the loss peak's
    tau_p = 1/omega_p): log tau_k' = log tau_c + b (log tau_k - log tau_c); moduli unchanged.

    Exact effect: the E_k-weighted rms of ln(tau_k / tau_c) (:func:`log_tau_spread`) grows by
    exactly b; b > 1 broadens the loss peak and lowers it, b = 1 is the identity and
    stretch(stretch(sp, b, tau_c), 1/b, tau_c) gives sp back.
    """
    if not b > 0:
        raise ValueError(f"stretch_spectrum: b = {b!r}: expected > 0")
    tau_c = 1.0 / loss_peak_omega(sp.E_k, sp.tau) if tau_c is None else float(tau_c)
    return replace(sp, tau=tau_c * (sp.tau / tau_c) ** b)


def log_tau_spread(sp: Spectrum, tau_c: float) -> float:
    """E_k-weighted rms of ln(tau_k / tau_c): the width of the discrete relaxation spectrum."""
    d = np.log(sp.tau / tau_c)
    return float(math.sqrt(np.sum(sp.E_k * d * d) / np.sum(sp.E_k)))


def filler_volume_fraction(phr: float, rho_filler: float = 1.8, rho_rubber: float = 0.93
                           ) -> float:
    """Volume fraction of ``phr`` parts of filler per hundred of rubber (densities in g/cm^3;
    carbon black 1.8, a diene rubber blend 0.93)."""
    v = phr / rho_filler
    return v / (v + 100.0 / rho_rubber)


def guth_gold(phi: float) -> float:
    """Guth-Gold hydrodynamic reinforcement E_filled / E_gum = 1 + 2.5 phi + 14.1 phi^2 (E. Guth,
    J. Appl. Phys. 16, 20-25, 1945: Einstein's dilute-sphere term plus pair interactions)."""
    return 1.0 + 2.5 * phi + 14.1 * phi * phi


def apply_filler(sp: Spectrum, stretch: float, modulus_factor: float) -> Spectrum:
    """More filler (thesis 6.5.1, fig. 6.22, table 6.1 f0 vs f0 + 35 phr): a broader loss peak
    and a higher dynamic modulus.

    The relaxation spectrum is stretched by ``stretch`` in log tau about the base's loss peak
    (:func:`stretch_spectrum`: the bound-rubber shells around filler particles add slower and
    faster segment mobilities on both sides of the matrix transition), and every Maxwell modulus
    E_k is multiplied by ``modulus_factor`` (hydrodynamic reinforcement, :func:`guth_gold`, on the
    dynamic part; E_inf stays: at equal Shore hardness, table 6.1's filled compounds have no higher
    long-term modulus, c3 vs c6 and c1 vs c2).  Exact effects: the spectrum's
    :func:`log_tau_spread` about the base's loss peak grows by ``stretch``; the glassy increment
    E0 - E_inf = sum E_k grows by ``modulus_factor``; E''(omega) of the result is modulus_factor
    times E'' of the stretched series.  The FWHM of E'' in log frequency grows with the stretch
    but not by a closed-form factor (each Maxwell term keeps its own 1.14-decade Debye width);
    :func:`loss_fwhm_decades` measures it.
    """
    if not modulus_factor > 0:
        raise ValueError(f"apply_filler: modulus_factor = {modulus_factor!r}: expected > 0")
    s = stretch_spectrum(sp, stretch)
    return replace(s, E_k=s.E_k * modulus_factor)


def with_long_term(sp: Spectrum, E_inf: float) -> Spectrum:
    """The same Maxwell moduli and times with another long-term modulus E_inf (MPa): E'' is
    unchanged at every frequency, E' moves by E_inf - sp.E_inf."""
    return replace(sp, E_inf=E_inf)
