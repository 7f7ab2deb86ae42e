"""One complex-modulus evaluation of a Prony series (eq. 3.34), pinned against one Maxwell element.

Closed form of an equilibrium spring M_inf in parallel with one Maxwell element (M_1, tau):
M*(omega) = M_inf + M_1 i omega tau / (1 + i omega tau), written out here in complex arithmetic.
Every former evaluation site (the compound, the theory baselines, the sinusoid closed forms and
the relaxation verification) now calls ``prony_complex_modulus``; each is checked against this
closed form to rel 1e-14 (a few round-offs of the real-arithmetic form).
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.sliding.sinusoid import effective_modulus, shear_modulus
from rubberfriction.driver.theory.rubber import prony_modulus, rubber_from_compound
from rubberfriction.driver.verification.relaxation import harmonic_shear
from rubberfriction.forms.compound import (WLF, Compound, MooneyRivlin, PronySeries,
                                           prony_complex_modulus)

TAU = 2.0e-3  # s
GAMMA = 0.9  # gamma_1 = E_1 / E0, gamma_inf = 0.1
OMEGA = np.array([0.0, 1e-2, 1.0, 0.37 / TAU, 1.0 / TAU, 11.0 / TAU, 1e9])
RTOL = 1e-14


def maxwell(omega, M_inf: float, M_1: float, tau: float) -> np.ndarray:
    """Oracle: M_inf + M_1 (i w tau) / (1 + i w tau), complex arithmetic."""
    iwt = 1j * np.asarray(omega, dtype=float) * tau
    return M_inf + M_1 * iwt / (1.0 + iwt)


def compound(wlf: WLF | None = None) -> Compound:
    return Compound("maxwell", MooneyRivlin(C10=0.4, C01=0.1, D1=0.02),
                    PronySeries([GAMMA], [TAU]), wlf, None)


def test_the_kernel_is_one_maxwell_element() -> None:
    E = prony_complex_modulus(OMEGA, 3.0, [27.0], [TAU])
    np.testing.assert_allclose(E, maxwell(OMEGA, 3.0, 27.0, TAU), rtol=RTOL, atol=0)
    assert E[0] == 3.0 and E.shape == OMEGA.shape  # E*(0) = E_inf, real
    W = OMEGA[1:].reshape(2, 3)
    np.testing.assert_allclose(prony_complex_modulus(W, 3.0, [27.0], [TAU]),
                               maxwell(W, 3.0, 27.0, TAU), rtol=RTOL, atol=0)


def test_compound_and_theory_give_the_closed_form() -> None:
    wlf = WLF(c1=8.86, c2=101.6, T_ref=293.15)
    c = compound(wlf)
    E1 = GAMMA * c.E_inf / (1.0 - GAMMA)  # E_1 = gamma_1 E0, E0 = E_inf / gamma_inf
    exact = maxwell(OMEGA, c.E_inf, E1, TAU)
    np.testing.assert_allclose(c.complex_modulus(OMEGA), exact, rtol=RTOL, atol=0)
    np.testing.assert_allclose(c.prony.complex_modulus(OMEGA, c.E_inf), exact, rtol=RTOL, atol=0)
    np.testing.assert_allclose(rubber_from_compound(c).E(OMEGA), exact, rtol=RTOL, atol=0)
    np.testing.assert_allclose(prony_modulus(c.E_inf, [E1], [TAU])(OMEGA), exact, rtol=RTOL,
                               atol=0)
    T, aT = 310.0, 10.0 ** (-8.86 * (310.0 - 293.15) / (101.6 + 310.0 - 293.15))  # eq. 3.33
    np.testing.assert_allclose(c.complex_modulus(OMEGA, T), maxwell(OMEGA, c.E_inf, E1, aT * TAU),
                               rtol=RTOL, atol=0)


@pytest.mark.parametrize("T", [None, 310.0])
def test_sinusoid_shear_and_effective_modulus_give_the_closed_form(T: float | None) -> None:
    wlf = WLF(c1=8.86, c2=101.6, T_ref=293.15)
    c = compound(wlf)
    aT = 1.0 if T is None else 10.0 ** (-8.86 * (T - 293.15) / (101.6 + T - 293.15))
    mu, K = c.hyperelastic.mu, c.hyperelastic.K
    for w in OMEGA:
        G = maxwell(w, mu, GAMMA * mu / (1.0 - GAMMA), aT * TAU)  # G_1 = gamma_1 G0
        assert shear_modulus(c, w, T) == pytest.approx(G, rel=RTOL, abs=0)
        E_eff = 4.0 * G * (3.0 * K + G) / (3.0 * K + 4.0 * G)
        assert effective_modulus(c, w, T) == pytest.approx(E_eff, rel=RTOL, abs=0)
    # without WLF data the temperature is ignored (the reference response), as before
    assert shear_modulus(compound(), 1.0 / TAU, 400.0) == shear_modulus(compound(), 1.0 / TAU)


def test_relaxation_verification_exact_moduli_give_the_closed_form() -> None:
    hyp = compound().hyperelastic
    h = harmonic_shear(hyp, [GAMMA], [TAU], omega=1.7 / TAU, per_cycle=8, cycles=1)
    G = maxwell(1.7 / TAU, hyp.mu, GAMMA * hyp.mu / (1.0 - GAMMA), TAU)
    assert h["G_storage_exact"] == pytest.approx(G.real, rel=RTOL, abs=0)
    assert h["G_loss_exact"] == pytest.approx(G.imag, rel=RTOL, abs=0)
