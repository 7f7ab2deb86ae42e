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


def shear_modulus(compound: Compound, omega: float, temperature: float | None = None) -> complex:
    """G*(omega) = G_inf (1 + sum_k g_k i omega tau_k / (1 + i omega tau_k)), tau_k WLF-shifted."""
    hyp, prony = compound.hyperelastic, compound.prony
    if prony is None:
        return complex(hyp.mu)
    if temperature is not None and compound.wlf is not None:  # tau(T) = a(T) tau (eq. 3.37)
        omega = omega * compound.wlf.aT(temperature)
    return complex(prony.complex_modulus(omega, hyp.mu))  # G_k = g_k G_inf = gamma_k G0


def effective_modulus(compound: Compound, omega: float,
                      temperature: float | None = None) -> complex:
    """E*_eff(omega) = 4 G*(3K + G*)/(3K + 4G*) of the FE material model (elastic volume)."""
    G = shear_modulus(compound, omega, temperature)
    K = compound.hyperelastic.K
    return 4.0 * G * (3.0 * K + G) / (3.0 * K + 4.0 * G)


def closed_form_mu(compound: Compound, wavelength: float, amplitude: float, pressure: float,
                   velocity: float, temperature: float | None = None) -> float:
    k = 2.0 * np.pi / wavelength
    E = effective_modulus(compound, k * velocity, temperature)
    return float((k * amplitude) ** 2 * E.imag / (4.0 * pressure))


def full_contact_pressure(compound: Compound, wavelength: float, amplitude: float,
                          velocity: float) -> float:
    """Smallest mean pressure that keeps full contact: |E*_eff| k h0 / 2 (Westergaard p*)."""
    k = 2.0 * np.pi / wavelength
    return float(abs(effective_modulus(compound, k * velocity)) * k * amplitude / 2.0)


def layered_strip_pressure(compound: Compound, wavelength: float, velocity: float, height: float,
                           layers: tuple[tuple[float, float], ...] = (),
                           background: float | None = None) -> complex:
    """Complex pressure amplitude P per unit amplitude of a layered strip (frictionless, full
    contact): the linear viscoelastic solution behind ``layered_strip_mu``.

    The strip 0 <= z <= height (z from the contact face up) is pushed by u_z = e^{i(kx + wt)}
    at z = 0 with zero shear there and held (u = 0) at z = height, as the FE block's top (held
    in x, u_z tied: no harmonic part).  For fields ~ e^{ikx}, plane strain, the state
    y = (u_x, u_z, s_xz, s_zz) solves y' = M y with, per layer (G* at omega = k v and the layer's
    temperature, lambda = K - 2 G*/3),
        u_x'  = -ik u_z + s_xz / G
        u_z'  = (-ik lambda u_x + s_zz) / (lambda + 2G)
        s_xz' = 4 k^2 G (lambda + G) / (lambda + 2G) u_x - ik lambda / (lambda + 2G) s_zz
        s_zz' = -ik s_xz
    (Hooke's law and equilibrium), so y(height) = prod_i expm(M_i d_i) y(0).  The two
    conditions u_x = u_z = 0 at the top fix the unknown u_x(0), s_zz(0); P = -s_zz(0).
    """
    from scipy.linalg import expm

    k = 2.0 * np.pi / wavelength
    omega = k * velocity
    K = compound.hyperelastic.K
    bounds, z = [], 0.0
    for d, T in layers:
        d = min(float(d), height - z)
        if d > 0.0:
            bounds.append((d, T))
            z += d
    if height - z > 0.0:
        bounds.append((height - z, background))
    Phi = np.eye(4, dtype=complex)
    for d, T in bounds:
        G = shear_modulus(compound, omega, T)
        lam = K - 2.0 * G / 3.0
        c = lam + 2.0 * G
        M = np.array([[0.0, -1j * k, 1.0 / G, 0.0],
                      [-1j * k * lam / c, 0.0, 0.0, 1.0 / c],
                      [4.0 * k * k * G * (lam + G) / c, 0.0, 0.0, -1j * k * lam / c],
                      [0.0, 0.0, -1j * k, 0.0]], dtype=complex)
        Phi = expm(M * d) @ Phi
    # y(0) = (a, 1, 0, s): rows u_x, u_z of Phi y(0) vanish
    A = Phi[:2][:, [0, 3]]
    rhs = -Phi[:2, 1]
    _, s_zz = np.linalg.solve(A, rhs)
    return complex(-s_zz)


def layered_strip_mu(compound: Compound, wavelength: float, amplitude: float, pressure: float,
                     velocity: float, height: float, layers: tuple[tuple[float, float], ...] = (),
                     background: float | None = None) -> float:
    """mu = <p h'> / p0 = k h0^2 Im P / (2 p0) of a block of finite height with stepwise constant
    temperature layers (``driver.sliding.temperature``) over a sinusoid h0 cos(kx), in full
    frictionless contact; P from ``layered_strip_pressure``.  One layer over a deep block gives
    ``closed_form_mu``: P -> E*_eff k / 2."""
    k = 2.0 * np.pi / wavelength
    P = layered_strip_pressure(compound, wavelength, velocity, height, layers, background)
    return float(k * amplitude**2 * P.imag / (2.0 * pressure))
