"""The finite-element model of one sliding attempt: the block, its constraints, the road contact.

The block (bottom at the highest asperity) with its solid (``driver.fe.solid``: the spec's element,
Prony history, temperatures), its top edge held in x and tied in z (first under a prescribed
displacement, then under the force F_ext), on a periodic cell the periodic edges
x_r - x_l = X_r - X_l (eq. 6.5), the contact with the rigid road, the viscous stabiliser
(driver.fe.stabilisation) and the Newton solvers.  Also the element check (det F), the top
reaction and the state a warm start takes over.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import ufl

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.fe.stabilisation import ViscousStabilisation
from rubberfriction.driver.fe.trust_region import TrustRegionSolver
from rubberfriction.driver.sliding.intrusion import road_intrusion
from rubberfriction.driver.sliding.spec import (
    InitialState,
    SlidingSpec,
    default_h_contact,
    mesh_digest,
    penalty_modulus,
)
from rubberfriction.driver.sliding.temperature import (
    MIN_ROW_FRACTION,
    cell_temperatures,
    mesh_levels,
)
from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient

#: trial steps (linear solves) a trust-region solve may take (driver.fe.trust_region)
TRUST_REGION_STEPS = 60


def geometry(s: SlidingSpec) -> tuple[float, float, float]:
    """(length, height, contact element length) of the block of spec ``s``."""
    L = s.block_length or s.period
    if not L > 0:
        raise ValueError("block_length: needs a positive value (or a periodic surface)")
    H = s.block_height or L
    hc = s.h_contact or default_h_contact(s)
    return L, H, hc


class SlidingModel:
    """The model of one attempt of spec ``spec``; :meth:`build` makes it (mesh, solid,
    constraints, contact of ``formulation``, solvers with the LU package ``linear_solver`` and
    its factorisations reused for ``factor_reuse`` GMRES iterations, ``driver.fe.newton``)."""

    def __init__(self, spec: SlidingSpec, mesh_factory, contact_factory, linear_solver: str,
                 factor_reuse: int = 0):
        self.spec = spec
        self.mesh_factory, self.contact_factory = mesh_factory, contact_factory
        self.linear_solver = linear_solver
        self.factor_reuse = factor_reuse  # NewtonSettings.factor_reuse
        self._detF = None  # det F at the quadrature points, compiled on first use
        self.iterate_det_F = math.nan  # its smallest value at the last checked iterate

    def build(self, contact_formulation: str) -> None:
        """Mesh, solid, constraints, contact, stabiliser and solvers, in this order."""
        s = self.spec
        L, H, hc = geometry(s)
        self.L, self.H, self.hc = L, H, hc
        z0 = float(np.max(s.surface_h))  # block bottom rests on the highest asperity
        options = {}  # only what the spec uses: custom factories need not know the rest
        if s.temperature_layers:  # layer bounds become mesh lines where rows stay thick enough
            options["levels"] = mesh_levels(s.temperature_layers, H, MIN_ROW_FRACTION * hc)
        if s.edge_radius > 0.0:
            options["edge_radius"] = s.edge_radius
        body = self.mesh_factory(L, H, hc, s.grading, z0, **options)
        self.mesh, self.facet_tags = body.mesh, body.facet_tags
        # Q1P0s: the jump stabilisation scaled by the shear modulus at the run's excitation
        # frequency (E* ~ 4 G, nearly incompressible), the modulus the cell's deformation sees
        G_s = 0.25 * penalty_modulus(s) if s.element == "Q1P0s" else 0.0
        self.sp = SolidProblem(self.mesh, self.facet_tags, s.compound,
                               SolidSettings(element=s.element, stabilisation_modulus=G_s))
        if s.temperature_layers:  # partitions over the height (thesis 8.3.3)
            background = s.temperature if s.temperature is not None else s.compound.wlf.T_ref
            lower, upper = self.sp.cell_bounds(axis=1) - z0  # depth spans of the cells
            self.sp.set_temperature(cell_temperatures(s.temperature_layers, background, lower,
                                                      upper))
        elif s.temperature is not None and getattr(s.compound, "wlf", None) is not None:
            self.sp.set_temperature(s.temperature)  # (without WLF data the relaxation has no T)
        nfull = self.sp.W.dofmap.index_map.size_local * self.sp.W.dofmap.index_map_bs
        X, d = self.sp.node_X, self.sp.displacement_dofs()
        tol = 1e-9 * max(L, H)
        self.top = np.nonzero(np.abs(X[:, 1] - (z0 + H)) < tol)[0]
        spec = ConstraintSpec(nfull)
        spec.fix(d[self.top, 0], 0.0)  # held in x: F_x is the reaction here
        spec.tie(d[self.top, 1])
        self.top_z_dof = int(d[self.top[0], 1])
        if s.period > 0:
            left = np.nonzero(np.abs(X[:, 0] - X[:, 0].min()) < tol)[0]
            right = np.nonzero(np.abs(X[:, 0] - X[:, 0].max()) < tol)[0]
            left, right = left[np.argsort(X[left, 1])], right[np.argsort(X[right, 1])]
            if left.size != right.size or np.abs(X[left, 1] - X[right, 1]).max() > tol:
                raise RuntimeError("periodic cell: left and right edge nodes do not match")
            spec.equal(d[left, 0], d[right, 0])  # x_r - x_l = X_r - X_l, eq. (6.5)
            spec.equal(d[left, 1], d[right, 1])
        spec.fix(self.top_z_dof, 0.0)  # displacement control until contact carries load
        self.cspec = spec
        self.cmap = ConstraintMap(spec)
        self.contact = self.contact_factory(self.sp, s, contact_formulation)
        self.fext = np.zeros(nfull)
        # inactive until a sub-step needs it; not on the top row: its reaction is the load
        self.stabiliser = ViscousStabilisation(np.delete(d, self.top, axis=0), nfull)
        self.stabilised_x = np.isin(self.stabiliser.dofs, d[:, 0])  # its x-dofs (net force)
        self.problem = self.sp.nonlinear_problem(self.cmap,
                                                 hooks=[self.contact.hook, self.stabiliser],
                                                 extra_couplings=self.contact.couplings(),
                                                 external_force=self.fext)
        self.force_scale = s.pressure * L
        # strict backtracking (no residual growth accepted): with friction a full step from trial
        # slip can jump over the narrow stick cone into reverse slip and back (2-cycle); without,
        # on steep rough samples, it also saves iterations (docs/performance.md)
        # stagnation: cycling active sets are cut back after 8 iterations instead of 25
        settings = NewtonSettings(rtol=s.newton_rtol, atol=1e-12 * self.force_scale,
                                  backtrack_growth=1.0, stagnation=8,
                                  linear_solver=self.linear_solver,
                                  factor_reuse=self.factor_reuse)
        self.trust = None  # the trust-region solver (newton = "trust-region" or "hybrid")
        if s.newton in ("trust-region", "hybrid"):  # every trial step counts: more per solve
            self.trust = TrustRegionSolver(
                self.problem, dataclasses.replace(settings, max_iterations=TRUST_REGION_STEPS),
                force_scale=self.force_scale, relax=self.sp.pressure_relaxation(),
                displacement_dofs=self.sp.umap)
        if s.newton == "trust-region":
            self.newton = self.trust
        else:
            self.newton = NewtonSolver(self.problem, settings, force_scale=self.force_scale)

    def switch_to_force_control(self) -> None:
        """The tied top u_z becomes an unknown loaded by F_ext (compression phase)."""
        self.cspec.fixed.pop(self.top_z_dof)
        self.cmap = ConstraintMap(self.cspec)
        self.problem.set_constraints(self.cmap)  # the solver refactorises the new P^T A P

    def inverted(self) -> bool:
        """Whether the iterate has an inverted or collapsed element: a quadrature point with
        det F <= spec.min_jacobian (the smallest value is kept for the reason text)."""
        if self._detF is None:
            u, _ = self.sp.split()
            self._detF = jit.expression(ufl.det(deformation_gradient(u)), self.sp.rule.points)
            ncell = self.mesh.topology.index_map(2).size_local
            self._cells = np.arange(ncell, dtype=np.int32)
        self.iterate_det_F = float(self._detF.eval(self._cells).min())
        return self.iterate_det_F <= self.spec.min_jacobian

    def bad_element_reason(self) -> str:
        """Why :meth:`inverted` refused the iterate."""
        j = self.iterate_det_F
        if not j > 0.0:
            return "element inversion (det F <= 0)"
        return f"element collapse (det F = {j:.3g} <= min_jacobian {self.spec.min_jacobian:g})"

    def road_intrusion(self) -> float:
        """How deep the road reaches into the rubber face now (``intrusion.road_intrusion``)."""
        slave, s = self.contact.slave, self.spec
        x = slave.X + self.sp.w.x.array[slave.dofs]
        ox, oz = self.contact.offset
        return road_intrusion(x[:, 0], x[:, 1], np.asarray(s.surface_x) + ox,
                              np.asarray(s.surface_h) + oz, s.period)

    def top_reaction(self) -> float:
        """Vertical force the tied top edge carries (internal force sum at its u_z dofs)."""
        d = self.sp.displacement_dofs()[self.top, 1]
        return float(self.problem.reaction(d).sum())

    def fits(self, state: InitialState | None) -> bool:
        """Whether ``state`` was computed on this mesh (a warm start can take it over)."""
        return bool(state is not None and state.mesh == mesh_digest(self.sp.node_X)
                    and state.w.shape == self.sp.w.x.array.shape)

    def restore(self, state: InitialState, F_target: float) -> None:
        """Take an earlier run's final state as the converged state now: displacements and
        pressures, the Prony histories at this run's temperatures, the contact's reference
        positions at the road's offset then with its stick history, force control at
        F_target."""
        self.switch_to_force_control()
        x = self.sp.w.x.array
        x[:] = state.w
        if self.sp.history is not None:
            self.sp.history.restore(state.history, state.sbar)
        self.problem.constraints.set_prescribed(x)
        gap = state.elastic_gap if state.elastic_gap.size else None
        self.contact.reset_history(x, (state.offset, 0.0), gap)
        self.fext[:] = 0.0
        self.fext[self.top_z_dof] = -F_target

    def final_state(self, offset: float, refine: int) -> InitialState:
        """The converged state now, for a later run to start from (spec.keep_state)."""
        h = self.sp.history
        empty = np.zeros(0)
        return InitialState("", self.sp.w.x.array.copy(),
                            h.H.copy() if h is not None else empty,
                            h.Sbar_n.copy() if h is not None else empty,
                            float(offset % self.L) if self.spec.period > 0 else float(offset),
                            mesh_digest(self.sp.node_X), self.contact.elastic_gap(), refine)
