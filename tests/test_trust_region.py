"""Trust-region Newton on the incremental potential (driver.fe.trust_region).

* The premise: a viscoelastic step is conservative.  The bulk residual of a step (fixed Hstar,
  beta) is the derivative of Pi = int [(1 + beta) W_iso(Cbar) + Hstar : Cbar / 2 + W_vol] dV
  (UFL derivative against the residual form, to round-off); with the Q1P0 pressures relaxed to
  their cell optimum K <J - 1>_e the displacement residual is the gradient of
  Pi(u) = int [(1 + beta) W_iso + Hstar : Cbar / 2] dV + sum_e |e| K/2 <J - 1>_e^2 (central
  differences, 1e-6).
* The method on a closed form: the double well Pi = (x^2 - 1)^2 / 4 - f x from x = 0, where the
  tangent is negative.  Newton with its residual line search converges to the root of
  x^3 - x - f = 0 that is a maximum of Pi; the trust region to a minimum (x^3 - x - f = 0 to
  1e-10, 3 x^2 - 1 > 0).
* The kept failing input f280d52c of issue 14 (micro2, mortar, no stabilisation): line-search
  Newton stagnates at the first sliding step; the trust region slides on, alone or where Newton
  fails (hybrid).  With node-to-surface
  contact it slides too, into a state with the road's peaks through the rubber face (the
  road-intrusion check, driver.sliding.intrusion).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc

from fe_helpers import unit_square
from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.driver.fe.trust_region import TrustRegionSolver
from rubberfriction.driver.multiscale.specs import find_key, stored_spec
from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, sliding_contact
from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient, plane_sym_from_vector
from rubberfriction.forms.material_files import load_compound

FAILING = Path(__file__).parent / "data" / "failing_runs"


def _deformed_viscoelastic(element: str, seed: int = 3) -> SolidProblem:
    """tread_default on a 3 x 3 square, a random deformation and random step history."""
    mesh, tags = unit_square(3)
    sp = SolidProblem(mesh, tags, load_compound("tread_default"), SolidSettings(element=element))
    rng = np.random.default_rng(seed)
    sp.w.x.array[sp.umap] = 0.08 * rng.standard_normal(sp.umap.size)
    sp.history.Hstar.x.array[:] = 0.2 * rng.standard_normal(sp.history.Hstar.x.array.size)
    sp.history.beta.x.array[:] = 0.5 + rng.random(sp.history.beta.x.array.size)
    return sp


def _step_potential_density(sp: SolidProblem, volumetric: bool):
    """(1 + beta) W_iso(Cbar) + Hstar : Cbar / 2 (+ (J - 1)^2 / D1) as UFL."""
    u, _ = sp.split()
    F = deformation_gradient(u)
    J = ufl.det(F)
    Cbar = J ** (-2.0 / 3.0) * F.T * F
    I1 = ufl.tr(Cbar)
    I2 = 0.5 * (I1 * I1 - ufl.tr(Cbar * Cbar))
    hyp, h = sp.hyperelastic, sp.history
    W = (1.0 + h.beta) * (hyp.C10 * (I1 - 3.0) + hyp.C01 * (I2 - 3.0))
    W += 0.5 * ufl.inner(plane_sym_from_vector(h.Hstar), Cbar)
    if volumetric:
        W += (J - 1.0) ** 2 / hyp.D1
    return W


def test_viscoelastic_step_residual_is_the_gradient_of_its_potential():
    sp = _deformed_viscoelastic("Q1")
    Pi = _step_potential_density(sp, volumetric=True) * sp.dx
    grad = fem_petsc.assemble_vector(jit.form(ufl.derivative(Pi, sp.w, ufl.TestFunction(sp.W))))
    res = fem_petsc.assemble_vector(jit.form(sp.residual))
    scale = np.abs(res.array).max()
    assert scale > 0.1
    assert np.abs(grad.array - res.array).max() <= 1e-11 * scale


def test_relaxed_q1p0_residual_is_the_gradient_of_the_mean_dilatation_potential():
    sp = _deformed_viscoelastic("Q1P0")
    relax = sp.pressure_relaxation()
    x = sp.w.x.array
    K = sp.bulk_modulus
    Q, _ = sp.W.sub(1).collapse()
    q = ufl.TestFunction(Q)
    u, _ = sp.split()
    cell_dilatation = jit.form((ufl.det(deformation_gradient(u)) - 1.0) * q * sp.dx)
    volume = fem_petsc.assemble_vector(jit.form(1.0 * q * sp.dx)).array.copy()
    iso = jit.form(_step_potential_density(sp, volumetric=False) * sp.dx)

    def potential() -> float:
        g = fem_petsc.assemble_vector(cell_dilatation).array
        return fem.assemble_scalar(iso) + 0.5 * K * float(np.sum(g * g / volume))

    relax(x)
    res = fem_petsc.assemble_vector(jit.form(sp.residual)).array
    p_dofs = np.setdiff1d(np.arange(x.size), sp.umap)
    assert np.abs(res[p_dofs]).max() <= 1e-12 * np.abs(res[sp.umap]).max()  # constraint holds
    rng = np.random.default_rng(7)
    v = np.zeros_like(x)
    v[sp.umap] = rng.standard_normal(sp.umap.size)
    x0, eps = x.copy(), 1e-6
    x[:] = x0 + eps * v
    plus = potential()
    x[:] = x0 - eps * v
    minus = potential()
    directional = (plus - minus) / (2.0 * eps)
    assert directional == pytest.approx(float(res @ v), rel=1e-6)
    with pytest.raises(ValueError, match="Q1P0s"):
        SolidProblem(*unit_square(2), load_compound("tread_default"),
                     SolidSettings(element="Q1P0s")).pressure_relaxation()


class DoubleWell:
    """Pi(x) = sum_i (x_i^2 - 1)^2 / 4 - f x_i + c (x_0 - x_1)^2 / 2 as a NonlinearProblem."""

    def __init__(self, f: float, c: float = 0.2, x0: float = 0.0):
        self.f, self.c, n = f, c, 2
        self.w = type("W", (), {})()
        self.w.x = type("X", (), {})()
        self.w.x.array = np.full(n, x0)
        self.constraints = type("C", (), {"set_prescribed": staticmethod(lambda x: None)})()
        self.P = PETSc.Mat().createDense([n, n])
        self.P.setUp()
        for i in range(n):
            self.P.setValue(i, i, 1.0)
        self.P.assemble()
        self.Ar = PETSc.Mat().createAIJ([n, n], nnz=n)
        for i in range(n):
            for j in range(n):
                self.Ar.setValue(i, j, 0.0)
        self.Ar.assemble()
        self.br, self.dur = self.P.createVecRight(), self.P.createVecRight()
        self.du = self.P.createVecLeft()
        self.cpu = {"bulk": 0.0, "hooks": 0.0, "condense": 0.0, "linear": 0.0}

    def residual(self, x):
        r = x**3 - x - self.f
        r[0] += self.c * (x[0] - x[1])
        r[1] -= self.c * (x[0] - x[1])
        return r

    def assemble(self, need_matrix: bool = True, need_vector: bool = True) -> None:
        x = self.w.x.array
        if need_vector:
            self.br.array[:] = self.residual(x)
        if need_matrix:
            K = np.diag(3.0 * x**2 - 1.0) + self.c * np.array([[1.0, -1.0], [-1.0, 1.0]])
            for i in range(2):
                for j in range(2):
                    self.Ar.setValue(i, j, K[i, j])
            self.Ar.assemble()


def test_trust_region_finds_the_minimum_where_newton_finds_the_maximum():
    f = 0.1
    settings = NewtonSettings(rtol=1e-13, atol=1e-13, max_iterations=60)
    newton = DoubleWell(f)
    res = NewtonSolver(newton, settings).solve()
    assert res.converged
    x = newton.w.x.array
    assert np.all(3.0 * x**2 - 1.0 < 0.0)  # a maximum of every well
    tr = DoubleWell(f)
    res = TrustRegionSolver(tr, settings).solve()
    assert res.converged, res.reason
    x = tr.w.x.array
    assert np.abs(x**3 - x - f).max() < 1e-10  # symmetric: x_0 = x_1, the coupling is idle
    assert np.all(3.0 * x**2 - 1.0 > 0.0)  # a minimum (of either well)


def test_failing_micro2_input_slides_with_the_trust_region():
    stored = stored_spec(Store(FAILING).load(find_key(Store(FAILING), "f280d52c")),
                         compound_dir=FAILING / "compounds")
    assert stored.stabilisation == 0.0 and stored.contact == "mortar"
    short = dataclasses.replace(stored, slide_distance=12 * stored.step_length, converge_tol=0.0,
                                steady_state=False)
    results = {}
    for newton in ("line-search", "trust-region", "hybrid"):
        run = SlidingRun(dataclasses.replace(short, newton=newton), block_mesh, sliding_contact)
        first = run.attempts()[0]
        run.attempts = lambda first=first: [first]
        results[newton] = run.run()
    assert not results["line-search"].ok and "sliding" in results["line-search"].reason
    tr = results["trust-region"]
    assert tr.ok, tr.reason
    assert tr.stats["stabilised_steps"] == 0 and tr.stats["rejected_steps"] > 0
    hybrid = results["hybrid"]  # Newton first, the trust region where it stagnates
    assert hybrid.ok, hybrid.reason
    assert hybrid.stats["stabilised_steps"] == 0 and hybrid.stats["trust_region_solves"] >= 1
    # node-to-surface is conservative, so the trust region converges there too, but the road's
    # peaks (narrower than the 0.5 um elements) cut through the face between the nodes: the
    # deepest road vertex inside the rubber (measured 21.6 elements deep; mortar 1.4)
    run = SlidingRun(dataclasses.replace(short, newton="trust-region", contact="surface"),
                     block_mesh, sliding_contact)
    first = run.attempts()[0]
    run.attempts = lambda: [first]
    surface = run.run()
    assert surface.ok, surface.reason
    assert tr.road_intrusion < 2.0 < 10.0 < surface.road_intrusion
    assert surface.contact_fraction > 1.0  # the face stretched over the road, peaks inside it
