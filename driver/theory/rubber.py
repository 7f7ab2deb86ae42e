"""The rubber as the analytical theories see it: a complex modulus, a Poisson ratio, a shift.

The theories only need the linear viscoelastic response of the compound (thesis ch. 3.3.1,
Prony series eq. 3.33-3.36 and WLF eq. 3.37), so they take a plain callable rather than the FE
material object:

* ``modulus(omega)``: complex Young's modulus ``E*(omega) = E'(omega) + i E''(omega)`` in MPa
  at angular frequency ``omega`` (rad/s), at the reference temperature of the shift function.
  Sign convention: a harmonic strain ``Re[eps0 exp(i omega t)]`` gives the stress
  ``Re[E*(omega) eps0 exp(i omega t)]``, so ``E'' >= 0`` for ``omega > 0`` (dissipation is
  positive).  Only ``omega >= 0`` is ever requested; negative frequencies follow from
  ``E*(-omega) = conj(E*(omega))``, which the theories use explicitly.
* ``nu``: Poisson ratio (default 0.5, incompressible rubber).  The theories use the plane-strain
  (contact) modulus ``E/(1 - nu^2)``, which is ``4E/3 = 4G`` for nu = 1/2.
* ``log10_aT(T)``: WLF (or any) shift, ``log10 a_T`` with ``a_T(T_ref) = 1``; the modulus at
  temperature T is ``E*(omega, T) = E*(omega a_T(T), T_ref)`` (time-temperature superposition,
  thesis eq. 3.37: relaxation times scale as ``tau_i(T) = a_T(T) tau_i(T_ref)``).
* thermal data ``rho`` (t/mm^3), ``c`` (mJ/(t K)), ``k`` (mW/(mm K)) for the flash temperature.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.forms.compound import Compound, prony_complex_modulus

#: Frequencies (rad/s) at which a modulus callable is checked when a Rubber is built.
PROBE_OMEGA = np.logspace(-8.0, 14.0, 45)


@dataclass(frozen=True)
class Rubber:
    """Linear viscoelastic rubber for the analytical theories (see module docstring)."""

    modulus: Callable[[np.ndarray], np.ndarray]
    nu: float = 0.5
    log10_aT: Callable[[np.ndarray], np.ndarray] | None = None
    rho: float | None = None
    c: float | None = None
    k: float | None = None
    name: str = ""
    T_ref: float | None = None

    def __post_init__(self) -> None:
        if not callable(self.modulus):
            raise TheoryInputError("Rubber.modulus must be a callable omega -> complex E* (MPa)")
        if not (math.isfinite(self.nu) and -1.0 < self.nu <= 0.5):
            raise TheoryInputError(f"Poisson ratio nu = {self.nu!r}; expected -1 < nu <= 0.5")
        E = self.E(PROBE_OMEGA)
        if not np.all(np.isfinite(E)):
            bad = PROBE_OMEGA[~np.isfinite(E)][0]
            raise TheoryInputError(f"modulus(omega) is not finite at omega = {bad:g} rad/s")
        if np.any(E.real <= 0):
            bad = PROBE_OMEGA[E.real <= 0][0]
            raise TheoryInputError(
                f"storage modulus E'(omega) must be > 0 MPa; got {E.real[E.real <= 0][0]:g} at "
                f"omega = {bad:g} rad/s"
            )
        tol = 1e-12 * np.abs(E)
        if np.any(E.imag < -tol):
            bad = PROBE_OMEGA[E.imag < -tol][0]
            raise TheoryInputError(
                f"loss modulus E''(omega) < 0 at omega = {bad:g} rad/s: the modulus must follow "
                "E* = E' + i E'' with E'' >= 0 for omega > 0 (time factor exp(+i omega t))"
            )
        for name in ("rho", "c", "k"):
            val = getattr(self, name)
            if val is not None and not (math.isfinite(val) and val > 0):
                raise TheoryInputError(f"thermal parameter {name} = {val!r} must be > 0")

    @property
    def plane_strain_factor(self) -> float:
        """``1/(1 - nu^2)``: multiplies E to give the contact (plane-strain) modulus."""
        return 1.0 / (1.0 - self.nu**2)

    @property
    def has_thermal(self) -> bool:
        """True if density, heat capacity and conductivity are all given."""
        return self.rho is not None and self.c is not None and self.k is not None

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity ``D = k/(rho c)`` in mm^2/s."""
        if not self.has_thermal:
            raise TheoryInputError("the rubber has no thermal data (rho, c, k)")
        return float(self.k) / (float(self.rho) * float(self.c))

    def aT(self, T: np.ndarray | float) -> np.ndarray:
        """Shift factor ``a_T(T)`` (1 where no shift function is given)."""
        T = np.asarray(T, dtype=float)
        if self.log10_aT is None:
            return np.ones_like(T)
        val = np.asarray(self.log10_aT(T), dtype=float)
        if not np.all(np.isfinite(val)):
            raise TheoryInputError(
                f"log10 a_T is not finite for T in [{np.min(T):g}, {np.max(T):g}] K (WLF outside "
                "its range?)"
            )
        return 10.0**val

    def E(self, omega: np.ndarray | float, T: np.ndarray | float | None = None) -> np.ndarray:
        """Complex Young's modulus (MPa) at ``omega >= 0`` rad/s and temperature T (K).

        ``T`` broadcasts against ``omega``; ``None`` means the reference temperature.
        """
        w = np.asarray(omega, dtype=float)
        if T is not None:
            w = w * self.aT(T)
        shape = w.shape
        out = np.asarray(self.modulus(w.ravel()), dtype=complex)
        if out.shape != (w.size,):
            out = np.broadcast_to(out, (w.size,)) if out.size == 1 else out.reshape(w.size)
        return out.reshape(shape)


def prony_modulus(E_inf: float, E_i: np.ndarray,
                  tau_i: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """Generalised Maxwell (Prony) modulus ``E_inf + sum_i E_i i omega tau_i/(1 + i omega tau_i)``.

    Thesis eq. (3.33)-(3.36) in the frequency domain: ``E' = E_inf + sum E_i w^2 t^2/(1+w^2 t^2)``
    and ``E'' = sum E_i w t/(1 + w^2 t^2)`` (MPa, tau in s).
    """
    E_i = np.atleast_1d(np.asarray(E_i, dtype=float))
    tau_i = np.atleast_1d(np.asarray(tau_i, dtype=float))
    if E_i.shape != tau_i.shape:
        raise TheoryInputError("Prony moduli and relaxation times differ in length")
    if not (E_inf > 0 and np.all(E_i >= 0) and np.all(tau_i > 0)):
        raise TheoryInputError("Prony series needs E_inf > 0, E_i >= 0, tau_i > 0")

    def modulus(omega: np.ndarray) -> np.ndarray:
        return prony_complex_modulus(omega, E_inf, E_i, tau_i)

    return modulus


def rubber_from_compound(compound: Compound, T_ref: float | None = None) -> Rubber:
    """A :class:`Rubber` from a ``forms.compound.Compound``: its Young's modulus E* (eq. 3.34) at
    the WLF reference temperature (``T_ref`` unless given), Poisson ratio, WLF shift and thermal
    data (rho, c, k) where it has them."""
    wlf, thermal, prony = compound.wlf, compound.thermal, compound.prony
    if T_ref is None and wlf is not None:
        T_ref = float(wlf.T_ref)
    if prony is not None:
        # the compound's eq. (3.34) with its own E_inf, E_k, tau_k, checked once here rather
        # than on every call of compound.complex_modulus
        E_inf = float(compound.E_inf)
        modulus = prony_modulus(E_inf, np.asarray(prony.moduli(E_inf), dtype=float),
                                np.asarray(prony.tau, dtype=float))
    else:
        def modulus(omega: np.ndarray) -> np.ndarray:
            w = np.asarray(omega, dtype=float)
            return np.asarray(compound.complex_modulus(w), dtype=complex)

    return Rubber(
        modulus=modulus,
        nu=float(compound.hyperelastic.nu),
        log10_aT=None if wlf is None else wlf.log10_aT,
        rho=None if thermal is None else float(thermal.rho),
        c=None if thermal is None else float(thermal.c),
        k=None if thermal is None else float(thermal.k),
        name=str(compound.name),
        T_ref=T_ref,
    )
