"""The stabilised mixed element Q1P0s against Q1P0: spurious pressure modes of a confined block.

Closed-form facts checked (``rubberfriction verify pressure-modes``, module docstring there): in a
block confined on all sides the uniform pressure is a mode of every element, lambda_1 = 1 / K; Q1P0
has a second, spurious one (the checkerboard, lambda_2 = 1 / K on every uniform mesh) and its
lowest regular eigenvalue falls like h^2 (inf-sup constant -> 0); Q1P0s keeps lambda_2 G bounded
under refinement (measured 0.069, 0.074, 0.076 for n = 8, 16, 32 with beta = 0.01).  G = 2.5 MPa
here, so that a slip between lambda G and lambda / G shows.
"""

import pytest

from rubberfriction.driver.verification.pressure_modes import pressure_modes, pressure_spectrum

G, K = 2.5, 1e8


def test_stabilised_element_has_no_spurious_mode():
    r = pressure_modes(n=(8, 16), G=G, K=K)
    failed = [c for c in r["checks"] if not c["passed"]]
    assert not failed, failed
    lam = {n: pressure_spectrum("Q1P0s", n, G, K) for n in (8, 16)}
    assert lam[16][1] * G > 0.05 and lam[16][1] > 0.75 * lam[8][1], lam


def test_q1p0_has_the_checkerboard_mode_and_a_decaying_inf_sup_constant():
    lam = {n: pressure_spectrum("Q1P0", n, G, K) for n in (8, 16)}
    for n in lam:
        assert lam[n][0] * K == pytest.approx(1.0, rel=1e-3)  # uniform pressure
        assert lam[n][1] * K == pytest.approx(1.0, rel=1e-3)  # checkerboard: spurious
    assert lam[16][2] < 0.5 * lam[8][2], lam  # ~h^2: not inf-sup stable


def test_bad_stabilisation_is_refused():
    from rubberfriction.driver.fe.solid import SolidSettings

    with pytest.raises(ValueError, match="stabilisation"):
        SolidSettings(element="Q1P0s", stabilisation=0.0)
    with pytest.raises(ValueError, match="element"):
        SolidSettings(element="Q2P1")


def test_pressure_jump_hook_equals_the_mixed_form():
    """The constant hook (assembled on the pressure space, mapped to the mixed dofs) gives the
    residual and tangent of the same integral written in the mixed form (1e-12), at a random
    state."""
    import numpy as np
    import ufl
    from dolfinx import fem
    from dolfinx import mesh as dmesh
    from dolfinx.fem import petsc as fem_petsc
    from mpi4py import MPI

    from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
    from rubberfriction.forms.bulk import pressure_jump_stabilisation
    from rubberfriction.forms.compound import Compound, MooneyRivlin

    m = dmesh.create_rectangle(MPI.COMM_SELF, [np.array([0.0, 0.0]), np.array([2.0, 0.5])], [6, 5],
                               dmesh.CellType.quadrilateral)
    m.geometry.x[:, 1] = m.geometry.x[:, 1] ** 2 / 0.5  # graded rows: thin cells at the bottom
    tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
    mat = Compound(name="x", hyperelastic=MooneyRivlin.neo_hooke(0.7, 500.0), prony=None, wlf=None,
                   thermal=None)
    sp = SolidProblem(m, tags, mat, SolidSettings(element="Q1P0s", stabilisation=0.3))
    x = np.random.default_rng(1).normal(size=sp.w.x.array.size)
    sp.w.x.array[:] = x
    _, p = sp.split()
    _, q = sp.test_functions()
    form = pressure_jump_stabilisation(p, q, m, 0.3 / 0.7)
    b = fem_petsc.assemble_vector(fem.form(form)).array
    A = fem_petsc.assemble_matrix(fem.form(ufl.derivative(form, sp.w, ufl.TrialFunction(sp.W))))
    A.assemble()
    L = sp.pressure_jump.L
    assert np.abs(L @ x - b).max() < 1e-12 * np.abs(b).max()
    assert (np.abs(L.toarray() - A.convert("dense").getDenseArray()).max()
            < 1e-12 * np.abs(L.data).max())
