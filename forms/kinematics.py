"""Plane-strain kinematics embedded in 3D (thesis ch. 3.1).

The finite-element fields live in the x-z plane (stored as x, y).  Constitutive laws are written
for 3x3 tensors: the out-of-plane stretch is 1 (plane strain), so F = [[F_2D, 0], [0, 1]].  The
out-of-plane stress component S_33 is non-zero and enters the isochoric/volumetric split through
the 3D invariants, as in ABAQUS' CPE elements.
"""

from __future__ import annotations

import ufl


def deformation_gradient(u) -> ufl.core.expr.Expr:
    """3x3 deformation gradient of a plane-strain displacement field u = (u_x, u_z)."""
    g = ufl.grad(u)
    return ufl.as_matrix(
        [[1.0 + g[0, 0], g[0, 1], 0.0], [g[1, 0], 1.0 + g[1, 1], 0.0], [0.0, 0.0, 1.0]]
    )


def embed_gradient(v) -> ufl.core.expr.Expr:
    """Gradient of a plane test/trial field as a 3x3 tensor with zero third row and column."""
    g = ufl.grad(v)
    return ufl.as_matrix([[g[0, 0], g[0, 1], 0.0], [g[1, 0], g[1, 1], 0.0], [0.0, 0.0, 0.0]])


def vector_from_tensor3(T) -> ufl.core.expr.Expr:
    """9-component row-major vector of a 3x3 tensor (for evaluation at quadrature points)."""
    return ufl.as_vector([T[i, j] for i in range(3) for j in range(3)])


#: (row, column) of the 4 independent components of a symmetric plane-strain tensor (xx, zz,
#: out-of-plane yy, xz): the x-y and z-y shears are zero, T = [[T0, T3, 0], [T3, T1, 0], [0, 0, T2]]
PLANE_SYM_COMPONENTS = ((0, 0), (1, 1), (2, 2), (0, 1))
#: weights of the components in T : T (the shear appears twice)
PLANE_SYM_WEIGHTS = (1.0, 1.0, 1.0, 2.0)


def plane_sym_from_vector(v) -> ufl.core.expr.Expr:
    """Symmetric plane-strain 3x3 tensor from its 4 components (``PLANE_SYM_COMPONENTS``)."""
    return ufl.as_matrix([[v[0], v[3], 0.0], [v[3], v[1], 0.0], [0.0, 0.0, v[2]]])


def vector_from_plane_sym(T) -> ufl.core.expr.Expr:
    """The 4 components (``PLANE_SYM_COMPONENTS``) of a symmetric plane-strain 3x3 tensor."""
    return ufl.as_vector([T[i, j] for i, j in PLANE_SYM_COMPONENTS])
