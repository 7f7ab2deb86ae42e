"""Assembly straight into PETSc: same numbers as the local system, sparsity, Dirichlet dofs, errors.

* A matrix preallocated from ``sparsity_pairs()`` (with MAT_NEW_NONZERO_ALLOCATION_ERR on) takes
  the contact blocks without a malloc during a sliding sequence, and holds the same values as the
  COO local system; the vector gets the residual.
* A matrix without the contact couplings raises an error that names the sparsity pattern; with
  ``allow_new_nonzeros`` the assembly succeeds and reports the mallocs.
* Fixed (Dirichlet) dofs: their rows and columns are skipped.
* A communicator with more than one rank is refused.
* A and b are type-checked petsc4py objects: an integer handle, a Vec for A, a Mat for b or any
  other object raises TypeError naming the expected type; an object without a PETSc object
  raises ValueError.
"""

from __future__ import annotations

import numpy as np
import pytest
from petsc4py import PETSc

from rubberfriction.driver.fe.contact import (Contact, DeformableMaster, PenaltySettings,
                                              RigidMaster, SlaveSurface)


def interface(deformable=False, **kw):
    n = 12
    x = np.linspace(0.0, 1.0, n)
    slave = SlaveSurface(np.column_stack([x, 0.02 * np.sin(4 * x)]), np.arange(2 * n).reshape(n, 2),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    ndof = 2 * n
    if deformable:
        m = 15
        xm = np.linspace(1.4, -0.4, m)
        master = DeformableMaster(np.column_stack([xm, -0.01 + 0.02 * np.cos(3 * xm)]),
                                  ndof + np.arange(2 * m).reshape(m, 2),
                                  np.column_stack([np.arange(m - 1), np.arange(1, m)]))
        ndof += 2 * m
    else:
        xm = np.linspace(-2.0, 3.0, 300)
        master = RigidMaster(np.column_stack([xm, -0.01 + 0.02 * np.cos(3 * xm)]))
    c = Contact(slave, master, friction=0.3, penalty=PenaltySettings(c_N=100.0, c_T=50.0),
                search_radius=0.2, **kw)
    u = np.zeros(ndof)
    u[1:2 * n:2] = -0.02
    return c, u, ndof


def preallocated(ndof, rows, cols, extra_diagonal=True):
    nnz = np.zeros(ndof, dtype=PETSc.IntType)
    pairs = set(zip(rows.tolist(), cols.tolist()))
    if extra_diagonal:
        pairs |= {(i, i) for i in range(ndof)}
    rr = np.array(sorted(pairs), dtype=PETSc.IntType)
    np.add.at(nnz, rr[:, 0], 1)
    indptr = np.concatenate([[0], np.cumsum(nnz)]).astype(PETSc.IntType)
    A = PETSc.Mat().createAIJ((ndof, ndof), csr=(indptr, rr[:, 1], np.zeros(len(rr))),
                              comm=PETSc.COMM_SELF)
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
    A.assemble()
    return A


def dense(A):
    return A.convert("dense").getDenseArray().copy()


def coo(c, u, ndof, **kw):
    rr, rv, jr, jc, jv = c.local_system(u, **kw)
    R = np.zeros(ndof)
    np.add.at(R, rr, rv)
    J = np.zeros((ndof, ndof))
    np.add.at(J, (jr, jc), jv)
    return R, J


@pytest.mark.parametrize("deformable", [False, True])
def test_assembly_matches_local_system_and_pattern_survives_sliding(deformable):
    c, u, ndof = interface(deformable)
    rows, cols = c.sparsity_pairs(margin=1.0)
    A = preallocated(ndof, rows, cols)
    b = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    for k in range(12):  # slide the slave over the master with committed steps
        u[0:24:2] = 0.05 * k
        A.zeroEntries()
        b.set(0.0)
        rep = c.assemble(u, A, b, dt=0.1)
        A.assemble()
        assert rep["mallocs"] == 0
        R, J = coo(c, u, ndof, dt=0.1)
        np.testing.assert_allclose(b.getArray(), R, rtol=0, atol=1e-13 * max(1.0, np.abs(R).max()))
        np.testing.assert_allclose(dense(A), J, rtol=0, atol=1e-13 * np.abs(J).max())
        assert c.state()["n_active"] > 0
        c.commit()
    # dense blocks and pairs describe the same pattern
    blocks = c.coupling_blocks(margin=1.0)
    from_blocks = {(int(r), int(k)) for rows_b, cols_b in blocks for r in rows_b for k in cols_b}
    assert from_blocks == set(zip(rows.tolist(), cols.tolist()))


def test_missing_pattern_is_an_error_and_fallback_reports_mallocs():
    c, u, ndof = interface()
    A = preallocated(ndof, np.array([], PETSc.IntType), np.array([], PETSc.IntType))
    with pytest.raises(RuntimeError, match="sparsity"):
        c.assemble(u, A, None)
    c2, u, ndof = interface(allow_new_nonzeros=True)
    A = preallocated(ndof, np.array([], PETSc.IntType), np.array([], PETSc.IntType))
    rep = c2.assemble(u, A, None)
    A.assemble()
    assert rep["mallocs"] > 0
    _, J = coo(c2, u, ndof)
    np.testing.assert_allclose(dense(A), J, rtol=0, atol=1e-13 * np.abs(J).max())


def test_fixed_dofs_rows_and_columns_skipped():
    fixed = np.array([1, 6, 7, 10])
    c, u, ndof = interface(fixed_dofs=fixed)
    c_free, _, _ = interface()
    rows, cols = c_free.sparsity_pairs()
    A = preallocated(ndof, rows, cols)
    b = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    c.assemble(u, A, b)
    A.assemble()
    R, J = coo(c_free, u, ndof)
    J[fixed, :] = 0.0
    J[:, fixed] = 0.0
    R[fixed] = 0.0
    np.testing.assert_allclose(dense(A), J, rtol=0, atol=1e-13 * np.abs(J).max())
    np.testing.assert_allclose(b.getArray(), R, rtol=0, atol=1e-13 * np.abs(R).max())


def test_dof_outside_system_is_reported():
    c, u, ndof = interface()
    b = PETSc.Vec().createSeq(ndof - 5, comm=PETSc.COMM_SELF)
    with pytest.raises(RuntimeError, match="outside the global system"):
        c.assemble(u, None, b)


def test_handles_are_accepted():
    c, u, ndof = interface()
    b1 = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    b2 = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    c.assemble(u, None, b1)
    c.cpp.assemble(u, None, b2)
    np.testing.assert_array_equal(b1.getArray(), b2.getArray())


def test_petsc4py_objects_are_taken_as_they_are():
    c, u, ndof = interface()
    rows, cols = c.sparsity_pairs()
    A = preallocated(ndof, rows, cols)
    b = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    rep = c.cpp.assemble(u, A, b)
    A.assemble()
    assert rep["entries"] > 0
    R, J = coo(c, u, ndof)
    np.testing.assert_allclose(b.getArray(), R, rtol=0, atol=1e-13 * np.abs(R).max())
    np.testing.assert_allclose(dense(A), J, rtol=0, atol=1e-13 * np.abs(J).max())
    assert c.cpp.assemble(u, None, None)["entries"] == 0  # None skips both


class _HasHandle:
    def __init__(self, obj):
        self.handle = obj.handle


@pytest.mark.parametrize("via_driver", [False, True])
def test_wrong_petsc_types_raise_type_error(via_driver):
    c, u, ndof = interface()
    A = preallocated(ndof, *c.sparsity_pairs())
    b = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)
    assemble = c.assemble if via_driver else c.cpp.assemble
    wrong = [
        ((A.handle, None),
         r"expected a petsc4py\.PETSc\.Mat, got int \(integer handles are not accepted"),
        ((None, b.handle), r"expected a petsc4py\.PETSc\.Vec, got int"),
        ((b, None), r"expected a petsc4py\.PETSc\.Mat, got petsc4py\.PETSc\.Vec"),
        ((None, A), r"expected a petsc4py\.PETSc\.Vec, got petsc4py\.PETSc\.Mat"),
        ((_HasHandle(A), b), r"expected a petsc4py\.PETSc\.Mat, got _HasHandle"),
        ((A, "b"), r"expected a petsc4py\.PETSc\.Vec, got str"),
    ]
    b.set(1.0)
    for args, message in wrong:
        with pytest.raises(TypeError, match=message):
            assemble(u, *args)
    assert np.all(b.getArray() == 1.0)  # nothing was added
    with pytest.raises(ValueError, match="holds no PETSc object"):
        assemble(u, PETSc.Mat(), None)
    with pytest.raises(ValueError, match="holds no PETSc object"):
        assemble(u, None, PETSc.Vec())


class _TwoRanks:
    size = 2


def test_distributed_communicator_refused():
    n = 3
    slave = SlaveSurface(np.array([[0.0, 0], [1, 0], [2, 0]]), np.arange(6).reshape(3, 2),
                         np.array([[0, 1], [1, 2]]))
    with pytest.raises(ValueError, match="serially on its own communicator"):
        Contact(slave, RigidMaster(np.array([[0.0, 0], [3, 0]])), penalty=PenaltySettings(c_N=1.0),
                comm=_TwoRanks())
    assert n == 3


def test_an_evaluation_at_the_same_state_is_reused_and_only_then():
    """Newton assembles the residual, then the tangent, at the same iterate: the second call
    reuses the first evaluation (exactly: same inputs, same history).  A new displacement, time
    step or offset, or a commit (new history) evaluates again, and every answer equals that of a
    fresh interface evaluated once at the same state and history."""
    c, u, ndof = interface()
    rows, cols = c.sparsity_pairs(margin=1.0)
    A = preallocated(ndof, rows, cols)
    b = PETSc.Vec().createSeq(ndof, comm=PETSc.COMM_SELF)

    def counts():
        r = c.report()
        return r["evaluations"], r["reused_evaluations"]

    c.assemble(u, None, b, dt=0.1)
    c.assemble(u, A, None, dt=0.1)
    A.assemble()
    assert counts() == (2, 1)
    fresh, _, _ = interface()
    R, J = coo(fresh, u, ndof, dt=0.1)
    np.testing.assert_allclose(b.getArray(), R, rtol=0, atol=1e-13 * np.abs(R).max())
    np.testing.assert_allclose(dense(A), J, rtol=0, atol=1e-13 * np.abs(J).max())
    c.assemble(u, None, b, dt=0.2)  # another time step
    c.assemble(u, None, b, dt=0.2, offset=(0.01, 0.0))  # another master offset
    u2 = u.copy()
    u2[0:24:2] += 0.03
    c.assemble(u2, None, b, dt=0.2, offset=(0.01, 0.0))  # another state
    assert counts() == (5, 1)
    c.commit()  # new history: the same inputs are a new evaluation
    b.set(0.0)
    c.assemble(u2, None, b, dt=0.2, offset=(0.01, 0.0))
    assert counts() == (6, 1)
    fresh.assemble(u2, None, None, dt=0.2, offset=(0.01, 0.0))
    fresh.commit()
    Rc, _ = coo(fresh, u2, ndof, dt=0.2, offset=(0.01, 0.0))
    np.testing.assert_allclose(b.getArray(), Rc, rtol=0, atol=1e-13 * np.abs(Rc).max())
    # an evaluation that raises (a non-finite state) leaves nothing to reuse
    bad = u2.copy()
    bad[0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        c.assemble(bad, None, b, dt=0.2, offset=(0.01, 0.0))
    b.set(0.0)
    c.assemble(u2, None, b, dt=0.2, offset=(0.01, 0.0))
    assert counts() == (8, 1)
    np.testing.assert_allclose(b.getArray(), Rc, rtol=0, atol=1e-13 * np.abs(Rc).max())
