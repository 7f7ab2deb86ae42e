"""Linear dof constraints as one prolongation: u_full = P u_red (+ prescribed values).

Every linear constraint a sliding run needs is a statement that some dofs equal others or are
prescribed:

* Dirichlet dofs: prescribed values, removed from the unknowns;
* periodic cells, eq. (6.5): x_r - x_l = X_r - X_l, i.e. u_r = u_l for each matched node pair;
* the top edge of a block moves as one (thesis 6.2.2): all its vertical dofs share one unknown.

Dofs tied together form groups (connected components), each group is one reduced unknown, and a
group that contains a prescribed dof is prescribed as a whole.  P (n_full x n_red) has one 1 per
row of a free dof.  The Newton solver works on P^T A P and P^T b; contact and bulk contributions
are assembled in the full space and condensed here, which is why our C++ contact blocks need no
special treatment for periodicity or ties (dolfinx_mpc 0.5 condenses UFL forms only, not our C++
contact blocks).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from petsc4py import PETSc
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


@dataclass
class ConstraintSpec:
    """Plain description of the constraints of one run (all indices are full-space dofs)."""

    n_full: int
    fixed: dict[int, float] = field(default_factory=dict)  # dof -> prescribed value
    pairs: list[tuple[int, int]] = field(default_factory=list)  # dofs that must be equal

    def fix(self, dofs, value: float = 0.0) -> None:
        for d in np.atleast_1d(dofs):
            self.fixed[int(d)] = float(value)

    def tie(self, dofs) -> None:
        """All dofs in `dofs` share one unknown."""
        d = np.atleast_1d(np.asarray(dofs, dtype=np.int64))
        self.pairs.extend((int(d[0]), int(x)) for x in d[1:])

    def equal(self, a, b) -> None:
        """Pairwise equality a[i] == b[i] (periodic node pairs)."""
        for x, y in zip(np.atleast_1d(a), np.atleast_1d(b)):
            self.pairs.append((int(x), int(y)))


class ConstraintMap:
    """The prolongation P and the bookkeeping of prescribed groups for one ConstraintSpec."""

    def __init__(self, spec: ConstraintSpec):
        n = spec.n_full
        roots = tie_groups(n, spec.pairs)
        self.roots = roots
        fixed_roots: dict[int, float] = {}
        for d, v in spec.fixed.items():
            r = int(roots[d])
            if r in fixed_roots and abs(fixed_roots[r] - v) > 1e-14 * max(1.0, abs(v)):
                raise ValueError(f"constraints: dof {d} prescribed {v} but tied to a dof "
                                 f"prescribed {fixed_roots[r]}")
            fixed_roots[r] = v
        self.fixed_roots = fixed_roots
        is_fixed = np.array([r in fixed_roots for r in roots]) if fixed_roots else np.zeros(n, bool)
        self.fixed_mask = is_fixed
        free_roots = np.unique(roots[~is_fixed])
        red_index = -np.ones(n, dtype=np.int64)
        red_index[free_roots] = np.arange(free_roots.size)
        self.red_of_full = np.where(is_fixed, -1, red_index[roots])
        self.n_full = n
        self.n_red = int(free_roots.size)
        rows = np.nonzero(~is_fixed)[0].astype(PETSc.IntType)
        cols = self.red_of_full[rows].astype(PETSc.IntType)
        self.P = _aij_from_coo(n, self.n_red, rows, cols, np.ones(rows.size))

    def prescribed_dofs(self) -> tuple[np.ndarray, np.ndarray]:
        """(dofs, values) of every full-space dof whose value is prescribed."""
        dofs = np.nonzero(self.fixed_mask)[0]
        vals = np.array([self.fixed_roots[int(self.roots[d])] for d in dofs])
        return dofs.astype(np.int32), vals

    def set_prescribed(self, x: np.ndarray) -> None:
        """Write the prescribed values into a full-space array."""
        dofs, vals = self.prescribed_dofs()
        x[dofs] = vals

    def update_value(self, dofs, value: float) -> None:
        """Change the prescribed value of (the groups of) `dofs`, e.g. a load path."""
        for d in np.atleast_1d(dofs):
            r = int(self.roots[int(d)])
            if r not in self.fixed_roots:
                raise ValueError(f"dof {d} is not prescribed")
            self.fixed_roots[r] = float(value)


def tie_groups(n: int, pairs: list[tuple[int, int]]) -> np.ndarray:
    """The group of every dof: the smallest dof it is tied to through ``pairs`` (itself if none).

    The groups are the connected components of the graph whose edges are the pairs
    (``scipy.sparse.csgraph``); naming each by its smallest dof keeps the reduced numbering
    ordered like the full one."""
    edges = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    smallest = np.full(label.max() + 1 if n else 0, n, dtype=np.int64)
    np.minimum.at(smallest, label, np.arange(n))
    return smallest[label]


def _aij_from_coo(m: int, n: int, rows, cols, vals) -> PETSc.Mat:
    """AIJ matrix with at most one entry per row (rows strictly increasing)."""
    counts = np.zeros(m, dtype=PETSc.IntType)
    counts[rows] = 1
    indptr = np.concatenate([[0], np.cumsum(counts)]).astype(PETSc.IntType)
    A = PETSc.Mat().createAIJ((m, n), csr=(indptr, np.asarray(cols, PETSc.IntType),
                                           np.asarray(vals, float)),
                              comm=PETSc.COMM_SELF)
    A.assemble()
    return A
