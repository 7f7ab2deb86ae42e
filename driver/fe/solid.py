"""The viscoelastic rubber body: function spaces, bulk residual, history, boundary dofs.

One `SolidProblem` per body and run.  It assembles nothing itself; `newton.py` does, with the
constraints and contact hooks the driver adds.  The weak form is ``forms/bulk.py``.  Elements
(``SolidSettings.element``):

* ``"Q1P0"`` (default): bilinear displacement, piecewise-constant pressure, the mixed element of the
  thesis' ABAQUS hybrid elements (CPE4H), perturbed-Lagrangian form  int (J - 1 - p/K) dp = 0 that
  stays well posed as K -> infinity and avoids volumetric locking (thesis 3.3.3, eq. 3.61).
* ``"Q1P0s"``: Q1P0 with the pressure-jump stabilisation of Kechkar and Silvester (Math. Comp. 58,
  1992) in the constraint equation,

      int (J - 1 - p/K) q dV  -  (beta / G_s) sum_F h_F int_F [p][q] dS = 0   (interior facets F,
                                                           h_F the cells' width across F),

  which removes the checkerboard pressure mode of Q1P0 (a pair that is not inf-sup stable: the
  mode grows critical where rubber is confined in a filled valley far above its modulus) and makes
  the pair stable.  The term vanishes for a uniform pressure, so the patch tests still hold
  exactly, and contact faces stay bilinear (a Q2 element's midside nodes would need
  quadratic mortar segments: linear ones fail the contact patch test).  G_s is the shear modulus
  the deformation sees (``SolidSettings.stabilisation_modulus``; 0: the long-term one), beta =
  ``SolidSettings.stabilisation`` (Kechkar and Silvester: stable for any beta > 0).  Default 0.01:
  the lowest non-uniform pressure mode of a confined block stays bounded below under refinement
  (``verify pressure-modes``), and the full-contact sinusoid stays close to its closed form, where
  a larger beta acts as a compressibility on the mesh scale (figures: docs/verification.md).
  The term is linear in p and constant, so it enters as a Newton hook on the pressure dofs
  (:class:`PressureJump`): build the Newton problem with :meth:`SolidProblem.nonlinear_problem`,
  which adds it (``residual`` is the bulk form alone).
* ``"Q1"``: displacement only, for comparison (locks when nearly incompressible).

Bulk stress and residual: :func:`rubberfriction.forms.bulk.second_piola` and
:func:`~rubberfriction.forms.bulk.bulk_residual` (eq. 3.77, 3.85, 3.61), plane strain.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import basix
import numpy as np
import ufl
from dolfinx import cpp as _cpp
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc
from scipy.sparse import csr_matrix
from scipy.spatial import cKDTree

from rubberfriction.driver.fe.constraints import ConstraintMap
from rubberfriction.driver.fe.newton import ConstrainedNonlinearProblem
from rubberfriction.forms import jit
from rubberfriction.forms.bulk import bulk_residual, pressure_jump_stabilisation, second_piola
from rubberfriction.forms.hyperelastic import dev, fictitious_stress, volumetric_measure
from rubberfriction.forms.kinematics import deformation_gradient, vector_from_plane_sym
from rubberfriction.forms.viscoelastic import ViscoelasticHistory, quadrature_rule

ELEMENTS = ("Q1P0", "Q1P0s", "Q1")
#: elements with an independent pressure
MIXED = ("Q1P0", "Q1P0s")


@dataclass(frozen=True)
class SolidSettings:
    element: str = "Q1P0"
    quadrature_degree: int = 2
    # history update: "linear" (exact for ramps) or "midpoint" (3.76)
    viscous_scheme: str = "linear"
    stabilisation: float = 0.01  # beta of Q1P0s
    stabilisation_modulus: float = 0.0  # G_s of Q1P0s in MPa; 0: the long-term shear modulus

    def __post_init__(self) -> None:
        if self.element not in ELEMENTS:
            raise ValueError(f"element: got {self.element!r}, expected one of {ELEMENTS}")
        if self.viscous_scheme not in ("linear", "midpoint"):
            raise ValueError(f"viscous_scheme: got {self.viscous_scheme!r}, expected 'linear' or "
                             "'midpoint'")
        if self.quadrature_degree < 1:
            raise ValueError(f"quadrature_degree must be >= 1, got {self.quadrature_degree}")
        if not (self.stabilisation > 0.0 and self.stabilisation_modulus >= 0.0):
            raise ValueError(f"stabilisation = {self.stabilisation!r} (> 0), "
                             f"stabilisation_modulus = {self.stabilisation_modulus!r} MPa (>= 0; "
                             "0: long-term G)")

    @property
    def mixed(self) -> bool:
        return self.element in MIXED


@dataclass(frozen=True)
class BoundaryNodes:
    """Nodes of a tagged boundary: reference coordinates, displacement dofs and segments.

    segments[i] = (a, b) indexes into the node arrays, ordered so that the body lies on the LEFT
    of a -> b: the outward normal is the right-hand normal (t_z, -t_x) of t = X_b - X_a.  On the
    bottom face of a block this runs in +x and the outward normal is -z.
    """

    X: np.ndarray  # (n, 2)
    dofs: np.ndarray  # (n, 2) full-space dofs of (u_x, u_z), int32
    segments: np.ndarray  # (m, 2)
    nodes: np.ndarray  # (n,) index of each node in the displacement node numbering


class SolidProblem:
    """Rubber body with Mooney-Rivlin equilibrium and optional Prony viscoelasticity.

    material: an object with ``hyperelastic`` (C10, C01, D1, form), optionally ``prony`` (gamma,
    tau) and ``wlf`` (aT(T)) -- a ``rubberfriction.forms.compound.Compound``.
    """

    def __init__(self, mesh, facet_tags, material, settings: SolidSettings | None = None,
                 cell_tags=None, viscous: bool | None = None):
        if mesh.comm.size > 1:
            raise ValueError("SolidProblem runs on one rank per run (farm runs over ranks "
                             f"instead); got a mesh on a communicator of size {mesh.comm.size}")
        self.mesh, self.facet_tags, self.cell_tags = mesh, facet_tags, cell_tags
        self.settings = settings or SolidSettings()
        self.material = material
        hyp = material.hyperelastic
        self.hyperelastic = hyp
        prony = getattr(material, "prony", None)
        self.viscous = ((prony is not None) if viscous is None
                        else bool(viscous and prony is not None))
        cell = mesh.ufl_cell()
        Ve = ufl.VectorElement("Lagrange", cell, 1)
        if self.settings.mixed:
            if hyp.form != "split":
                raise ValueError(f"the mixed {self.settings.element} element needs the split "
                                 "Mooney-Rivlin form (3.58)")
            self.W = fem.FunctionSpace(mesh,
                                       ufl.MixedElement([Ve, ufl.FiniteElement("DG", cell, 0)]))
            self.V, umap = self.W.sub(0).collapse()
            self.umap = np.asarray(umap, dtype=np.int32)
        else:
            self.W = fem.FunctionSpace(mesh, Ve)
            self.V = self.W
            self.umap = np.arange(self.W.dofmap.index_map.size_local * 2, dtype=np.int32)
        self.w = fem.Function(self.W, name="state")
        self.rule = quadrature_rule(basix.cell.string_to_type(mesh.topology.cell_name()),
                                    self.settings.quadrature_degree)
        self.dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": self.rule.degree})
        self.ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        self.history = self._make_history(prony) if self.viscous else None
        self.residual = self._bulk_residual()
        self._sdev_expr = None
        self._pressure_jump: PressureJump | None = None
        self.cpu_history = 0.0  # CPU seconds spent in prepare_step + commit_step
        self.node_X = self.V.tabulate_dof_coordinates()[:, :2]
        self.n_nodes = self.node_X.shape[0]

    # --- forms -------------------------------------------------------------------------------
    def _make_history(self, prony) -> ViscoelasticHistory:
        gamma = np.asarray(prony.gamma, dtype=float)
        scale = 1.0 / (1.0 - gamma.sum())  # Mooney-Rivlin constants are the long-term moduli
        G_ref = self.shear_modulus_long_term
        wlf = getattr(self.material, "wlf", None)
        shift = wlf.aT if wlf is not None else None
        return ViscoelasticHistory(self.mesh, self.rule, gamma, prony.tau, scale, G_ref, shift,
                                   scheme=self.settings.viscous_scheme)

    def split(self):
        """(u, p) UFL parts of the state (p is None for Q1)."""
        if self.settings.mixed:
            u, p = ufl.split(self.w)
            return u, p
        return self.w, None

    def test_functions(self):
        if self.settings.mixed:
            v, q = ufl.TestFunctions(self.W)
            return v, q
        return ufl.TestFunction(self.W), None

    def fictitious_stress(self):
        u, _ = self.split()
        return fictitious_stress(deformation_gradient(u), self.hyperelastic)

    def second_piola(self):
        """Total second Piola-Kirchhoff stress S (3x3 UFL) of the current state."""
        u, p = self.split()
        return second_piola(u, p, self.hyperelastic, self.history)

    def _bulk_residual(self):
        u, p = self.split()
        v, q = self.test_functions()
        return bulk_residual(u, p, v, q, self.hyperelastic, self.dx, self.history)

    def nonlinear_problem(self, constraints: ConstraintMap, hooks=(), extra_couplings=(),
                          external_force=None) -> ConstrainedNonlinearProblem:
        """The body's Newton problem: its bulk forms, the Q1P0s pressure-jump term (a constant
        linear hook, :class:`PressureJump`) and the caller's hooks (contact) and couplings."""
        own = [] if self.pressure_jump is None else [self.pressure_jump]
        return ConstrainedNonlinearProblem(
            self.residual, self.jacobian(), self.w, constraints, hooks=own + list(hooks),
            extra_couplings=[h.couplings for h in own] + list(extra_couplings),
            external_force=external_force)

    def pressure_relaxation(self) -> Callable[[np.ndarray], None] | None:
        """For a trust-region solve (``driver.fe.trust_region``): a function that sets the cell
        pressures of a full-space state x to K <g(J)>_e, the cell means that make the constraint
        of eq. (3.61) hold exactly for the displacements in x (with p eliminated so, the residual
        is the gradient of the displacements' potential).  None for Q1 (no pressure); Q1P0s
        couples neighbouring pressures (no cell-local optimum) and is refused."""
        if not self.settings.mixed:
            return None
        if self.settings.element != "Q1P0":
            raise ValueError(f"element {self.settings.element!r}: the trust-region solver needs "
                             "cell-local pressures (Q1P0 or Q1); the pressure-jump term of Q1P0s "
                             "couples them")
        Q, pmap = self.W.sub(1).collapse()
        pmap = np.asarray(pmap, dtype=np.int64)
        u, _ = self.split()
        g, _ = volumetric_measure(ufl.det(deformation_gradient(u)), self.hyperelastic.volumetric)
        q = ufl.TestFunction(Q)
        mean_g = jit.form(g * q * self.dx)
        volume = fem_petsc.assemble_vector(jit.form(1.0 * q * self.dx)).array.copy()
        vec = fem_petsc.create_vector(mean_g)
        K = self.bulk_modulus

        def relax(x: np.ndarray) -> None:
            with vec.localForm() as local:
                local.set(0.0)
            fem_petsc.assemble_vector(vec, mean_g)  # reads the state, i.e. x
            x[pmap] = K * vec.array / volume

        return relax

    @property
    def pressure_jump(self) -> PressureJump | None:
        """The Q1P0s stabilisation (None for the other elements), built on first use."""
        if self.settings.element != "Q1P0s":
            return None
        if self._pressure_jump is None:
            G_s = self.settings.stabilisation_modulus or self.shear_modulus_long_term
            self._pressure_jump = PressureJump(self.W, self.settings.stabilisation / G_s)
        return self._pressure_jump

    def add_traction(self, tag: int, traction) -> None:
        """Dead-load traction (force per reference length, N/mm^2 per unit depth) on facets
        `tag`."""
        v, _ = self.test_functions()
        self.residual = self.residual - ufl.inner(traction, v) * self.ds(tag)

    def jacobian(self, residual=None):
        return ufl.derivative(residual if residual is not None else self.residual, self.w,
                              ufl.TrialFunction(self.W))

    # --- material numbers --------------------------------------------------------------------
    @property
    def shear_modulus_long_term(self) -> float:
        hyp = self.hyperelastic
        return 2.0 * (hyp.C10 + hyp.C01)

    @property
    def bulk_modulus(self) -> float:
        return 2.0 / self.hyperelastic.D1

    def plane_strain_modulus(self, instantaneous: bool = True) -> float:
        """E* = E/(1 - nu^2) = 4 G (3K + G)/(3K + 4G) for the long-term or instantaneous G."""
        G = self.shear_modulus_long_term
        if instantaneous and self.history is not None:
            G = G * (1.0 + float(np.sum(self.history.g)))
        K = self.bulk_modulus
        return 4.0 * G * (3.0 * K + G) / (3.0 * K + 4.0 * G)

    # --- time stepping -----------------------------------------------------------------------
    def prepare_step(self, dt: float) -> None:
        """History fields (Hstar, beta) of a step dt (eq. 3.76, ``ViscoelasticHistory``).  Called
        at the last converged state: after a restored history (warm start) it also records that
        state's Cbar, which the exact dissipation of the next step starts from."""
        if self.history is not None:
            c0 = time.process_time()
            if self.history.Cbar_n is None:
                self.history.Cbar_n = self.history_kinematics()[1]
            self.history.prepare_step(dt)
            self.cpu_history += time.process_time() - c0

    def commit_step(self) -> float:
        """Store the converged state in the history; returns the viscous energy of the step."""
        if self.history is None:
            return 0.0
        c0 = time.process_time()
        dE = self.history.commit_step(*self.history_kinematics())
        self.cpu_history += time.process_time() - c0
        return dE

    def history_kinematics(self) -> tuple[np.ndarray, np.ndarray]:
        """DEV{Sbar} and Cbar = J^(-2/3) C of the current state at the quadrature points, each
        (n_points, 4) (``PLANE_SYM_COMPONENTS``): what the history update convolves (eq. 3.76)
        and the strain its branch stresses work on (exact dissipation, ``forms.viscoelastic``)."""
        if self._sdev_expr is None:
            u, _ = self.split()
            F = deformation_gradient(u)
            C = F.T * F
            # (3.76) convolves DEV{Sbar} taken with the C of its own time
            Sdev = dev(self.fictitious_stress(), C)
            Cbar = ufl.det(F) ** (-2.0 / 3.0) * C
            both = ufl.as_vector(list(vector_from_plane_sym(Sdev))
                                 + list(vector_from_plane_sym(Cbar)))
            self._sdev_expr = jit.expression(both, self.rule.points)
        cells = self.history.cells
        vals = self._sdev_expr.eval(cells).reshape(cells.size * self.rule.points.shape[0], -1)
        n = vals.shape[1] // 2
        return np.ascontiguousarray(vals[:, :n]), np.ascontiguousarray(vals[:, n:])

    def set_temperature(self, T_cell) -> None:
        """Temperature per cell (K) for the WLF shift of the relaxation times."""
        if self.history is not None:
            self.history.set_temperature(T_cell)

    # --- dofs --------------------------------------------------------------------------------
    def displacement_dofs(self) -> np.ndarray:
        """(n_nodes, 2) full-space dofs of (u_x, u_z) per displacement node."""
        return self.umap.reshape(-1, 2)

    def dofs_where(self, predicate, component: int | None = None) -> np.ndarray:
        """Full-space displacement dofs of nodes whose coordinates satisfy `predicate(X)`."""
        nodes = np.nonzero(predicate(self.node_X))[0]
        d = self.displacement_dofs()[nodes]
        return d[:, component].copy() if component is not None else d.ravel()

    def boundary(self, tag: int) -> BoundaryNodes:
        """Nodes and outward-oriented segments of the facets carrying `tag`."""
        mesh = self.mesh
        tdim = mesh.topology.dim
        facets = self.facet_tags.indices[self.facet_tags.values == tag]
        if facets.size == 0:
            raise ValueError(f"no facets carry tag {tag}")
        mesh.topology.create_connectivity(tdim - 1, 0)
        mesh.topology.create_connectivity(tdim - 1, tdim)
        f2v = mesh.topology.connectivity(tdim - 1, 0)
        f2c = mesh.topology.connectivity(tdim - 1, tdim)
        verts = np.array([f2v.links(f) for f in facets])
        gnodes = _cpp.mesh.entities_to_geometry(getattr(mesh, "_mesh", mesh), 0,
                                                verts.ravel().astype(np.int32), False).ravel()
        vx = mesh.geometry.x[gnodes, :2]
        dist, node = cKDTree(self.node_X).query(vx)
        if dist.max() > 1e-10 * max(1.0, np.abs(self.node_X).max()):
            raise RuntimeError("boundary vertices do not coincide with displacement nodes")
        seg_nodes = node.reshape(-1, 2)
        # orient each segment so the owning cell lies on its left
        cells = np.array([f2c.links(f)[0] for f in facets])
        centroids = self._cell_centroids(cells)
        a, b = self.node_X[seg_nodes[:, 0]], self.node_X[seg_nodes[:, 1]]
        t = b - a
        n_right = np.column_stack([t[:, 1], -t[:, 0]])
        flip = np.einsum("ij,ij->i", n_right, 0.5 * (a + b) - centroids) < 0.0
        seg_nodes[flip] = seg_nodes[flip][:, ::-1]
        uniq, inv = np.unique(seg_nodes.ravel(), return_inverse=True)
        return BoundaryNodes(self.node_X[uniq].copy(), self.displacement_dofs()[uniq].copy(),
                             inv.reshape(-1, 2).astype(np.int32), uniq.astype(np.int32))

    def _cell_centroids(self, cells: np.ndarray) -> np.ndarray:
        return self.cell_centroids()[np.asarray(cells, dtype=np.int64)]

    def _cell_vertices(self) -> np.ndarray:
        """(n_cells, n_vertices, 2) reference coordinates of the local cells' geometry nodes, in
        the cell order of the history arrays and of ``set_temperature``."""
        x = self.mesh.geometry.x[:, :2]
        n = self.mesh.topology.index_map(self.mesh.topology.dim).size_local
        gd = self.mesh.geometry.dofmap  # one cell type: equal links per cell
        gdofs = gd.array.reshape(-1, int(gd.offsets[1] - gd.offsets[0]))
        return x[gdofs[:n]]

    def cell_centroids(self) -> np.ndarray:
        """(n_cells, 2) vertex means of the local cells in the reference configuration."""
        return self._cell_vertices().mean(axis=1)

    def cell_bounds(self, axis: int) -> np.ndarray:
        """(2, n_cells): the lowest and highest reference coordinate ``axis`` of each local cell."""
        c = self._cell_vertices()[:, :, axis]
        return np.stack([c.min(axis=1), c.max(axis=1)])

    def nodal_displacement(self) -> np.ndarray:
        """(n_nodes, 2) current displacement."""
        return self.w.x.array[self.umap].reshape(-1, 2)


class PressureJump:
    """The Q1P0s term  - (beta / G_s) sum_F h_F int_F [p][q] dS  as a constant matrix L on the
    pressure dofs of the mixed space: residual += L x, tangent += L (a Newton hook).

    Assembled once on the pressure space alone (``forms.bulk.pressure_jump_stabilisation``), so it
    couples the pressures of neighbouring cells only.  The same integral in the mixed form would
    couple every dof of two neighbouring cells: a much dearer Newton iteration, most of it LU fill
    (docs/performance.md; ``bench sliding --part iterations --element Q1P0s``)."""

    def __init__(self, W: fem.FunctionSpace, scale: float):
        Q, pmap = W.sub(1).collapse()
        pmap = np.asarray(pmap, dtype=np.int64)
        p, q = ufl.TrialFunction(Q), ufl.TestFunction(Q)
        c = fem.Constant(Q.mesh, float(scale))  # not a float in the form: one compiled form for all
        C = fem_petsc.assemble_matrix(jit.form(pressure_jump_stabilisation(p, q, Q.mesh, c)))
        C.assemble()
        indptr, cols, vals = C.getValuesCSR()
        rows = np.repeat(np.arange(indptr.size - 1), np.diff(indptr))
        n = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
        self.L = csr_matrix((vals, (pmap[rows], pmap[cols])), shape=(n, n))
        self.L.sort_indices()
        coo = self.L.tocoo()
        self.couplings = (coo.row.astype(np.int32), coo.col.astype(np.int32))
        self._indptr = self.L.indptr.astype(PETSc.IntType)
        self._indices = self.L.indices.astype(PETSc.IntType)

    def __call__(self, x: np.ndarray, A, b) -> None:
        if b is not None:
            b.array[:] += self.L @ x
        if A is not None:
            A.setValuesCSR(self._indptr, self._indices, self.L.data,
                           addv=PETSc.InsertMode.ADD_VALUES)
