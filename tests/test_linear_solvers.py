"""The Newton solver's LU packages (driver.fe.newton.LINEAR_SOLVERS).

PETSc's own LU does not pivot: the solver checks every solve's relative residual against
``LU_CHECK`` and turns to MUMPS (threshold pivoting) for good when a solve fails or misses it.

* a well-conditioned system: the pivot-free solve is the exact solution (1e-12), no fallback;
* a zero pivot in the natural order ([[0, 1], [1, 0]]): PETSc's LU stops, MUMPS solves it and
  the rest of that Newton solve; the next Newton solve tries PETSc's LU first again;
* a tiny pivot ([[1e-20, 1], [1, 1]]): the pivot-free LU returns a wrong answer without an
  error (growth 1e20); the residual check catches it and MUMPS solves it within 1e-12;
* an unknown package is refused naming the field;
* a reused factorisation (``factor_reuse``) preconditions GMRES on a changed matrix: a small
  change is solved to KRYLOV_RTOL without a new factorisation, a large one is refactorised and
  solved, a zero pivot still goes to MUMPS;
* the packages, orderings and the reuse agree on a real sliding run to 1e-9 of mu with the same
  Newton iterations (``bench sliding --part linear-solvers`` measures their speed).
"""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from petsc4py import PETSc

from rubberfriction.driver.fe.newton import (KRYLOV_RTOL, LINEAR_SOLVERS, LU_CHECK,
                                             NewtonSettings, NewtonSolver)
from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, sliding_contact
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.forms.material_files import load_compound


def linear_problem(A: np.ndarray, b: np.ndarray) -> SimpleNamespace:
    """The reduced system attributes NewtonSolver._linear_solve uses: Ar du = -br."""
    n = len(b)
    pb = SimpleNamespace(Ar=PETSc.Mat().createAIJ([n, n], nnz=n), br=PETSc.Vec().createSeq(n),
                         dur=PETSc.Vec().createSeq(n))
    set_matrix(pb, A, b)
    return pb


def set_matrix(pb, A: np.ndarray, b: np.ndarray) -> None:
    """Values of the reduced matrix (the same matrix: as Newton's next tangent) and the right
    side; the solver solves Ar dur = -br."""
    n = len(b)
    for i in range(n):
        for j in range(n):
            pb.Ar.setValue(i, j, A[i, j])
    pb.Ar.assemble()
    pb.br.array[:] = -b


def solve(solver: NewtonSolver, A: np.ndarray, b: np.ndarray) -> np.ndarray:
    solver.problem = linear_problem(A, b)
    solver._linear_solve()
    return solver.problem.dur.array.copy()


def test_a_well_conditioned_system_needs_no_fallback():
    rng = np.random.default_rng(1)
    A = rng.normal(size=(6, 6)) + 6.0 * np.eye(6)
    b = rng.normal(size=6)
    s = NewtonSolver(None, NewtonSettings(linear_solver="petsc"))
    np.testing.assert_allclose(solve(s, A, b), np.linalg.solve(A, b), rtol=0, atol=1e-12)
    assert s.lu_fallbacks == 0 and not s._use_backup
    assert s.ksp.getPC().getFactorSolverType() == "petsc"


def test_a_zero_pivot_falls_back_to_mumps_for_the_rest_of_the_newton_solve():
    A, b = np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([2.0, 3.0])
    s = NewtonSolver(None, NewtonSettings(linear_solver="petsc"))
    np.testing.assert_allclose(solve(s, A, b), [3.0, 2.0], rtol=0, atol=1e-12)
    assert s.lu_fallbacks == 1 and s._use_backup
    # the next system of the same Newton solve goes to MUMPS directly (no second failure)
    np.testing.assert_allclose(solve(s, A, 2.0 * b), [6.0, 4.0], rtol=0, atol=1e-12)
    assert s.lu_fallbacks == 1
    # a new Newton solve (solve() clears the flag) tries the pivot-free LU first again
    s._use_backup = False
    np.testing.assert_allclose(solve(s, np.eye(2), b), b, atol=1e-12)
    assert s.lu_fallbacks == 1 and not s._use_backup
    assert s.ksp.getPC().getFactorSolverType() == "petsc"
    np.testing.assert_allclose(solve(s, A, b), [3.0, 2.0], rtol=0, atol=1e-12)
    assert s.lu_fallbacks == 2


def test_a_tiny_pivot_is_caught_by_the_residual_check():
    A, b = np.array([[1e-20, 1.0], [1.0, 1.0]]), np.array([1.0, 2.0])
    exact = np.linalg.solve(A, b)
    # what the pivot-free LU alone gives: a wrong answer, no error
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("petsc")
    pb = linear_problem(A, b)
    ksp.setOperators(pb.Ar)
    x = pb.dur.duplicate()
    rhs = pb.br.copy()
    rhs.scale(-1.0)
    ksp.solve(rhs, x)
    r = np.linalg.norm(A @ x.array - b) / np.linalg.norm(b)
    assert r > LU_CHECK  # the check has something to catch
    s = NewtonSolver(None, NewtonSettings(linear_solver="petsc"))
    np.testing.assert_allclose(solve(s, A, b), exact, rtol=1e-12)
    assert s.lu_fallbacks == 1


def test_a_reused_factorisation_preconditions_gmres_until_it_is_too_stale():
    rng = np.random.default_rng(2)
    n = 12
    A0 = rng.normal(size=(n, n)) + 8.0 * np.eye(n)
    b = rng.normal(size=n)
    s = NewtonSolver(None, NewtonSettings(linear_solver="petsc", factor_reuse=10))
    np.testing.assert_allclose(solve(s, A0, b), np.linalg.solve(A0, b), rtol=1e-10)
    assert s.factorisations == 1
    # a change of rank 2 (two contact nodes): GMRES on the old factor, at most 3 iterations
    A1 = A0.copy()
    A1[3, 3] += 50.0
    A1[7, 7] += 20.0
    set_matrix(s.problem, A1, b)
    its = s.krylov_iterations
    s._linear_solve()
    x = s.problem.dur.array
    assert s.factorisations == 1 and 1 < s.krylov_iterations - its <= 3
    assert np.linalg.norm(A1 @ x - b) <= KRYLOV_RTOL * np.linalg.norm(b)
    # a new matrix altogether: more than 10 iterations needed, so a new factorisation
    A2 = rng.normal(size=(n, n)) + 8.0 * np.eye(n)
    set_matrix(s.problem, A2, b)
    s._linear_solve()
    assert s.factorisations == 2 and s.lu_fallbacks == 0
    np.testing.assert_allclose(s.problem.dur.array, np.linalg.solve(A2, b), rtol=1e-8)


def test_a_zero_pivot_with_reuse_falls_back_to_mumps():
    A, b = np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([2.0, 3.0])
    s = NewtonSolver(None, NewtonSettings(linear_solver="petsc", factor_reuse=10))
    np.testing.assert_allclose(solve(s, A, b), [3.0, 2.0], rtol=0, atol=1e-12)
    assert s.lu_fallbacks == 1 and s._use_backup and s._reuse is None


def test_an_unknown_package_is_refused():
    with pytest.raises(ValueError, match="linear_solver = 'umfpack'"):
        NewtonSolver(None, NewtonSettings(linear_solver="umfpack"))
    spec = SlidingSpec(surface_x=np.linspace(0, 1, 9)[:-1], surface_h=np.zeros(8), period=1.0,
                       pressure=0.1, velocity=10.0, compound=load_compound("tread_default"))
    with pytest.raises(ValueError, match="linear_solver = 'lu'"):
        SlidingRun(spec, block_mesh, sliding_contact, linear_solver="lu")
    for bad in (-1, 2.5):
        with pytest.raises(ValueError, match=f"factor_reuse: .* got {bad}"):
            SlidingRun(spec, block_mesh, sliding_contact, factor_reuse=bad)


def test_all_packages_give_the_same_sliding_run():
    """The full-contact viscoelastic sinusoid (1 mm, 2 um, 0.1 MPa, 10 mm/s), a quarter period:
    same Newton iterations, mu within 1e-9, whatever the package, the ordering and whether the
    factorisations are reused."""
    x = np.linspace(0.0, 1.0, 129)[:-1]
    spec = SlidingSpec(surface_x=x, surface_h=0.002 * np.cos(2.0 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=load_compound("tread_default"),
                       h_contact=1.0 / 16, slide_distance=0.25, step_length=0.5 / 16)
    res = {s: SlidingRun(dataclasses.replace(spec), block_mesh, sliding_contact,
                         linear_solver=s).run() for s in LINEAR_SOLVERS}
    res["fresh"] = SlidingRun(dataclasses.replace(spec), block_mesh, sliding_contact,
                              factor_reuse=0).run()
    assert all(r.ok for r in res.values())
    # the default reuses its factorisations: fewer than one per Newton iteration
    assert 0 < res["petsc"].stats["factorisations"] < res["petsc"].stats["newton_iterations"]
    assert res["fresh"].stats["factorisations"] == res["mumps"].stats["factorisations"] == 0
    for other in ("petsc-nd", "mumps", "fresh"):
        assert res["petsc"].stats["newton_iterations"] == res[other].stats["newton_iterations"]
        assert res["petsc"].mu_force == pytest.approx(res[other].mu_force, rel=1e-9)
    assert res["petsc"].stats["lu_fallbacks"] == res["petsc-nd"].stats["lu_fallbacks"] == 0
