"""Newton's method for the bulk forms plus C++ contributions (contact), on constrained dofs.

The system is assembled in the full space of a dolfinx function (bulk forms by dolfinx, then any
number of *hooks* that add into the same PETSc matrix and vector, e.g. the C++ mortar contact),
condensed with the constraint prolongation P (``constraints.py``) to  P^T A P du_r = -P^T R,
and solved with a direct LU factorisation: PETSc's own (minimum degree ordering, no pivoting),
each solve checked by its residual, or MUMPS (threshold pivoting), which solves the system a
pivot-free solve fails on (or misses ``LU_CHECK``) and the rest of that Newton solve.  On the
sliding runs' small reduced systems PETSc's LU is the faster, MUMPS's analysis and scaling
costing more than the small fronts (docs/performance.md; ``bench sliding --part
linear-solvers``).  Convention: R(u) = F_int - F_ext, so hooks add
dPi/du into the vector and its derivative into the matrix.

The matrix sparsity is the bulk form's pattern plus every coupling a hook declares up front
(``extra_couplings``), so hooks never hit a missing entry (PETSc would otherwise drop or error).

What is reused, and why the pattern is fixed: A keeps its pattern for the life of the problem (new
nonzeros are an error), so P^T A P keeps its pattern while the constraints stay (``MatPtAP`` with
MAT_REUSE_MATRIX: its symbolic product is computed once per constraint set), and the LU keeps
its symbolic factorisation (the ordering and fill; for MUMPS its analysis: ordering, scaling,
tree) as long as it is handed the same reduced matrix with an unchanged nonzero state; only the
numeric factorisation is redone.  With ``NewtonSettings.factor_reuse`` (the sliding runs') even
that is kept across iterations and steps: the numeric factor of an earlier tangent preconditions
GMRES on the current one, which gives the exact Newton direction (to ``KRYLOV_RTOL``, far
below the bound the pivot-free LU is checked against) where a reused factor alone would be a
modified Newton method with other iterates; the tangent is refactorised when GMRES needs more
than ``factor_reuse`` iterations.
:meth:`ConstrainedNonlinearProblem.set_constraints` makes a new reduced matrix; the solver notices
the new object and starts a new factorisation (symbolic included) by itself.

Per iteration the residual is assembled once: the tangent at an accepted iterate is assembled
without the vector, which the convergence test has just assembled at the same state.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
from dolfinx import cpp as _cpp
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc

from rubberfriction.driver.fe.constraints import ConstraintMap
from rubberfriction.forms import jit


class NonlinearProblem(Protocol):
    """What :class:`NewtonSolver` uses of a problem (:class:`ConstrainedNonlinearProblem`)."""

    w: fem.Function  # the unknowns (full space): w.x.array
    constraints: ConstraintMap  # set_prescribed(x)
    P: PETSc.Mat  # prolongation u_full = P u_red
    Ar: PETSc.Mat | None  # reduced tangent P^T A P
    br: PETSc.Vec  # reduced residual P^T b
    dur: PETSc.Vec  # reduced Newton step
    du: PETSc.Vec  # full-space Newton step
    cpu: dict[str, float]  # cumulative CPU seconds of the assembly parts (CPU_PARTS)

    def assemble(self, need_matrix: bool = True, need_vector: bool = True) -> None: ...


class Hook(Protocol):
    """A contribution assembled into the full-space system at every Newton iteration; A or b is
    None when only the other one is needed."""

    def __call__(self, x: np.ndarray, A: PETSc.Mat | None, b: PETSc.Vec | None) -> None: ...


@dataclass
class NewtonSettings:
    max_iterations: int = 25
    rtol: float = 1e-9  # on the reduced residual norm, relative to the reference force
    atol: float = 1e-10  # absolute floor on the reduced residual norm (N/mm)
    # backtrack when a full step blows the residual up (inversion, overshoot)
    line_search: bool = True
    max_backtracks: int = 5
    backtrack_growth: float = 10.0  # ... i.e. grows it by more than this factor (active-set changes
    # in penalty contact make moderate growth normal; halving those steps only slows Newton down)
    stol: float = 1e-12  # converged when ||du|| <= stol ||u|| (residual stalled at round-off)
    divergence_factor: float = 1e6  # stop if the residual grows by this factor
    # stop early when the last `stagnation` iterations did not halve the best residual before
    # them (active-set cycling in penalty contact); for callers that can cut the step back, which
    # is then cheaper than the remaining iterations (sliding runs use 8); 0 = never
    stagnation: int = 0
    linear_solver: str = "petsc"  # see LINEAR_SOLVERS
    # GMRES iterations a reused factorisation may take as the preconditioner of the current
    # tangent before it is refactorised (exact Newton directions to KRYLOV_RTOL either way);
    # 0: a new numeric factorisation at every iteration.  Pivot-free packages only ("mumps"
    # factorises at every iteration whatever this says).
    factor_reuse: int = 0


@dataclass
class NewtonResult:
    converged: bool
    iterations: int
    residuals: list[float] = field(default_factory=list)
    reason: str = ""
    time_assemble: float = 0.0
    time_solve: float = 0.0
    backtracks: int = 0
    # CPU seconds of this process (robust to other jobs on the machine) by part of the solve:
    # bulk forms, hooks (contact), condensation P^T A P and P^T b (with PETSc's assembly calls),
    # linear solve (numeric factorisation + triangular solves); see ``CPU_PARTS``
    cpu: dict[str, float] = field(default_factory=lambda: dict.fromkeys(CPU_PARTS, 0.0))


#: the parts of NewtonResult.cpu
CPU_PARTS = ("bulk", "hooks", "condense", "linear")

#: LU packages of NewtonSettings.linear_solver -> (PETSc solver type, fill-reducing ordering):
#: "petsc" (PETSc's LU without pivoting, approximate minimum degree ordering, every solve
#: checked, MUMPS after a failure for the rest of that Newton solve), "petsc-nd" (the same with
#: nested dissection, the former default), "mumps" (MUMPS with threshold pivoting and its own
#: ordering, unchecked).  Minimum
#: degree fills less than nested dissection on the sliding runs' reduced systems (a tied top row
#: and periodic columns): a faster numeric factorisation on every scale of the default road
#: (docs/performance.md; ``rubberfriction bench sliding --part linear-solvers``)
LINEAR_SOLVERS = {"petsc": ("petsc", "amd"), "petsc-nd": ("petsc", "nd"),
                  "mumps": ("mumps", None)}
#: relative residual ||A x - b|| / ||b|| a pivot-free solve must reach, else the solver turns to
#: MUMPS (an inexact Newton direction this close converges like the exact one down to ~1e-12)
LU_CHECK = 1e-6


#: relative true residual of a Krylov solve preconditioned by a reused factorisation: far
#: below the pivot-free LU's check, as near the LU's own solves as costs little (at 1e-6 a
#: micro1 friction run near a contact jump took another path than with the LU alone,
#: docs/performance.md "Factorisations reused")
KRYLOV_RTOL = 1e-10
#: ... and below this part of Newton's absolute tolerance atol + rtol force_scale
KRYLOV_MARGIN = 1e-4
#: GMRES iterations a sliding run's reused factorisation may take before it is refactorised
#: (``NewtonSettings.factor_reuse``): a numeric factorisation costs tens of preconditioned
#: GMRES iterations on the sliding runs' systems, and a factor lasts a few steps
#: (docs/performance.md, "Factorisations reused")
FACTOR_REUSE = 15


def _krylov_solver(package: str, max_iterations: int) -> PETSc.KSP:
    """GMRES, right-preconditioned (its norm is the true residual's) by the LU factorisation of
    its preconditioning matrix, at most ``max_iterations`` without restart."""
    ksp = _lu_solver(package)
    ksp.setType("gmres")
    ksp.setPCSide(PETSc.PC.Side.RIGHT)
    ksp.setNormType(PETSc.KSP.NormType.UNPRECONDITIONED)
    ksp.setTolerances(rtol=KRYLOV_RTOL, atol=0.0, max_it=max_iterations)
    ksp.setGMRESRestart(max_iterations)
    return ksp


def _lu_solver(package: str) -> PETSc.KSP:
    """A direct solver (KSP preonly + LU) with the package and ordering of LINEAR_SOLVERS."""
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    solver_type, ordering = LINEAR_SOLVERS[package]
    pc.setFactorSolverType(solver_type)
    if ordering is not None:
        pc.setFactorOrdering(ordering)
    return ksp


class ConstrainedNonlinearProblem:
    """Residual/Jacobian of one nonlinear system on a dolfinx Function with linear constraints.

    Parameters
    ----------
    residual, jacobian: UFL forms (residual linear in the test function; jacobian its derivative).
    w: the unknown dolfinx Function (full space, serial).
    constraints: ConstraintMap (Dirichlet, periodic, ties).
    hooks: extra contributions (contact), called as hook(x, A, b).
    extra_couplings: list of (rows, cols) arrays of dof pairs every hook may write into.
    external_force: optional full-space array F_ext subtracted from the residual.
    """

    def __init__(self, residual, jacobian, w: fem.Function, constraints: ConstraintMap,
                 hooks: list[Hook] | None = None, extra_couplings=None, external_force=None):
        self.w = w
        self.F_form = jit.form(residual)
        self.J_form = jit.form(jacobian)
        self.hooks = list(hooks or [])
        self.external_force = external_force
        self.cpu = dict.fromkeys(CPU_PARTS, 0.0)  # cumulative CPU seconds (NewtonResult.cpu)
        self.A = self._create_matrix(extra_couplings or [])
        self.b = fem_petsc.create_vector(self.F_form)
        self.set_constraints(constraints)
        self.du = self.P.createVecLeft()

    def set_constraints(self, constraints: ConstraintMap) -> None:
        """Use new constraints (e.g. a prescribed dof becomes free); the reduced system is
        rebuilt."""
        self.constraints = constraints
        self.P = constraints.P
        self.Ar: PETSc.Mat | None = None
        self.br = self.P.createVecRight()
        self.dur = self.P.createVecRight()

    def _create_matrix(self, couplings) -> PETSc.Mat:
        """Bulk sparsity plus every (row, col) pair in `couplings` (list of (rows, cols) arrays)."""
        sp = fem.create_sparsity_pattern(self.J_form)
        bs = self.w.function_space.dofmap.index_map_bs
        for rows, cols in couplings:
            r = np.asarray(rows, dtype=np.int64) // bs
            c = np.asarray(cols, dtype=np.int64) // bs
            if r.size == 0:
                continue
            order = np.lexsort((c, r))
            r, c = r[order], c[order]
            starts = np.nonzero(np.diff(np.concatenate([[-1], r])))[0]
            for row, cs in zip(r[starts], np.split(c, starts[1:])):
                sp.insert(np.array([row], dtype=np.int32), np.unique(cs).astype(np.int32))
        sp.assemble()
        A = _cpp.la.petsc.create_matrix(self.w.function_space.mesh.comm, sp)
        A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
        # PETSc squeezes never-written preallocated slots out at the first final assembly (and
        # dolfinx does not check MatSetValuesLocal errors): write the bulk pattern and explicit
        # zeros for every declared coupling before it, so no entry is ever dropped later
        fem_petsc.assemble_matrix(A, self.J_form)
        for rows, cols in couplings:
            r = np.asarray(rows, dtype=PETSc.IntType)
            c = np.asarray(cols, dtype=PETSc.IntType)
            if r.size == 0:
                continue
            order = np.lexsort((c, r))
            r, c = r[order], c[order]
            counts = np.bincount(r, minlength=A.getSize()[0]).astype(PETSc.IntType)
            indptr = np.concatenate([[0], np.cumsum(counts)]).astype(PETSc.IntType)
            A.setValuesCSR(indptr, c, np.zeros(c.size), addv=PETSc.InsertMode.ADD_VALUES)
        A.assemble()
        A.zeroEntries()
        return A

    def assemble(self, need_matrix: bool = True, need_vector: bool = True) -> None:
        """Assemble R and/or A in the full space, then the reduced system.

        ``need_vector=False`` leaves b and br as they are: for the tangent at the state whose
        residual was the last one assembled (the solver's accepted iterate).  A non-finite
        iterate (a diverged Newton step) gets a NaN residual without calling the forms or hooks:
        the solver's finiteness checks then reject it (line search, divergence).
        """
        x = self.w.x.array
        if not np.isfinite(x).all():
            self.b.set(np.nan)
            self.br.set(np.nan)
            return
        cpu, clock = self.cpu, time.process_time
        t0 = clock()
        A = self.A if need_matrix else None
        b = self.b if need_vector else None
        if b is not None:
            with b.localForm() as bl:
                bl.set(0.0)
            fem_petsc.assemble_vector(b, self.F_form)
        if A is not None:
            A.zeroEntries()
            fem_petsc.assemble_matrix(A, self.J_form)
        t1 = clock()
        for hook in self.hooks:
            hook(x, A, b)
        t2 = clock()
        if A is not None:
            A.assemble()
        if b is not None:
            b.assemble()
            if self.external_force is not None:
                b.array[:] -= self.external_force
            self.P.multTranspose(b, self.br)
        if A is not None:
            if self.Ar is None:
                self.Ar = A.PtAP(self.P)
            else:
                A.PtAP(self.P, self.Ar)
        cpu["bulk"] += t1 - t0
        cpu["hooks"] += t2 - t1
        cpu["condense"] += clock() - t2

    def reaction(self, dofs) -> np.ndarray:
        """Full-space residual at `dofs` after the last assembly (reaction forces at fixed dofs)."""
        return self.b.array[np.asarray(dofs)].copy()


class NewtonSolver:
    """Plain Newton iteration with LU on the reduced system; reports instead of raising."""

    def __init__(self, problem: NonlinearProblem, settings: NewtonSettings | None = None,
                 force_scale: float = 1.0,
                 on_iteration: Callable[[int, float], None] | None = None):
        self.problem = problem
        self.settings = settings or NewtonSettings()
        self.force_scale = float(force_scale)
        self.on_iteration = on_iteration
        self.cpu_linear = 0.0  # CPU seconds of all linear solves of this solver
        if self.settings.linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"linear_solver = {self.settings.linear_solver!r}: expected one of "
                             f"{tuple(LINEAR_SOLVERS)}")
        self.lu_fallbacks = 0  # pivot-free solves that failed (MUMPS solved those systems)
        self.factorisations = 0  # numeric factorisations (with factor_reuse)
        self.krylov_iterations = 0  # GMRES iterations (with factor_reuse)
        self._use_backup = False  # MUMPS for the rest of this Newton solve
        self.reset()

    def reset(self) -> None:
        """New linear solver.  Needed only after a failed factorisation: a new reduced matrix
        (``set_constraints``) gets a new factorisation by itself (:meth:`_linear_solve`)."""
        self.ksp = _lu_solver(self.settings.linear_solver)
        self._reuse: PETSc.KSP | None = None  # GMRES on a reused factorisation (factor_reuse)
        self._frozen: PETSc.Mat | None = None  # the reduced matrix that factorisation is of
        self._backup: PETSc.KSP | None = None  # MUMPS, after a failed pivot-free solve
        self._operator: PETSc.Mat | None = None  # the reduced matrix this factorisation is for
        self._check: PETSc.Vec | None = None

    def _linear_solve(self) -> None:
        """dur = -Ar^-1 br.  A new reduced matrix (new constraints, new pattern) gets a new LU
        (symbolic factorisation included); the same one only a numeric refactorisation.  A
        pivot-free solve that fails or misses LU_CHECK is done again with MUMPS, which then
        solves the rest of this Newton solve (the failures come in runs, the iterates of one hard
        sub-step); the next solve starts with the pivot-free LU again.  Staying with MUMPS for
        good after the first failure sent much of a run's solves to the dearer MUMPS
        (docs/performance.md)."""
        pb = self.problem
        if pb.Ar is not self._operator:
            if self._operator is not None:
                self.reset()
            self._bind()
        pb.br.scale(-1.0)
        if self.settings.linear_solver == "mumps":
            self.ksp.solve(pb.br, pb.dur)
            return
        if self._use_backup:
            self._backup_solver().solve(pb.br, pb.dur)
            return
        try:
            if self.settings.factor_reuse > 0:
                ok = self._reused_solve()
            else:
                self.ksp.solve(pb.br, pb.dur)
                ok = self.ksp.getConvergedReason() >= 0 and self._solve_error() <= LU_CHECK
        except PETSc.Error:  # a zero pivot
            ok = False
        if ok:
            return
        self.lu_fallbacks += 1
        self._use_backup = True
        # a failed factorisation leaves its PC unusable: new ones for the next solve
        self._reuse = self._frozen = None
        self.ksp = _lu_solver(self.settings.linear_solver)
        self.ksp.setOperators(pb.Ar)
        self._backup_solver().solve(pb.br, pb.dur)

    def _reused_solve(self) -> bool:
        """dur = Ar^-1 br by GMRES preconditioned with the last factorisation; where it does not
        converge within ``factor_reuse`` iterations, Ar is copied and factorised and GMRES
        solves again (one or two iterations with an exact factor).  Converged: the true
        residual below KRYLOV_RTOL of br and below KRYLOV_MARGIN of Newton's own tolerance, so
        the iterates are Newton's (an iteration near convergence is not lost to the linear
        solve), or with a fresh factor below LU_CHECK (as the pivot-free LU alone).  Returns
        whether it converged."""
        pb, st = self.problem, self.settings
        floor = KRYLOV_MARGIN * (st.atol + st.rtol * self.force_scale)
        rtol = min(KRYLOV_RTOL, floor / max(pb.br.norm(), 1e-300))
        fresh = self._reuse is None
        if fresh:
            self._frozen = pb.Ar.copy()
            self._reuse = _krylov_solver(st.linear_solver, st.factor_reuse)
            self._reuse.setOperators(pb.Ar, self._frozen)
        self._reuse.setTolerances(rtol=rtol)
        if not fresh:
            self._reuse.solve(pb.br, pb.dur)
            self.krylov_iterations += self._reuse.getIterationNumber()
            if self._reuse.getConvergedReason() > 0:
                return True
            pb.Ar.copy(self._frozen, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
        self.factorisations += 1
        self._reuse.solve(pb.br, pb.dur)
        self.krylov_iterations += self._reuse.getIterationNumber()
        # with a fresh factor, what a pivot-free LU alone had to reach
        return self._reuse.getConvergedReason() > 0 or self._solve_error() <= LU_CHECK

    def _backup_solver(self) -> PETSc.KSP:
        """MUMPS on the current reduced matrix (made at the first failure after a reset)."""
        if self._backup is None:
            self._backup = _lu_solver("mumps")
            self._backup.setOperators(self.problem.Ar)
        return self._backup

    def _solve_direction(self, res: NewtonResult) -> str:
        """dur = -Ar^-1 br with its CPU time booked; the failure reason, or "" on success."""
        c0 = time.process_time()
        try:
            self._linear_solve()
        except PETSc.Error as err:
            self.reset()  # a failed factorisation leaves the PC unusable
            return f"linear solve failed: {str(err).splitlines()[0]}"
        finally:
            c1 = time.process_time()
            res.cpu["linear"] += c1 - c0
            self.cpu_linear += c1 - c0
        if self.ksp.getConvergedReason() < 0:
            return f"linear solve failed (PETSc reason {self.ksp.getConvergedReason()})"
        return ""

    def _bind(self) -> None:
        """Factorise the problem's current reduced matrix from the next solve on."""
        self.ksp.setOperators(self.problem.Ar)
        self._operator = self.problem.Ar

    def _solve_error(self) -> float:
        """||Ar dur - br|| / ||br|| of the last solve (NaN-safe: a non-finite one is inf)."""
        pb = self.problem
        if self._check is None:
            self._check = pb.br.duplicate()
        pb.Ar.mult(pb.dur, self._check)
        self._check.axpy(-1.0, pb.br)
        err = self._check.norm() / max(pb.br.norm(), 1e-300)
        return err if np.isfinite(err) else np.inf

    def solve(self) -> NewtonResult:
        res = NewtonResult(False, 0)
        self._use_backup = False  # every solve starts with the configured package
        cpu0 = dict(self.problem.cpu)
        try:
            self._iterate(res)
        finally:
            for k, v in self.problem.cpu.items():
                res.cpu[k] += v - cpu0[k]
        return res

    def _iterate(self, res: NewtonResult) -> None:
        s, pb = self.settings, self.problem
        x = pb.w.x.array
        pb.constraints.set_prescribed(x)
        t0 = time.perf_counter()
        pb.assemble()
        res.time_assemble += time.perf_counter() - t0
        r0 = pb.br.norm()
        res.residuals.append(r0)
        if not np.isfinite(r0):
            res.reason = "residual is not finite (element inversion or overflow)"
            return
        if r0 <= s.atol + s.rtol * self.force_scale:
            res.converged = True
            return
        ref = max(r0, self.force_scale)
        for it in range(1, s.max_iterations + 1):
            t0 = time.perf_counter()
            res.reason = self._solve_direction(res)
            if res.reason:
                return
            pb.P.mult(pb.dur, pb.du)
            du = pb.du.array.copy()
            x += du
            small_step = np.linalg.norm(du) <= s.stol * max(np.linalg.norm(x), 1e-300)
            res.time_solve += time.perf_counter() - t0
            # residual only (no matrix) while line searching and testing convergence: the
            # tangent is assembled once the iterate is accepted and another iteration follows
            t0 = time.perf_counter()
            pb.assemble(need_matrix=False)
            r_prev, alpha = res.residuals[-1], 1.0
            for _ in range(s.max_backtracks if s.line_search else 0):
                r_try = pb.br.norm()
                if np.isfinite(r_try) and r_try <= s.backtrack_growth * r_prev:
                    break
                x -= 0.5 * alpha * du  # halve the step
                alpha *= 0.5
                res.backtracks += 1
                pb.assemble(need_matrix=False)
            r = pb.br.norm()
            res.residuals.append(r)
            res.iterations = it
            if self.on_iteration:
                self.on_iteration(it, r)
            if r <= s.atol + s.rtol * ref or (small_step and r <= 1e3 * (s.atol + s.rtol * ref)):
                res.time_assemble += time.perf_counter() - t0
                res.converged = True
                return
            if not np.isfinite(r) or r > s.divergence_factor * ref:
                res.reason = f"diverged: residual {r:.3e} after {it} iterations"
                return
            w = s.stagnation
            if (0 < w < len(res.residuals)
                    and min(res.residuals[-w:]) > 0.5 * min(res.residuals[:-w])):
                res.time_assemble += time.perf_counter() - t0
                res.reason = (f"stagnated: residual {r:.3e} not halved in {w} iterations "
                              f"(best {min(res.residuals):.3e})")
                return
            pb.assemble(need_vector=False)  # the residual at this iterate is assembled
            res.time_assemble += time.perf_counter() - t0
        res.reason = (f"no convergence in {s.max_iterations} iterations (residual "
                      f"{res.residuals[-1]:.3e})")
