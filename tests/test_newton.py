"""The Newton driver's stopping rules on one-unknown problems with known Newton sequences.

R(x) = sign(x) sqrt(|x|) makes Newton jump x -> -x forever (a 2-cycle with a constant residual, the
pattern of active-set cycling in penalty contact): the solver must stop on stagnation after
`stagnation` iterations instead of spending all `max_iterations`.  R(x) = x^3 - 8 converges
quadratically and must not be stopped.  A non-finite start is reported, not iterated.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from petsc4py import PETSc

from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver


class ScalarProblem:
    """The attributes of ConstrainedNonlinearProblem that NewtonSolver uses, for R(x), one dof."""

    def __init__(self, residual, derivative, x0: float):
        self.residual, self.derivative = residual, derivative
        self.w = SimpleNamespace(x=SimpleNamespace(array=np.array([x0])))
        self.constraints = SimpleNamespace(set_prescribed=lambda x: None)
        self.br, self.dur, self.du = (PETSc.Vec().createSeq(1) for _ in range(3))
        self.Ar = PETSc.Mat().createAIJ([1, 1], nnz=1)
        self.P = PETSc.Mat().createAIJ([1, 1], nnz=1)
        self.P.setValue(0, 0, 1.0)
        self.P.assemble()
        self.Ar.setValue(0, 0, 1.0)
        self.Ar.assemble()
        self.cpu = {}

    def assemble(self, need_matrix: bool = True, need_vector: bool = True) -> None:
        x = float(self.w.x.array[0])
        if need_vector:
            self.br.setValue(0, self.residual(x))
            self.br.assemble()
        if need_matrix:
            self.Ar.setValue(0, 0, self.derivative(x))
            self.Ar.assemble()


def cycling() -> ScalarProblem:
    return ScalarProblem(lambda x: math.copysign(math.sqrt(abs(x)), x),
                         lambda x: 0.5 / math.sqrt(abs(x)), 1.0)


def test_cycling_newton_stops_on_stagnation():
    res = NewtonSolver(cycling(), NewtonSettings(max_iterations=25, stagnation=8)).solve()
    assert not res.converged and res.iterations == 8
    assert res.reason.startswith("stagnated")
    assert np.allclose(res.residuals, 1.0)  # the 2-cycle x = +-1


def test_stagnation_rule_is_off_by_default():
    res = NewtonSolver(cycling(), NewtonSettings(max_iterations=25)).solve()  # default: off
    assert not res.converged and res.iterations == 25 and "no convergence" in res.reason


def test_quadratic_convergence_is_not_stopped():
    pb = ScalarProblem(lambda x: x**3 - 8.0, lambda x: 3.0 * x**2, 10.0)
    res = NewtonSolver(pb, NewtonSettings(rtol=1e-12, atol=1e-14, stagnation=3)).solve()
    assert res.converged and abs(pb.w.x.array[0] - 2.0) < 1e-12
    assert res.iterations > 3  # long enough for the rule to have had its chance


def test_non_finite_start_is_reported():
    pb = ScalarProblem(lambda x: x, lambda x: 1.0, math.nan)
    res = NewtonSolver(pb).solve()
    assert not res.converged and res.iterations == 0 and "not finite" in res.reason
