"""Hyperelastic equilibrium stresses for rubber (thesis ch. 3.3.3).

Three strain-energy forms, all written for the 3x3 plane-strain deformation gradient:

* ``"split"`` -- Mooney-Rivlin with volumetric/isochoric split, eq. (3.58) (ABAQUS form)::

      Psi = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1

  The thesis prints ``- C01 (I2bar - 3)``; with that sign the initial shear modulus would be
  2 (C10 - C01), negative for several tabulated compounds, contradicting eq. (A.8)
  mu = 2 (C10 + C01).  We use ``+``, the ABAQUS definition the thesis' data were fitted for.
* ``"feap"`` -- the unsplit compressible form of eq. (3.53) with Lame-type constants.  The thesis'
  ``- mu2/2 (II_b ...)`` has the same sign issue; we use ``+ mu2/2 (II_b - 3 - 4 ln J)`` with
  mu1 = 2 C10, mu2 = 2 C01 and lambda = K - 2/3 mu - 2 mu2, which reproduces the small-strain
  shear modulus mu = 2 (C10 + C01) and bulk modulus K = 2/D1 of the split form.
* neo-Hooke is the split form with C01 = 0.

The volumetric energy of the split form is Psi_vol = K/2 g(J)^2 with K = 2/D1 (``volumetric``,
:func:`volumetric_measure`):

* ``"quadratic"``: g = J - 1, i.e. (J - 1)^2 / D1, eq. (3.58)/(3.78), the ABAQUS form the thesis'
  D1 were fitted for.  Its hydrostatic Cauchy pressure -K (J - 1) is bounded by K as J -> 0: under
  a compressive pressure above K there is no equilibrium and the material collapses to zero volume
  (and its bulk modulus K J falls with pressure).
* ``"logarithmic"``: g = ln J (Hencky), pressure -K ln(J) / J, unbounded as J -> 0 (bulk
  modulus K (1 - ln J) / J, rising with pressure like a real solid's, dK/dp = 2 at J = 1).

Both have the same small-strain bulk modulus K; they differ at second order in J - 1.

The stress measure is the second Piola-Kirchhoff stress S.  For the split form the isochoric part
is returned through the *fictitious* stress Sbar = 2 dPsi_iso/dCbar, because finite linear
viscoelasticity (eqs. 3.73-3.78, ``viscoelastic.py``) convolves exactly this quantity.
"""

from __future__ import annotations

from typing import Protocol

import ufl


class MooneyRivlinLike(Protocol):
    """What the forms need from a material (``rubberfriction.forms.compound.MooneyRivlin``)."""

    C10: float
    C01: float
    D1: float
    form: str
    volumetric: str


def invariants(C) -> tuple:
    """I1, I2 and J = sqrt(det C) of a 3x3 right Cauchy-Green tensor."""
    I1 = ufl.tr(C)
    I2 = 0.5 * (I1 * I1 - ufl.tr(C * C))
    J = ufl.sqrt(ufl.det(C))
    return I1, I2, J


def dev(T, C) -> ufl.core.expr.Expr:
    """Referential deviator DEV[T] = T - 1/3 (T : C) C^-1, eq. (3.74)."""
    return T - (1.0 / 3.0) * ufl.inner(T, C) * ufl.inv(C)


def fictitious_stress(F, mat: MooneyRivlinLike) -> ufl.core.expr.Expr:
    """Sbar = 2 dPsi_iso/dCbar for Psi_iso = C10 (I1bar - 3) + C01 (I2bar - 3).

    With I1bar = tr Cbar and I2bar = 1/2 (I1bar^2 - tr Cbar^2):
    Sbar = 2 [(C10 + C01 I1bar) 1 - C01 Cbar].
    """
    C = F.T * F
    J = ufl.det(F)
    Cbar = J ** (-2.0 / 3.0) * C
    eye = ufl.Identity(3)
    return 2.0 * ((mat.C10 + mat.C01 * ufl.tr(Cbar)) * eye - mat.C01 * Cbar)


def isochoric_stress(F, Sbar) -> ufl.core.expr.Expr:
    """S_iso = J^(-2/3) DEV{Sbar}, eq. (3.78)."""
    C = F.T * F
    return ufl.det(F) ** (-2.0 / 3.0) * dev(Sbar, C)


def volumetric_measure(J, volumetric: str) -> tuple:
    """g(J) and J g'(J) of Psi_vol = K/2 g(J)^2 (module docstring): J - 1 and J for
    ``"quadratic"`` (eq. 3.78), ln J and 1 for ``"logarithmic"``."""
    if volumetric == "quadratic":
        return J - 1.0, J
    if volumetric == "logarithmic":
        return ufl.ln(J), 1.0
    raise ValueError(f"volumetric energy: got {volumetric!r}, expected 'quadratic' or "
                     "'logarithmic'")


def volumetric_stress(F, mat: MooneyRivlinLike) -> ufl.core.expr.Expr:
    """S_vol = J dPsi_vol/dJ C^-1 = K g(J) J g'(J) C^-1, K = 2/D1 (eq. 3.78 for g = J - 1)."""
    C = F.T * F
    g, Jdg = volumetric_measure(ufl.det(F), mat.volumetric)
    return (2.0 / mat.D1) * g * Jdg * ufl.inv(C)


def pressure_stress(F, p, volumetric: str = "quadratic") -> ufl.core.expr.Expr:
    """Volumetric stress of the mixed formulation with the independent pressure p = K g(J):
    S = p J g'(J) C^-1 (J p C^-1 for the quadratic energy, p C^-1 for the logarithmic one)."""
    C = F.T * F
    _, Jdg = volumetric_measure(ufl.det(F), volumetric)
    return Jdg * p * ufl.inv(C)


def feap_stress(F, mat: MooneyRivlinLike) -> ufl.core.expr.Expr:
    """S of the unsplit form (3.53) (sign convention in the module docstring)."""
    C = ufl.variable(F.T * F)
    I1, I2, J = invariants(C)
    mu1, mu2 = 2.0 * mat.C10, 2.0 * mat.C01
    K = 2.0 / mat.D1
    lam = K - 2.0 / 3.0 * (mu1 + mu2) - 2.0 * mu2
    lnJ = ufl.ln(J)
    psi = (
        0.5 * mu1 * (I1 - 3.0 - 2.0 * lnJ)
        + 0.5 * mu2 * (I2 - 3.0 - 4.0 * lnJ)
        + 0.25 * lam * (J * J - 1.0 - 2.0 * lnJ)
    )
    return 2.0 * ufl.diff(psi, C)


def equilibrium_stress(F, mat: MooneyRivlinLike) -> ufl.core.expr.Expr:
    """Full hyperelastic S for the displacement-only formulation (any supported form)."""
    if mat.form == "feap":
        return feap_stress(F, mat)
    if mat.form != "split":
        raise ValueError(f"hyperelastic form: got {mat.form!r}, expected 'split' or 'feap'")
    return isochoric_stress(F, fictitious_stress(F, mat)) + volumetric_stress(F, mat)
