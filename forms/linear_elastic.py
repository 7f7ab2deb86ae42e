"""Small-strain linear elasticity in plane strain, for bodies far stiffer than rubber (the road
body of the thermal macro scale, E_road / E_rubber ~ 1e4, thesis table C.1).

    a(u, v) = int sigma(u) : eps(v) dA,   sigma = lambda tr(eps) I + 2 mu eps   (plane strain)

with lambda = E nu / ((1 + nu)(1 - 2 nu)) and mu = E / (2 (1 + nu)).  Units: E in MPa, lengths
in mm, forces per mm depth.
"""

from __future__ import annotations

from typing import Any

import ufl


def lame(E: float, nu: float) -> tuple[float, float]:
    """Lame constants (lambda, mu) of Young's modulus E and Poisson's ratio nu (plane strain)."""
    if not E > 0.0 or not -1.0 < nu < 0.5:
        raise ValueError(f"linear elasticity: E = {E!r} MPa and nu = {nu!r}: expected E > 0 and -1 < nu < 0.5")
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def plane_strain_stiffness(u: Any, v: Any, E: float, nu: float, dx: Any = None) -> Any:
    """Bilinear form a(u, v) of plane-strain linear elasticity (see the module doc)."""
    lam, mu = lame(E, nu)
    eps = lambda w: ufl.sym(ufl.grad(w))  # noqa: E731
    sigma = lam * ufl.tr(eps(u)) * ufl.Identity(2) + 2.0 * mu * eps(u)
    return ufl.inner(sigma, eps(v)) * (dx or ufl.dx)
