"""Closed form: a viscoelastic block sliding frictionless in full contact over a small sinusoid.

Closed form (plane strain, linear viscoelastic half-space, steady sliding).  The surface
z = h0 cos(k x) moves at -v relative to the block, so the rubber surface is excited at
omega = k v.  The half-plane surface stiffness gives the pressure perturbation
    p_1 = (E*_eff(omega) / 2) |k| h0,   E*_eff = E*/(1 - nu*^2) = 4 G* (3K + G*) / (3K + 4 G*),
with the complex shear modulus G*(omega) = G_inf (1 + sum_k g_k i omega tau_k / (1 + i omega tau_k))
(g_k = gamma_k / gamma_inf: the Mooney-Rivlin constants are long-term moduli) and the elastic bulk
modulus K = 2/D1.  The horizontal force per length is <p dh/dx>, so with the mean pressure p0
    mu = <p h'> / p0 = (k h0)^2 Im E*_eff(k v) / (4 p0).
Only the loss part contributes; an elastic material gives mu = 0.  The block height is one
wavelength (thesis 6.2.2), so the finite-height correction ~exp(-2 pi) is below 0.2 %.

Production physics: the automatic contact penalty takes ``effective_modulus`` at the run's
excitation frequency; ``rubberfriction verify viscoelastic-sinusoid`` compares FE runs with
``closed_form_mu``.
"""

from __future__ import annotations

import numpy as np

from rubberfriction.forms.compound import Compound


def effective_modulus(compound: Compound, omega: float, temperature: float | None = None) -> complex:
    """E*_eff(omega) = 4 G*(3K + G*)/(3K + 4G*) of the FE material model (elastic volume)."""
    hyp, prony = compound.hyperelastic, compound.prony
    G = complex(hyp.mu)
    if prony is not None:
        tau = np.asarray(prony.tau, float)
        if temperature is not None and compound.wlf is not None:
            tau = tau * compound.wlf.aT(temperature)
        g = np.asarray(prony.gamma, float) / prony.gamma_inf
        G = hyp.mu * (1.0 + np.sum(g * 1j * omega * tau / (1.0 + 1j * omega * tau)))
    K = hyp.K
    return 4.0 * G * (3.0 * K + G) / (3.0 * K + 4.0 * G)


def closed_form_mu(compound: Compound, wavelength: float, amplitude: float, pressure: float,
                   velocity: float, temperature: float | None = None) -> float:
    k = 2.0 * np.pi / wavelength
    E = effective_modulus(compound, k * velocity, temperature)
    return float((k * amplitude) ** 2 * E.imag / (4.0 * pressure))


def full_contact_pressure(compound: Compound, wavelength: float, amplitude: float, velocity: float) -> float:
    """Smallest mean pressure that keeps full contact: |E*_eff| k h0 / 2 (Westergaard p*)."""
    k = 2.0 * np.pi / wavelength
    return float(abs(effective_modulus(compound, k * velocity)) * k * amplitude / 2.0)
