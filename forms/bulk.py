"""The bulk weak form of the rubber: finite-strain viscoelastic stress and its residual.

Stress (thesis 3.3.3, 3.3.4; eq. 3.77, 3.78), plane strain embedded in 3D:

    S = S_vol + J^(-2/3) DEV{Sbar + beta Sbar + Hstar}

with the fictitious Mooney-Rivlin stress Sbar (``hyperelastic.py``) and the collapsed Prony
history (Hstar, beta) of ``viscoelastic.py``.  S_vol is the penalty volumetric stress of the
displacement-only element or J p C^-1 with an independent pressure p (mixed element).

Residual in the reference configuration (eq. 3.85) with the perturbed-Lagrangian constraint of the
mixed element (eq. 3.61), which stays well posed as K -> infinity:

    R(u, p; v, q) = int (F S) : grad(v) dV + int (g(J) - p/K) q dV

with g(J) = J - 1 for the thesis' quadratic volumetric energy (the form above with J - 1) and
g = ln J for the logarithmic one (``hyperelastic.py``); S_vol = p J g'(J) C^-1.

External loads (tractions) and contact are added by the caller.  The stabilised Q1P0 element
adds :func:`pressure_jump_stabilisation` to the constraint equation.
"""

from __future__ import annotations

from typing import Any

import ufl

from rubberfriction.forms.hyperelastic import (
    MooneyRivlinLike,
    equilibrium_stress,
    fictitious_stress,
    isochoric_stress,
    pressure_stress,
    volumetric_measure,
    volumetric_stress,
)
from rubberfriction.forms.kinematics import deformation_gradient, embed_gradient
from rubberfriction.forms.viscoelastic import viscous_stress


def second_piola(u: Any, p: Any, material: MooneyRivlinLike, history: Any = None) -> Any:
    """Total second Piola-Kirchhoff stress S (3x3 UFL) of displacement u and pressure p.

    ``p`` is the independent pressure of a mixed element or None (displacement-only: the
    volumetric stress follows from D1).  ``history``: an object with the UFL fields ``Hstar``
    and ``beta`` (:class:`~rubberfriction.forms.viscoelastic.ViscoelasticHistory`) or None
    (elastic)."""
    F = deformation_gradient(u)
    if material.form == "feap":
        if history is not None:
            raise ValueError("viscoelasticity needs the split Mooney-Rivlin form (3.58)")
        return equilibrium_stress(F, material)
    Sbar = fictitious_stress(F, material)
    S = isochoric_stress(F, Sbar)
    S = S + (pressure_stress(F, p, material.volumetric) if p is not None
             else volumetric_stress(F, material))
    if history is not None:
        S = S + viscous_stress(F, Sbar, history.Hstar, history.beta)
    return S


def bulk_residual(u: Any, p: Any, v: Any, q: Any, material: MooneyRivlinLike, dx: Any,
                  history: Any = None) -> Any:
    """Residual form of eq. (3.85) plus, for a mixed element (p, q given), eq. (3.61) with
    g(J) in place of J - 1 (module docstring)."""
    F = deformation_gradient(u)
    R = ufl.inner(F * second_piola(u, p, material, history), embed_gradient(v)) * dx
    if p is not None:
        K = 2.0 / material.D1
        g, _ = volumetric_measure(ufl.det(F), material.volumetric)
        R += (g - p / K) * q * dx
    return R


def pressure_jump_stabilisation(p: Any, q: Any, mesh: Any, scale: Any) -> Any:
    """- scale sum_F h_F int_F [p][q] dS over the interior facets (Kechkar and Silvester 1992, the
    global form): penalises pressure jumps between neighbouring cells, which removes the
    checkerboard mode of piecewise-constant pressures.  h_F is the cells' mean width across the
    facet, 1 / |K n| with the inverse Jacobian K (reference per physical length) and the facet
    normal n: on the graded contact layers (thin cells) each facet term is then about one cell area,
    like the pressure mass, whatever the aspect ratio.  ``scale`` = beta / G_s (1/MPa) makes the
    term commensurate with the pressure Schur complement ~ |q|^2 / G.  Zero for a uniform
    pressure (the patch tests are unaffected)."""
    K, n = ufl.JacobianInverse(mesh), ufl.FacetNormal(mesh)
    width = ufl.avg(1.0 / ufl.sqrt(ufl.dot(ufl.dot(K, n), ufl.dot(K, n))))
    return -scale * width * ufl.jump(p) * ufl.jump(q) * ufl.dS
