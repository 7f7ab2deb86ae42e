"""Adhesive friction: the bell law, thesis eq. (7.6), and its coefficient, eqs. (2.11) and (7.7).

Bell law, eq. (7.6) (after Lorenz et al. 2015)::

    tau_A(v) = tau0 exp(-c [log10(v / v0)]^2)

* ``tau0`` (MPa): peak frictional shear stress in the real contact area (thesis fits
  2.0-5.0 MPa); ``c`` (-): width, dimensionless (thesis 0.12-0.18); ``v0`` (mm/s): speed of the
  peak (thesis 20 and 110 mm/s = 0.02 and 0.11 m/s).
* The thesis writes "log"; we read the decadic logarithm, as Lorenz et al. (2015), whose law the
  thesis adopts, and because with c = 0.12-0.18 it gives the broad, several-decade bell that
  the thesis fits over v = 1e-5..1e-2 m/s (the natural log would narrow the bell by
  ln(10)^2 = 5.3).
* Only the ratio v/v0 enters, so the unit of speed cancels; the package uses mm/s throughout.

Adhesive coefficient, eq. (7.7) / (2.11)::

    mu_A(v) = tau_A(v) A_r(v) / p        with A_r = A/A0 the relative real contact area

``A_r`` is ``P(q_max)`` of Persson's theory (eq. 2.11, Lorenz et al. 2015) or the product of the
per-scale FE contact fractions (eq. 7.5).  The total of eq. (7.3)/(7.8) is
``mu = mu_H + alpha mu_A`` with ``alpha`` in [0, 1] (1 dry, 0 soap-water, between: wet).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubberfriction.driver.theory.errors import TheoryInputError


@dataclass(frozen=True)
class BellLaw:
    """Bell-shaped adhesive shear stress, eq. (7.6): tau0 (MPa), c (-), v0 (mm/s), and the share
    alpha in [0, 1] with which it enters the total, eq. (7.8) (1 dry .. 0 lubricated).

    The one bell-law type of the project: scenes (``[adhesion]``), the multiscale cascade and the
    analytical theories all pass this object.
    """

    tau0: float
    c: float
    v0: float
    alpha: float = 1.0

    def __post_init__(self) -> None:
        for name, val in (("tau0", self.tau0), ("c", self.c), ("v0", self.v0),
                          ("alpha", self.alpha)):
            if not (isinstance(val, (int, float, np.floating)) and math.isfinite(val)):
                raise TheoryInputError(f"bell law {name} = {val!r}; expected a finite number")
        if self.tau0 < 0:
            raise TheoryInputError(f"bell law tau0 = {self.tau0} MPa; expected >= 0")
        if self.c <= 0:
            raise TheoryInputError(f"bell law width c = {self.c}; expected > 0")
        if self.v0 <= 0:
            raise TheoryInputError(f"bell law peak speed v0 = {self.v0} mm/s; expected > 0")
        if not 0.0 <= self.alpha <= 1.0:
            raise TheoryInputError(f"bell law share alpha = {self.alpha}; expected 0 <= alpha <= 1")

    def tau(self, v: np.ndarray | float) -> np.ndarray:
        """``tau_A(v)`` (MPa) at sliding speeds v (mm/s), eq. (7.6)."""
        v = np.asarray(v, dtype=float)
        if np.any(~np.isfinite(v)) or np.any(v <= 0):
            raise TheoryInputError("bell law: sliding speeds must be finite and > 0 mm/s")
        return self.tau0 * np.exp(-self.c * np.log10(v / self.v0) ** 2)


def mu_adhesion(law: BellLaw, v: np.ndarray | float, pressure: float,
                area_ratio: np.ndarray | float) -> np.ndarray:
    """Adhesive friction coefficient ``tau_A(v) A_r / p``, eqs. (2.11) and (7.7).

    ``pressure`` is the nominal pressure p (MPa), ``area_ratio`` the relative real contact area
    A/A0 in [0, 1] (scalar or per speed).
    """
    if not (math.isfinite(pressure) and pressure > 0):
        raise TheoryInputError(f"pressure = {pressure!r} MPa; expected > 0")
    A = np.asarray(area_ratio, dtype=float)
    if np.any(~np.isfinite(A)) or np.any(A < 0) or np.any(A > 1 + 1e-12):
        raise TheoryInputError(f"relative contact area must lie in [0, 1]; got {A}")
    return law.tau(v) * A / pressure


def mu_combined(mu_h: np.ndarray, mu_a: np.ndarray, alpha: float) -> np.ndarray:
    """``mu = mu_H + alpha mu_A``, thesis eq. (7.3)/(7.8), alpha in [0, 1]."""
    if not (0.0 <= alpha <= 1.0):
        raise TheoryInputError(f"adhesion share alpha = {alpha}; expected 0 <= alpha <= 1")
    return np.asarray(mu_h, dtype=float) + alpha * np.asarray(mu_a, dtype=float)
