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

    With I1bar = tr Cbar and I2bar = 1/2 (I1bar^2 - tr Cbar^2):  Sbar = 2 [(C10 + C01 I1bar) 1 - C01 Cbar].
    """
    C = F.T * F
    J = ufl.det(F)
    Cbar = J ** (-2.0 / 3.0) * C
    I = ufl.Identity(3)
    return 2.0 * ((mat.C10 + mat.C01 * ufl.tr(Cbar)) * I - mat.C01 * Cbar)


def isochoric_stress(F, Sbar) -> ufl.core.expr.Expr:
    """S_iso = J^(-2/3) DEV{Sbar}, eq. (3.78)."""
    C = F.T * F
    return ufl.det(F) ** (-2.0 / 3.0) * dev(Sbar, C)


def volumetric_stress(F, D1: float) -> ufl.core.expr.Expr:
    """S_vol = J dPsi_vol/dJ C^-1 with Psi_vol = (J - 1)^2 / D1, eq. (3.78)."""
    C = F.T * F
    J = ufl.det(F)
    return J * (2.0 / D1) * (J - 1.0) * ufl.inv(C)


def pressure_stress(F, p) -> ufl.core.expr.Expr:
    """Volumetric stress of the mixed formulation: S = J p C^-1 with the independent pressure p."""
    C = F.T * F
    return ufl.det(F) * p * ufl.inv(C)


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
    return isochoric_stress(F, fictitious_stress(F, mat)) + volumetric_stress(F, mat.D1)
