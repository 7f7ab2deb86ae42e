"""Small-strain linear elasticity in plane strain, for bodies far stiffer than rubber (the road
body of the thermal macro scale, E_road / E_rubber ~ 1e4, thesis table C.1).

    a(u, v) = int sigma(u) : eps(v) dA,   sigma = lambda tr(eps) I + 2 mu eps   (plane strain)

with the Lame constants lambda and mu of the material (``forms.compound.Road.lame_lambda``,
``Road.mu``, eq. A.7).  Units: MPa, lengths in mm, forces per mm depth.
"""

from __future__ import annotations

from typing import Any

import ufl


def plane_strain_stiffness(u: Any, v: Any, lam: float, mu: float, dx: Any = None) -> Any:
    """Bilinear form a(u, v) of plane-strain linear elasticity with Lame constants lam, mu (MPa)."""
    eps = lambda w: ufl.sym(ufl.grad(w))  # noqa: E731
    sigma = lam * ufl.tr(eps(u)) * ufl.Identity(2) + 2.0 * mu * eps(u)
    return ufl.inner(sigma, eps(v)) * (dx or ufl.dx)
