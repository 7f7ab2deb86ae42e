"""Benchmark: cost of one Newton iteration of the viscoelastic block alone (no contact).

A square block (10 x 10 mm, default compound, Q1P0) is compressed by 1 % in one time step and
solved with Newton, at three mesh sizes.  Printed per Newton iteration, in CPU milliseconds of
this process (robust to other jobs on the machine): bulk forms (residual and tangent), the
condensation P^T A P, the linear solve (MUMPS numeric LU + triangular solves); per step: one
full bulk assembly (tangent + residual), the history update (``prepare_step`` + ``commit_step``,
eqs. 3.76-3.78) and their ratio.  ``conv`` says whether Newton converged (the 80 x 80 block of
tread_default does not in this one 1e-3 s step; its iterations still time the same operations).
This is the baseline the contact overhead is measured against
(``rubberfriction bench contact``).

``--compare-jit`` repeats every size with the forms compiled by dolfinx's default flags and
prints the ratio (what ``forms/jit.py``'s -fno-math-errno buys; the results are bitwise equal).

    rubberfriction bench bulk [--sizes 20 40 80] [--element Q1P0] [--compare-jit]
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from rubberfriction.driver.fe.constraints import ConstraintMap, ConstraintSpec
from rubberfriction.driver.fe.newton import NewtonSettings, NewtonSolver
from rubberfriction.driver.fe.solid import ELEMENTS, SolidProblem, SolidSettings
from rubberfriction.forms import jit
from rubberfriction.forms.material_files import load_compound

#: printed columns: key, header, format
COLUMNS = (("dofs", "dofs", "{:>8d}"), ("iterations", "its", "{:>4d}"),
           ("converged", "conv", "{!s:>5}"), ("bulk_ms", "bulk/it", "{:>9.2f}"),
           ("condense_ms", "PtAP/it", "{:>9.2f}"),
           ("linear_ms", "LU/it", "{:>9.2f}"), ("assembly_ms", "assembly", "{:>9.2f}"),
           ("prepare_ms", "prepare", "{:>9.2f}"), ("commit_ms", "commit", "{:>9.2f}"),
           ("history_per_assembly", "hist/asm", "{:>9.2f}"), ("setup_s", "setup [s]", "{:>10.2f}"),
           ("peak_rss_MB", "RSS [MB]", "{:>9.0f}"))


def run_size(n: int, element: str, compound: str) -> dict:
    """One compression step of an n x n block; CPU times of its parts (see the module doc)."""
    m = dmesh.create_rectangle(MPI.COMM_SELF, [[0.0, 0.0], [10.0, 10.0]], [n, n],
                               dmesh.CellType.quadrilateral)
    tags = dmesh.meshtags(m, 1, np.array([], np.int32), np.array([], np.int32))
    t0 = time.perf_counter()
    sp = SolidProblem(m, tags, load_compound(compound), SolidSettings(element=element))
    nfull = sp.W.dofmap.index_map.size_local * sp.W.dofmap.index_map_bs
    spec = ConstraintSpec(nfull)
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 1], 0.0)), 0.0)
    spec.fix(sp.dofs_where(lambda x: np.isclose(x[:, 1], 10.0), 1), -0.1)
    pb = sp.nonlinear_problem(ConstraintMap(spec))
    pb.assemble()  # compiles the forms: set-up, not iteration
    if sp.history is not None:  # compiles the history expressions (a step at rest: H stays 0)
        sp.prepare_step(1e-3)
        sp.commit_step()
    t_setup = time.perf_counter() - t0
    sp.w.x.array[:] = 0.0
    clock = time.process_time
    c0 = clock()
    sp.prepare_step(1e-3)
    t_prepare = clock() - c0
    res = NewtonSolver(pb, NewtonSettings(rtol=1e-10)).solve()
    c0 = clock()
    sp.commit_step()
    t_commit = clock() - c0
    bulk0 = pb.cpu["bulk"]
    pb.assemble()  # one full bulk assembly at the converged state
    t_assembly = pb.cpu["bulk"] - bulk0
    it = max(res.iterations, 1)
    return {"cells": n * n, "dofs": nfull, "iterations": res.iterations, "converged": res.converged,
            "bulk_ms": 1e3 * res.cpu["bulk"] / it, "condense_ms": 1e3 * res.cpu["condense"] / it,
            "linear_ms": 1e3 * res.cpu["linear"] / it, "assembly_ms": 1e3 * t_assembly,
            "prepare_ms": 1e3 * t_prepare, "commit_ms": 1e3 * t_commit,
            "history_per_assembly": (t_prepare + t_commit) / t_assembly, "setup_s": t_setup,
            "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}


def _row(r: dict) -> str:
    return f"{r['cells']:>8d} " + " ".join(fmt.format(r[k]) for k, _, fmt in COLUMNS)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rubberfriction bench bulk", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[20, 40, 80], help="elements per side")
    ap.add_argument("--element", default="Q1P0", choices=ELEMENTS)
    ap.add_argument("--compound", default="tread_default")
    ap.add_argument("--compare-jit", action="store_true",
                    help="also run with dolfinx's default compiler flags and print the ratios")
    args = ap.parse_args(argv)
    print(f"viscoelastic block, {args.element}, compound {args.compound}: CPU ms per Newton "
          f"iteration (/it) and per step of equal length; hist/asm = (prepare + commit) / one bulk "
          "assembly")
    print(f"{'cells':>8} " + " ".join(f"{h:>{len(fmt.format(0))}}" for _, h, fmt in COLUMNS))
    for n in args.sizes:
        r = run_size(n, args.element, args.compound)
        print(_row(r), flush=True)
        if args.compare_jit:
            with jit.compile_args(jit.DOLFINX_DEFAULT_ARGS):
                d = run_size(n, args.element, args.compound)
            print(_row(d) + "   <- dolfinx default flags: "
                  f"bulk/it x{d['bulk_ms'] / r['bulk_ms']:.2f}, "
                  f"assembly x{d['assembly_ms'] / r['assembly_ms']:.2f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
