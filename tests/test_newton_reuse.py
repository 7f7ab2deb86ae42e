"""What the Newton solver reuses between iterations is only what does not change.

* New constraints (``set_constraints``: a prescribed dof becomes an unknown, as when a sliding
  run switches to force control) make a reduced system of another size and pattern: the same
  solver must give the solution a fresh problem and solver give, without being told.
* The tangent assembled without the residual (the solver's accepted iterate, whose residual the
  convergence test has just assembled) is the tangent of a full assembly, and the residual stays.
"""

from __future__ import annotations

import numpy as np
from petsc4py import PETSc

from fe_helpers import n_full, unit_square
from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import (ConstrainedNonlinearProblem, NewtonSettings,
                                             NewtonSolver)
from rubberfriction.driver.fe.solid import SolidProblem
from rubberfriction.forms.compound import Compound, MooneyRivlin

E, NU = 10.0, 0.45


def block() -> SolidProblem:
    mu, K = E / (2.0 * (1.0 + NU)), E / (3.0 * (1.0 - 2.0 * NU))
    mat = Compound(name="block", hyperelastic=MooneyRivlin.neo_hooke(mu, K), prony=None, wlf=None,
                   thermal=None)
    m, tags = unit_square(4)
    return SolidProblem(m, tags, mat)


def constraints(sp: SolidProblem, top_z: float | None) -> tuple[ConstraintSpec, np.ndarray]:
    """Bottom clamped, top held in x with its u_z tied; u_z prescribed unless top_z is None."""
    spec = ConstraintSpec(n_full(sp))
    spec.fix(sp.dofs_where(lambda X: np.isclose(X[:, 1], 0.0)), 0.0)
    spec.fix(sp.dofs_where(lambda X: np.isclose(X[:, 1], 1.0), 0), 0.0)
    top = sp.dofs_where(lambda X: np.isclose(X[:, 1], 1.0), 1)
    spec.tie(top)
    if top_z is not None:
        spec.fix(top[0], top_z)
    return spec, top


SETTINGS = NewtonSettings(rtol=1e-12, atol=1e-14)


def test_new_constraints_give_the_solution_of_a_fresh_solver():
    sp = block()
    spec, top = constraints(sp, -0.05)
    fext = np.zeros(n_full(sp))
    pb = ConstrainedNonlinearProblem(sp.residual, sp.jacobian(), sp.w, ConstraintMap(spec),
                                     external_force=fext)
    solver = NewtonSolver(pb, SETTINGS)
    assert solver.solve().converged
    reaction = float(pb.reaction(top).sum())  # F_int at the top: the compressive force, < 0
    assert reaction < 0.0
    x0 = sp.w.x.array.copy()
    # force control at 1.5 times that force: one more unknown (the top u_z)
    fext[top[0]] = 1.5 * reaction
    free, _ = constraints(sp, None)
    pb.set_constraints(ConstraintMap(free))
    res = solver.solve()  # no reset(): the solver sees the new reduced matrix itself
    assert res.converged and res.iterations >= 2, res.reason
    x_same = sp.w.x.array.copy()
    # a fresh problem and solver from the same start
    sp.w.x.array[:] = x0
    fresh = ConstrainedNonlinearProblem(sp.residual, sp.jacobian(), sp.w, ConstraintMap(free),
                                        external_force=fext)
    assert NewtonSolver(fresh, SETTINGS).solve().converged
    scale = np.abs(x_same).max()
    assert np.abs(x_same - sp.w.x.array).max() <= 1e-12 * scale
    # and the load went up: the top moved further down than the prescribed 0.05
    assert x_same[top].max() < -0.05 - 1e-3


def test_tangent_without_the_residual_is_the_full_tangent():
    sp = block()
    spec, top = constraints(sp, -0.02)
    spring = sp.dofs_where(lambda X: np.isclose(X[:, 0], 1.0), 0).astype(PETSc.IntType)

    def hook(x, A, b):  # a spring pulling the right edge (residual and tangent parts)
        if b is not None:
            b.setValues(spring, 3.0 * x[spring] + 0.01, addv=PETSc.InsertMode.ADD_VALUES)
        if A is not None:
            for d in spring:
                A.setValue(d, d, 3.0, addv=PETSc.InsertMode.ADD_VALUES)

    pb = ConstrainedNonlinearProblem(sp.residual, sp.jacobian(), sp.w, ConstraintMap(spec),
                                     hooks=[hook])
    pb.constraints.set_prescribed(sp.w.x.array)
    sp.w.x.array[:] += 1e-3 * np.sin(np.arange(sp.w.x.array.size))
    pb.constraints.set_prescribed(sp.w.x.array)
    pb.assemble()
    A_full, r_full = pb.Ar.copy(), pb.br.copy()
    pb.assemble(need_matrix=False)
    pb.A.zeroEntries()  # nothing of the old tangent may survive
    pb.assemble(need_vector=False)
    diff = pb.Ar.copy()
    diff.axpy(-1.0, A_full)
    assert diff.norm(PETSc.NormType.INFINITY) == 0.0
    assert np.array_equal(pb.br.array, r_full.array)
