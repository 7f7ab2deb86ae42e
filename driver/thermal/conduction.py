"""Heat conduction in the rubber block and the road body of the thermal macro scale (thesis 8.3.1,
8.4.1), coupled through the contact interface (eqs. 4.24-4.26).

Frame: the block's.  The block [0, l] x [0, h] stands; the road [-behind, l + ahead] x [-d, 0]
is Eulerian, its material moving with velocity ``road_velocity`` along x (``-v`` for a block
sliding at +v), so the heat equation of the road carries the convective term rho c b . grad T,
stabilised by SUPG (``forms.heat.convected_heat_forms``).  A road as long as the slide
(Lagrangian, as in the thesis) would need ``slide / h_x`` element columns; in the block's frame
the road is ``(l + ahead + behind) / h_x`` columns whatever the slide length.  Fresh road enters
at T0 through the face ahead of the block (the inflow face); the wake leaves through the face
behind it (no diffusive flux there); all other outer faces are adiabatic, the block top is held at
T0 unless ``top_temperature`` is None (an adiabatic block, for heat bookkeeping).

Interface (node to node, lumped): block bottom node i and road top node i share x_i and the
length w_i of the interface they represent (h_x, h_x / 2 at the block's ends).  A frictional power
P_i (mW per mm depth, = q(x_i) w_i, eq. 4.25 with the frictional shear) enters the block with the
share kappa and the road with 1 - kappa; where the node is in contact the conductance h_c moves
h_c w_i (T_road - T_block) into the block (eq. 4.24).  This matches the nodal contact state of the
mechanical contact (pressure and weight per slave node).

Meshes: both bodies graded in z from the interface (first element 0.01 mm, thesis 8.4.1), equal
spacing h_x along x on both sides of the interface.  One DOLFINx mesh holds both bodies (they share
no vertices), Q1 elements, cellwise material.  The linear systems are assembled once per time
step size and contact set and their LU factorisations reused (SuperLU via scipy; serial: the
thermal macro run is one run on its own communicator).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import dolfinx
import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla
import ufl
from dolfinx import fem
from dolfinx.fem.petsc import assemble_matrix, assemble_vector
from mpi4py import MPI

from rubberfriction import validation as V
from rubberfriction.forms.compound import Thermal
from rubberfriction.forms.heat import convected_heat_forms
from rubberfriction.meshes.common import tensor_grid
from rubberfriction.meshes.grading import graded_nodes

#: Thesis 8.4.1: first element height at the interface, mm.
FIRST_LAYER = 0.01


def geometric_steps(total: float, n: int, first_fraction: float = 1e-3) -> np.ndarray:
    """n time steps adding up to `total`, from total * first_fraction / n growing geometrically:
    a sqrt(t) rise (a switched-on flux) or a cooling surface changes fastest at first, where
    implicit Euler with equal steps would lag."""
    dt0 = total * first_fraction / n
    lo, hi = 1e-12, 2.0  # log of the ratio r with dt0 (r^n - 1) / (r - 1) = total, by bisection
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        r = math.exp(mid)
        lo, hi = (mid, hi) if dt0 * (r ** n - 1.0) / (r - 1.0) < total else (lo, mid)
    steps = dt0 * math.exp(0.5 * (lo + hi)) ** np.arange(n)
    return steps * (total / steps.sum())


def block_levels(height: float, first_layer: float, grading: float) -> np.ndarray:
    """z of the heat block's node rows above the interface (graded from ``first_layer``)."""
    zb, _ = graded_nodes(height, first_layer, grading, name="block_height")
    return zb


@dataclass(frozen=True)
class HeatGeometry:
    """Sizes in mm: block l x h, road depth d, road length ahead of / behind the block, element
    length h_x along x, first element height at the interface and the largest growth ratio."""

    block_length: float = 20.0
    block_height: float = 8.0
    road_depth: float = 10.0
    road_ahead: float = 5.0
    road_behind: float = 20.0
    h_x: float = 0.1
    first_layer: float = FIRST_LAYER
    grading: float = 1.2

    def __post_init__(self) -> None:
        for name in ("block_length", "block_height", "road_depth", "h_x", "first_layer"):
            V.positive(f"HeatGeometry.{name}", getattr(self, name), "mm")
        for name in ("road_ahead", "road_behind"):
            V.nonnegative(f"HeatGeometry.{name}", getattr(self, name), "mm")
        if self.grading < 1.0:
            raise V.InputError(f"HeatGeometry.grading = {self.grading!r}: expected a ratio >= 1")
        for name in ("block_length", "road_ahead", "road_behind"):
            n = getattr(self, name) / self.h_x
            if abs(n - round(n)) > 1e-9 * max(1.0, n):
                raise V.InputError(f"HeatGeometry.{name} = {getattr(self, name)!r} mm is not a "
                                   f"whole number of elements h_x = {self.h_x!r} mm (the "
                                   "interface nodes of both bodies must match)")


@dataclass(frozen=True)
class InterfaceNodes:
    """The contact interface: x (n,), lumped lengths w (n,), block and road dof of each node."""

    x: np.ndarray
    weights: np.ndarray
    block_dofs: np.ndarray
    road_dofs: np.ndarray


class TwoBodyHeat:
    """Transient (implicit Euler, eq. 5.25) and steady heat conduction in block and road.

    ``lumped`` (default) integrates the block's capacity and conduction at the vertices
    (``forms.heat.LUMPED``): no under- or overshoots next to a concentrated heat input (a block
    corner), at about 0.6 % instead of 0.45 % on the closed-form flash (docs/verification.md).
    A moving road keeps consistent forms: lumping its transient convection lets about 1e-4 of
    the early heat leave through its faces (tests/test_thermal_macro.py).

    ``step(dt, power, contact)`` advances the temperature by dt with the nodal frictional power
    ``power`` (mW/mm, one value per interface node) and the contact mask (bool per node, or one
    bool); ``steady(power, contact)`` solves the steady state.  Temperatures in K.
    """

    def __init__(self, geometry: HeatGeometry, rubber: Thermal, road: Thermal, *, T0: float,
                 kappa: float = 1.0, h_c: float = 1.0e6, road_velocity: float = 0.0,
                 top_temperature: float | None = None, supg: bool = True,
                 lumped: bool = True) -> None:
        self.geometry = geometry
        self.rubber, self.road = rubber, road
        self.T0 = V.positive("T0", T0, "K")
        self.kappa = float(kappa)
        if not 0.0 <= self.kappa <= 1.0:
            raise V.InputError(f"kappa = {kappa!r}: expected a heat share in [0, 1]")
        self.h_c = V.nonnegative("h_c", h_c, "mW/(mm^2 K)")
        self.road_velocity = V.real("road_velocity", road_velocity, "mm/s")
        self.top_temperature = top_temperature
        self._build_mesh()
        self.V = fem.FunctionSpace(self.mesh, ("Lagrange", 1))
        self.T = fem.Function(self.V)
        self.T.x.array[:] = T0
        self._cell_data(supg)
        self._locate()
        self._dt = fem.Constant(self.mesh, 1.0)
        T, s = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        # the block lumped, a moving road (convection, SUPG) with consistent forms
        tags = dolfinx.mesh.meshtags(self.mesh, 2,
                                     np.arange(len(self._is_block_cell), dtype=np.int32),
                                     np.where(self._is_block_cell, 1, 2).astype(np.int32))
        dx = ufl.Measure("dx", domain=self.mesh, subdomain_data=tags)

        def forms(dt):
            # theta_n = the trial function: L becomes the matrix B of rhs = B T_n (once per dt)
            ab, Bb = convected_heat_forms(T, s, T, rho_c=self.rho_c, k=self.k, dt=dt, dx=dx(1),
                                          lumped=lumped)
            ar, Br = convected_heat_forms(T, s, T, rho_c=self.rho_c, k=self.k, dt=dt, dx=dx(2),
                                          velocity=self._velocity, tau=self._tau,
                                          lumped=lumped and self._velocity is None)
            return fem.form(ab + ar), (None if dt is None else fem.form(Bb + Br))

        self._forms = {"transient": forms(self._dt), "steady": forms(None)}
        self._cache: dict = {}
        self.time = 0.0

    # ------------------------------------------------------------------ set-up
    def _build_mesh(self) -> None:
        g = self.geometry
        nb = round(g.block_length / g.h_x)
        n_ahead, n_behind = round(g.road_ahead / g.h_x), round(g.road_behind / g.h_x)
        xb = np.linspace(0.0, g.block_length, nb + 1)
        xr = np.linspace(-g.road_behind, g.block_length + g.road_ahead, n_behind + nb + n_ahead + 1)
        zb = block_levels(g.block_height, g.first_layer, g.grading)
        zd, _ = graded_nodes(g.road_depth, g.first_layer, g.grading, name="road_depth")
        pb, cb = tensor_grid(xb, zb)
        pr, cr = tensor_grid(xr, -zd[::-1])
        points = np.vstack([pb, pr])
        cells = np.vstack([cb, cr + len(pb)])
        domain = ufl.Mesh(ufl.VectorElement("Lagrange",
                                            ufl.Cell("quadrilateral", geometric_dimension=2), 1))
        self.mesh = dolfinx.mesh.create_mesh(MPI.COMM_SELF, cells.astype(np.int64), points, domain)
        self._zb, self._zd = zb, zd
        self._block_grid: np.ndarray | None = None  # block dofs as (n_x, n_z), see block_grid

    def _cell_data(self, supg: bool) -> None:
        mesh = self.mesh
        Q = fem.FunctionSpace(mesh, ("DG", 0))
        ncell = mesh.topology.index_map(2).size_local
        mid = dolfinx.mesh.compute_midpoints(mesh, 2, np.arange(ncell, dtype=np.int32))[:, 1]
        self._is_block_cell = mid > 0.0
        rb, rr = self.rubber, self.road
        self.rho_c = fem.Function(Q)
        self.rho_c.x.array[:] = np.where(self._is_block_cell, rb.rho * rb.c, rr.rho * rr.c)
        self.k = fem.Function(Q)
        self.k.x.array[:] = np.where(self._is_block_cell, rb.k, rr.k)
        b = self.road_velocity
        self._velocity = None
        self._tau = None
        if b != 0.0:
            vel = fem.Function(fem.VectorFunctionSpace(mesh, ("DG", 0)))
            arr = vel.x.array.reshape(-1, 2)
            arr[:, 0] = np.where(self._is_block_cell, 0.0, b)
            self._velocity = vel
            if supg:
                h = self.geometry.h_x
                pe = abs(b) * h / (2.0 * rr.diffusivity)
                xi = 1.0 / math.tanh(pe) - 1.0 / pe if pe > 1e-8 else pe / 3.0
                tau = fem.Function(Q)
                tau.x.array[:] = np.where(self._is_block_cell, 0.0, h / (2.0 * abs(b)) * xi)
                self._tau = tau
        self.supg_peclet = abs(b) * self.geometry.h_x / (2.0 * rr.diffusivity)

    def _locate(self) -> None:
        g = self.geometry
        X = self.V.tabulate_dof_coordinates()[:, :2]
        dofmap = self.V.dofmap.list.array.reshape(-1, 4)
        in_block = np.zeros(len(X), bool)
        in_block[dofmap[self._is_block_cell].ravel()] = True
        in_road = np.zeros(len(X), bool)
        in_road[dofmap[~self._is_block_cell].ravel()] = True
        self.block_dofs = np.flatnonzero(in_block)
        self.road_dofs = np.flatnonzero(in_road)
        tol = 1e-9 * max(g.block_length, g.h_x)
        bot = np.flatnonzero(in_block & (np.abs(X[:, 1]) < tol))
        top = np.flatnonzero(in_road & (np.abs(X[:, 1]) < tol))
        bot = bot[np.argsort(X[bot, 0])]
        top = top[np.argsort(X[top, 0])]
        self.road_surface_dofs = top
        # road top nodes under the block: same x
        j = np.searchsorted(X[top, 0] - tol, X[bot, 0]) - 1
        j = np.clip(j, 0, len(top) - 1)
        j = np.where(np.abs(X[top[j], 0] - X[bot, 0]) < tol, j, np.clip(j + 1, 0, len(top) - 1))
        if np.abs(X[top[j], 0] - X[bot, 0]).max() > tol:
            raise RuntimeError("internal error: block and road interface nodes do not match")
        w = np.full(len(bot), g.h_x)
        w[[0, -1]] = 0.5 * g.h_x
        self.interface = InterfaceNodes(X[bot, 0].copy(), w, bot, top[j])
        fixed = []
        if self.top_temperature is not None:
            fixed.append(np.flatnonzero(in_block & (np.abs(X[:, 1] - g.block_height) < tol)))
        if self.road_velocity != 0.0:
            x_in = g.block_length + g.road_ahead if self.road_velocity < 0.0 else -g.road_behind
            fixed.append(np.flatnonzero(in_road & (np.abs(X[:, 0] - x_in) < tol)))
        self._fixed = np.unique(np.concatenate(fixed)) if fixed else np.zeros(0, np.int64)
        self._fixed_values = np.where(np.isin(self._fixed, self.block_dofs),
                                      (self.top_temperature if self.top_temperature is not None
                                       else self.T0),
                                      self.T0)
        self._free = np.setdiff1d(np.arange(len(X)), self._fixed)
        self.X = X
        s = ufl.TestFunction(self.V)
        self._heat_weights = assemble_vector(fem.form(self.rho_c * s * ufl.dx)).array.copy()

    # ------------------------------------------------------------------ assembly
    def _matrices(self, dt: float | None, contact: np.ndarray):
        key = (dt, contact.tobytes())
        if key in self._cache:
            return self._cache[key]
        if len(self._cache) > 8:
            self._cache.clear()
        a, b = self._forms["steady" if dt is None else "transient"]
        if dt is not None:
            self._dt.value = dt
        n = len(self.X)
        K = _csr(a, n)
        itf = self.interface
        H = self.h_c * itf.weights * contact
        b_, r_ = itf.block_dofs, itf.road_dofs
        rows = np.concatenate([b_, r_, b_, r_])
        cols = np.concatenate([b_, r_, r_, b_])
        vals = np.concatenate([H, H, -H, -H])
        K = (K + sps.csr_matrix((vals, (rows, cols)), shape=(n, n))).tocsr()
        Kff = K[self._free][:, self._free].tocsc()
        Kfd = K[self._free][:, self._fixed]
        entry = (spla.splu(Kff), Kfd, None if b is None else _csr(b, n))
        self._cache[key] = entry
        return entry

    def _solve(self, dt: float | None, power, contact) -> None:
        n_itf = len(self.interface.x)
        power = np.broadcast_to(np.asarray(power, float), (n_itf,))
        contact = np.broadcast_to(np.asarray(contact, bool), (n_itf,)).copy()
        if not np.all(np.isfinite(power)) or power.min() < 0.0:
            raise V.InputError("frictional power must be finite and >= 0 at every interface node")
        lu, Kfd, B = self._matrices(dt, contact)
        rhs = B @ self.T.x.array if B is not None else np.zeros(len(self.X))
        rhs[self.interface.block_dofs] += self.kappa * power
        rhs[self.interface.road_dofs] += (1.0 - self.kappa) * power
        rhs_f = rhs[self._free] - Kfd @ self._fixed_values
        T = self.T.x.array
        T[self._fixed] = self._fixed_values
        T[self._free] = lu.solve(rhs_f)

    def nearest_dof(self, x: float, z: float) -> int:
        """The dof nearest to (x, z) in the heat frame (x from the block's trailing edge)."""
        return int(np.argmin(np.hypot(self.X[:, 0] - x, self.X[:, 1] - z)))

    def step(self, dt: float, power, contact=True) -> None:
        """Advance by dt (s) with nodal frictional power (mW/mm) and contact mask."""
        self._solve(V.positive("dt", dt, "s"), power, contact)
        self.time += dt

    def steady(self, power, contact=True) -> None:
        """Steady state for constant power and contact (needs a Dirichlet face or an outflow)."""
        if len(self._fixed) == 0:
            raise V.InputError("steady heat conduction needs a fixed temperature (block top or "
                               "moving road)")
        self._solve(None, power, contact)

    # ------------------------------------------------------------------ outputs
    def heat_content(self) -> tuple[float, float]:
        """Heat stored in block and road relative to T0, int rho c (T - T0) dV (mJ per mm depth)."""
        dT = (self.T.x.array - self.T0) * self._heat_weights
        return float(dT[self.block_dofs].sum()), float(dT[self.road_dofs].sum())

    def interface_temperatures(self) -> tuple[np.ndarray, np.ndarray]:
        """Block-side and road-side temperature at each interface node (K)."""
        itf = self.interface
        return self.T.x.array[itf.block_dofs].copy(), self.T.x.array[itf.road_dofs].copy()

    def interface_gradients(self) -> tuple[np.ndarray, np.ndarray]:
        """dT/dz at each interface node, one-sided over the first element: block side (z > 0) and
        road side (z < 0), K/mm."""
        itf, X, T = self.interface, self.X, self.T.x.array
        tol = 1e-9 * max(1.0, self.geometry.block_length)
        out = []
        for dofs, body, z1 in ((itf.block_dofs, self.block_dofs, self._zb[1]),
                               (itf.road_dofs, self.road_dofs, -self._zd[1])):
            layer = body[np.abs(X[body, 1] - z1) < tol]
            layer = layer[np.argsort(X[layer, 0])]
            j = np.searchsorted(X[layer, 0], X[dofs, 0] - tol)
            out.append((T[layer[j]] - T[dofs]) / z1)
        return out[0], out[1]

    def block_grid(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The block's temperature on its tensor grid: x (n_x,) of the interface nodes, height
        z (n_z,) above the interface and T (n_x, n_z) in K (for the profile of eq. 8.1)."""
        if self._block_grid is None:
            X, d, xs, zs = self.X, self.block_dofs, self.interface.x, self._zb
            i = np.searchsorted(0.5 * (xs[1:] + xs[:-1]), X[d, 0])  # nearest grid line
            j = np.searchsorted(0.5 * (zs[1:] + zs[:-1]), X[d, 1])
            tol = 1e-9 * max(1.0, self.geometry.block_length)
            if (len(d) != len(xs) * len(zs) or np.abs(xs[i] - X[d, 0]).max() > tol
                    or np.abs(zs[j] - X[d, 1]).max() > tol):
                raise RuntimeError("internal error: the block's heat dofs are not a tensor grid")
            grid = np.empty((len(xs), len(zs)), dtype=np.int64)
            grid[i, j] = d
            self._block_grid = grid
        return self.interface.x.copy(), self._zb.copy(), self.T.x.array[self._block_grid]

    def road_surface(self) -> tuple[np.ndarray, np.ndarray]:
        """x and temperature of the road top, from behind the block to ahead of it."""
        d = self.road_surface_dofs
        return self.X[d, 0].copy(), self.T.x.array[d].copy()

    def describe(self) -> str:
        g = self.geometry
        return (f"two-body heat: block {g.block_length} x {g.block_height} mm, road "
                f"[{-g.road_behind}, {g.block_length + g.road_ahead}] x {g.road_depth} mm, "
                f"h_x = {g.h_x} mm, first layer {g.first_layer} mm, {len(self.X)} dofs, "
                f"kappa = {self.kappa}, h_c = {self.h_c:g}, road velocity "
                f"{self.road_velocity:g} mm/s (element Peclet {self.supg_peclet:.3g})")


def _csr(form, n: int) -> sps.csr_matrix:
    """An assembled bilinear form as a scipy CSR matrix (serial)."""
    A = assemble_matrix(form)
    A.assemble()
    ai, aj, av = A.getValuesCSR()
    return sps.csr_matrix((av, aj, ai), shape=(n, n))
