"""Each contact run is serial on its own communicator: on 2 ranks, a contact created on
MPI.COMM_SELF works on every rank (farming), while a distributed PETSc vector/matrix or a 2-rank
communicator is refused with a clear message."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from conftest import missing

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = textwrap.dedent("""
    import sys
    sys.path.insert(0, {root!r})
    import numpy as np
    from mpi4py import MPI
    from petsc4py import PETSc
    from rubberfriction.driver.fe.contact import Contact, PenaltySettings, RigidMaster, SlaveSurface

    n = 6
    slave = SlaveSurface(np.column_stack([np.linspace(0, 1, n), np.zeros(n)]),
                         np.arange(2 * n).reshape(n, 2),
                         np.column_stack([np.arange(n - 1), np.arange(1, n)]))
    master = RigidMaster(np.array([[-1.0, 0.0], [2.0, 0.0]]))
    u = np.zeros(2 * n)
    u[1::2] = -0.01 * (1 + MPI.COMM_WORLD.rank)
    # farming: one serial run per rank
    c = Contact(slave, master, penalty=PenaltySettings(c_N=100.0), comm=MPI.COMM_SELF)
    b = PETSc.Vec().createSeq(2 * n, comm=PETSc.COMM_SELF)
    c.assemble(u, None, b)
    expected = 100.0 * 0.01 * (1 + MPI.COMM_WORLD.rank)
    assert abs(c.state()["Fz"] - expected) < 1e-12 * expected, c.state()["Fz"]
    # a distributed vector is refused by the C++ assembly
    bd = PETSc.Vec().createMPI(2 * n, comm=PETSc.COMM_WORLD)
    try:
        c.assemble(u, None, bd)
        print("NOT REFUSED (vector)")
    except RuntimeError as err:
        assert "serial" in str(err) and "2 ranks" in str(err), err
    try:
        Contact(slave, master, penalty=PenaltySettings(c_N=100.0), comm=MPI.COMM_WORLD)
        print("NOT REFUSED (communicator)")
    except ValueError as err:
        assert "own communicator" in str(err), err
    print("rank", MPI.COMM_WORLD.rank, "ok")
""")


@pytest.mark.mpi
def test_two_ranks_farming_and_refusal(tmp_path):
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        missing("mpirun not available (openmpi-bin, installed by scripts/setup.sh)")
    script = tmp_path / "run.py"
    script.write_text(SCRIPT.format(root=str(ROOT)))
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMP_NUM_THREADS="1")
    out = subprocess.run([mpirun, "-n", "2", "--oversubscribe", sys.executable, str(script)],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.count("ok") == 2 and "NOT REFUSED" not in out.stdout, out.stdout
