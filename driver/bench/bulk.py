"""Benchmark: cost of one Newton iteration of the viscoelastic block alone (no contact).

A square block (10 x 10 mm, default compound, Q1P0) is compressed by 1 % in one time step and
solved with Newton; assembly (bulk forms into PETSc, condensation P^T A P) and solve (MUMPS LU)
are timed separately per iteration, at three mesh sizes.  This is the baseline the contact
overhead is measured against (``rubberfriction bench contact``).

    rubberfriction bench bulk [--sizes 20 40 80] [--element Q1P0]
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import (
    ConstrainedNonlinearProblem,
    NewtonSettings,
    NewtonSolver,
)
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.forms.material_files import load_compound


def run_size(n: int, element: str, compound: str) -> dict:
    m = dmesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [10.0, 10.0]], [n, n], dmesh.CellType.quadrilateral)
    tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
    t0 = time.perf_counter()
    sp = SolidProblem(m, tags, load_compound(compound), SolidSettings(element=element))
    nfull = sp.W.dofmap.index_map.size_local * sp.W.dofmap.index_map_bs
    spec = ConstraintSpec(nfull)
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 1], 0.0)), 0.0)
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 1], 10.0), 1), -0.1)
    pb = ConstrainedNonlinearProblem(sp.residual, sp.jacobian(), sp.w, ConstraintMap(spec))
    t_setup = time.perf_counter() - t0
    sp.prepare_step(1e-3)
    res = NewtonSolver(pb, NewtonSettings(rtol=1e-10)).solve()
    t0 = time.perf_counter()
    sp.commit_step()
    t_commit = time.perf_counter() - t0
    it = max(res.iterations, 1)
    return {"cells": n * n, "dofs": nfull, "iterations": res.iterations, "converged": res.converged,
            "assemble_per_it": res.time_assemble / (it + 1), "solve_per_it": res.time_solve / it,
            "history_update": t_commit, "setup": t_setup,
            "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench bulk", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[20, 40, 80], help="elements per side")
    ap.add_argument("--element", default="Q1P0", choices=["Q1P0", "Q1"])
    ap.add_argument("--compound", default="tread_default")
    args = ap.parse_args(argv)
    print(f"viscoelastic block, {args.element}, compound {args.compound}: time per Newton iteration")
    print(f"{'cells':>8} {'dofs':>8} {'its':>4} {'assemble [ms]':>14} {'solve [ms]':>11} "
          f"{'history [ms]':>13} {'setup [s]':>10} {'peak RSS [MB]':>14}")
    for n in args.sizes:
        r = run_size(n, args.element, args.compound)
        print(f"{r['cells']:>8} {r['dofs']:>8} {r['iterations']:>4} {1e3 * r['assemble_per_it']:>14.2f} "
              f"{1e3 * r['solve_per_it']:>11.2f} {1e3 * r['history_update']:>13.2f} {r['setup']:>10.2f} "
              f"{r['peak_rss_MB']:>14.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
