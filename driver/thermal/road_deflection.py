"""Elastic road body of the thermal macro scale: its surface deflection under the block's contact
forces, carried into the contact as the shape of the (otherwise rigid) road (staggered).

Thesis 8.4.1 takes the road as rigid for the mechanics because E_road / E_rubber ~ 1e4; issue 15
asks to show by measurement what that changes.  This module is the road of that measurement: a
plane-strain linear elastic rectangle (``forms.linear_elastic``, Q1, graded in z like the heat
road, ``meshes.road.road_body``) in the block's frame, clamped at its bottom and held in x on its
ends.  A linear elastic road has no history, so its deflection under the current contact forces
does not depend on the frame: the road material moving at -v through the block's frame carries no
state.  After each converged sliding step the slave's nodal contact forces (reversed) load the
road surface at the current slave x (linear hat weights, which keep the total force and moment),
the road's surface displacement (u_x, u_z) follows from one solve with the LU factorised once,
and the rigid master polyline is moved by it for the next step (``ThermalCoupler``).  The lag of
one step is of the order of the deflection's change per step (far below a micrometre here).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla
import ufl
from dolfinx import fem
from dolfinx.fem.petsc import assemble_matrix
from mpi4py import MPI

from rubberfriction import validation as V
from rubberfriction.forms import jit
from rubberfriction.forms.compound import Road
from rubberfriction.forms.linear_elastic import plane_strain_stiffness
from rubberfriction.meshes.common import LEFT, OPPOSITE, RIGHT
from rubberfriction.meshes.road import road_body


class ElasticRoad:
    """Plane-strain elastic road [x_lo, x_hi] x [-depth, 0] (mm, block frame) of the material
    ``road`` (its E and nu), bottom clamped, ends held in x (rollers), top loaded by nodal
    forces."""

    def __init__(self, x_lo: float, x_hi: float, depth: float, road: Road, *, h_x: float,
                 first_layer: float = 0.01, grading: float = 1.2) -> None:
        if not x_hi > x_lo:
            raise V.InputError(f"elastic road: x range [{x_lo!r}, {x_hi!r}] mm is empty")
        V.instance("elastic road material", road, Road)
        body = road_body(x_hi - x_lo, depth, h_surface=h_x, first_layer=first_layer,
                         grading=grading, comm=MPI.COMM_SELF)
        mesh = body.mesh
        mesh.geometry.x[:, 0] += x_lo
        self.depth = float(depth)
        self.V = fem.VectorFunctionSpace(mesh, ("Lagrange", 1))
        u, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        A = assemble_matrix(jit.form(plane_strain_stiffness(u, v, road.lame_lambda, road.mu)))
        A.assemble()
        ai, aj, av = A.getValuesCSR()
        n = len(ai) - 1
        K = sps.csr_matrix((av, aj, ai), shape=(n, n))
        X = self.V.tabulate_dof_coordinates()[:, :2]  # per block (node); dof = 2 node + component
        tags = body.facet_tags
        fdim = mesh.topology.dim - 1

        def nodes(tag: int) -> np.ndarray:
            return fem.locate_dofs_topological(self.V, fdim, tags.find(tag))

        fixed = np.concatenate([2 * nodes(OPPOSITE), 2 * nodes(OPPOSITE) + 1, 2 * nodes(LEFT),
                                2 * nodes(RIGHT)])
        self._fixed = np.unique(fixed)
        self._free = np.setdiff1d(np.arange(n), self._fixed)
        self._lu = spla.splu(K[self._free][:, self._free].tocsc())
        tol = 1e-9 * max(1.0, x_hi - x_lo)
        top = np.flatnonzero(np.abs(X[:, 1]) < tol)
        top = top[np.argsort(X[top, 0])]
        self.x_surface = X[top, 0].copy()
        self._top = top
        self.n_dofs = n
        self.u = np.zeros(n)

    def loads(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Nodal load vector of point forces f (m, 2) (N per mm depth) at surface positions x (m,):
        each split linearly onto the two surface nodes around it (sum and first moment kept)."""
        xs = self.x_surface
        x = np.asarray(x, float)
        if x.size and (x.min() < xs[0] - 1e-12 or x.max() > xs[-1] + 1e-12):
            raise V.InputError(f"elastic road: a contact force at x = [{x.min():g}, {x.max():g}] "
                               f"mm lies off the road [{xs[0]:g}, {xs[-1]:g}] mm")
        i = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, len(xs) - 2)
        t = (x - xs[i]) / (xs[i + 1] - xs[i])
        b = np.zeros(self.n_dofs)
        for c in (0, 1):
            node = self._top
            np.add.at(b, 2 * node[i] + c, (1.0 - t) * f[:, c])
            np.add.at(b, 2 * node[i + 1] + c, t * f[:, c])
        return b

    def deflect(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Solve for point forces f (m, 2) at x (m,); returns the surface displacement
        (n_surface, 2) (mm) at ``x_surface``."""
        b = self.loads(x, np.asarray(f, float).reshape(-1, 2))
        self.u[:] = 0.0
        self.u[self._free] = self._lu.solve(b[self._free])
        return self.surface_displacement()

    def surface_displacement(self) -> np.ndarray:
        """(u_x, u_z) of the surface nodes of the last solve (mm)."""
        return np.column_stack([self.u[2 * self._top], self.u[2 * self._top + 1]])

    def at(self, x: np.ndarray) -> np.ndarray:
        """Surface displacement (m, 2) at positions x (linear between nodes, zero beyond the
        road)."""
        d = self.surface_displacement()
        return np.column_stack([np.interp(x, self.x_surface, d[:, c], left=0.0, right=0.0)
                                for c in (0, 1)])
