"""Extrapolation of a periodic cell's creep to its limit (the period map's slowest mode).

With the steady-state jump (``ViscoelasticHistory.extrapolate_periodic``) every Prony branch
takes its periodic state for the path of the period just slid, yet the state still changes from
period to period, geometrically: on the four-scale road's micro2 cell at 7 MPa and 100 mm/s the
block creeps horizontally under the mean shear of the friction force (the mean horizontal
displacement grows by 7.7, 5.8, 4.3, 3.4, 2.6, ... um a period, ratio about 0.74), and after that
the contact's indentation settles with a ratio of about 0.7; mu falls with both for 18 periods
(``docs/performance.md``, "The periodic steady state").  A geometric sequence d_n = rho d_(n-1)
has its limit after three changes: x_inf = x_n + rho / (1 - rho) (x_n - x_(n-1)) (Aitken's
extrapolation of a linearly converging fixed-point iteration, along the observed direction).

Taken at a period start after the jump, while the contact face creeps by more than
``CREEP_ELEMENTS`` contact elements a period: the rows' mean horizontal displacements (of the
structured block mesh, ``meshes.block``) and the histories' row means are extrapolated, and the
road moves with the contact face so that the face meets it as before.  The full displacement
change cannot be extrapolated: between two period starts the material has moved under the road,
so the change holds the contact pattern shifted by the creep, which extrapolated inverts
elements.  The rows' vertical means are not extrapolated either: they follow the contact's
indentation, not the creep (extrapolated, Newton finds no equilibrium).  Nor is the settling of
the contact after the creep: extrapolating the whole state there passed the equilibrium check and
then broke the run's next steps (a meso cell of the trend study at 6 MPa and 1 m/s, which
converges in 7 periods without it, failed all its attempts with it; ``docs/performance.md``).

It is used only where two successive ratios of the mode's changes (projected on each other)
agree within ``RHO_AGREE`` and lie in [``RHO_MIN``, ``RHO_MAX``]: a geometric approach, not noise
or an oscillation.  The extrapolated state is then brought to equilibrium at the period start
(the caller's ``equilibrate``); where that fails the extrapolation is halved, and it goes as far
as equilibrium is found.  The state and histories are moved together: moving the displacement
alone is undone by the glassy branches in the next step, moving the histories alone by the
displacement (Anderson mixing of the histories gained nothing, ``docs/history.md``).  Any start is
a valid start of the period map, so the fixed point is unchanged; the window rule of
``driver.sliding.window`` decides stationarity on the periods after the last extrapolation.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

#: smallest ratio of successive period changes worth extrapolating (faster: a period or two)
RHO_MIN = 0.3
#: largest ratio used (omega = rho / (1 - rho) at most 9)
RHO_MAX = 0.9
#: two successive ratios must agree within this
RHO_AGREE = 0.1
#: extrapolated while the contact face creeps more than this many contact elements a period
CREEP_ELEMENTS = 0.25
#: equilibrium solves an extrapolation may take (its part halves after each that fails)
MAX_SOLVES = 6


class FaceCreep:
    """The contact face's mean horizontal displacement (the lowest row of the structured block
    mesh) in contact elements, for the creep guard of one-period windows
    (``driver.sliding.periods``): a cell whose face still creeps is not periodic, however flat
    its mu (the four-scale micro2 cell: two periods within 0.6 % at +34 % while the face crept
    by 15 elements a period)."""

    def __init__(self, sp):
        self.sp = sp
        self.rows = _rows(sp.node_X[:, 1])  # row index of each node, 0 the contact face
        self.x_dofs = np.asarray(sp.displacement_dofs(), dtype=np.int64)[self.rows == 0, 0]
        face = np.sort(sp.node_X[self.rows == 0, 0])
        self.h_face = float(np.min(np.diff(face))) if face.size > 1 else np.inf

    def __call__(self) -> float:
        """The face's mean horizontal displacement now, in contact elements."""
        return float(np.mean(self.sp.w.x.array[self.x_dofs])) / self.h_face


class SlowModeExtrapolation:
    """Period-start states of one sliding attempt; ``after_jump`` extrapolates the block's creep
    when its last three period changes are geometric.

    sp: the attempt's SolidProblem (solution vector ``w``, ``history``, kinematics) on a
    structured block mesh (``meshes.block``: the same x-columns at every height); ``face``: its
    FaceCreep (the rows and the contact element length), made here if not given.
    """

    def __init__(self, sp, face: FaceCreep | None = None):
        self.sp = sp
        face = face if face is not None else FaceCreep(sp)
        self.node_dofs = np.asarray(sp.displacement_dofs(), dtype=np.int64)  # (nodes, 2)
        self.node_rows = face.rows
        self.cell_rows = _rows(sp.cell_centroids()[:, 1])
        self.h_face = face.h_face
        self.xs: list[np.ndarray] = []  # solution vectors at the period starts since the last
        self.Hs: list[np.ndarray] = []  # extrapolation, and the histories (the last two)
        self.count = 0  # extrapolations made
        self.rejected = 0  # left out: no equilibrium even at the smallest part
        self.omegas: list[float] = []  # the factors used

    def after_jump(self, equilibrate: Callable[[float], bool],
                   worth: Callable[[float], bool] = lambda omega: True
                   ) -> tuple[np.ndarray, float] | None:
        """Record the period start just reached (after the history jump); where the contact face
        creeps and the last three changes are geometric, move the state to their limit.
        ``equilibrate(shift)`` moves the road by ``shift`` (beyond the shifts before) and solves
        equilibrium at the period start; it returns whether that converged.  ``worth(omega)``:
        whether an extrapolation by omega periods' changes would move the results enough to pay
        for the periods it restarts.  Returns the change of the solution vector and the road's shift
        (None: not extrapolated)."""
        sp = self.sp
        self.xs = (self.xs + [sp.w.x.array.copy()])[-4:]
        self.Hs = (self.Hs + [sp.history.H.copy()])[-2:]
        if len(self.xs) < 4:
            return None
        u = [x[self.node_dofs] for x in self.xs]  # (nodes, 2) each
        means = [_row_mean(ui[:, 0], self.node_rows) for ui in u]
        if abs(means[-1][0] - means[-2][0]) <= CREEP_ELEMENTS * self.h_face:
            return None  # the face hardly creeps: nothing to extrapolate
        d = [b - a for a, b in zip(means[:-1], means[1:])]
        rho = [_ratio(d[1], d[0]), _ratio(d[2], d[1])]
        if not (RHO_MIN <= rho[1] <= RHO_MAX and abs(rho[1] - rho[0]) <= RHO_AGREE):
            return None
        omega = rho[1] / (1.0 - rho[1])
        if not worth(omega):
            return None
        dx = np.zeros_like(self.xs[-1])
        dx[self.node_dofs[:, 0]] = d[2][self.node_rows]
        hist = sp.history
        dH = _row_mean((self.Hs[-1] - self.Hs[-2]).reshape(
            hist.H.shape[0], -1, hist.npts, hist.H.shape[2]), self.cell_rows, axis=1)
        dH = dH[:, self.cell_rows].reshape(hist.H.shape)
        shift = float(d[2][0])  # the contact face's row: the road moves with it
        done = self._move(omega, dx, dH, shift, equilibrate)
        if done == 0.0:
            self.rejected += 1
            return None
        self.count += 1
        self.omegas.append(done * omega)
        moved = sp.w.x.array - self.xs[-1]
        self.xs, self.Hs = [sp.w.x.array.copy()], [sp.history.H.copy()]
        return moved, done * omega * shift

    def _move(self, omega: float, dx: np.ndarray, dH: np.ndarray, shift: float,
              equilibrate: Callable[[float], bool]) -> float:
        """Move the state by f omega (dx, dH, road shift) with f as close to 1 as equilibrium
        allows (halving from 1, then on from the last converged part); returns f (0: the state
        as it was)."""
        sp, hist = self.sp, self.sp.history
        x0, H0, Sbar0 = self.xs[-1], self.Hs[-1], hist.Sbar_n.copy()
        done, part, x_done, Sbar_done = 0.0, 1.0, x0.copy(), Sbar0
        for _ in range(MAX_SOLVES):
            f = min(1.0, done + part)
            sp.w.x.array[:] = x_done + (f - done) * omega * dx
            hist.restore(H0 + f * omega * dH, sp.history_kinematics()[0])
            if equilibrate(f * omega * shift):
                done, x_done, Sbar_done = f, sp.w.x.array.copy(), hist.Sbar_n.copy()
                if done >= 1.0:
                    break
            else:
                part *= 0.5
        sp.w.x.array[:] = x_done
        hist.restore(H0 + done * omega * dH, Sbar_done)
        if done == 0.0:
            equilibrate(0.0)  # the road back where it was
        return done


def _rows(z: np.ndarray) -> np.ndarray:
    """Row index (0 at the lowest) of each height z of a structured mesh."""
    scale = max(1.0, float(np.ptp(z)))
    _, inv = np.unique(np.round(z / (1e-9 * scale)), return_inverse=True)
    return inv


def _row_mean(a: np.ndarray, rows: np.ndarray, axis: int = 0) -> np.ndarray:
    """Means of ``a`` over the entries of each row along ``axis`` (that axis becomes the rows)."""
    a = np.moveaxis(np.asarray(a, dtype=float), axis, 0)
    n = int(rows.max()) + 1
    sums = np.zeros((n,) + a.shape[1:])
    np.add.at(sums, rows, a)
    counts = np.bincount(rows, minlength=n).reshape((n,) + (1,) * (a.ndim - 1))
    return np.moveaxis(sums / counts, 0, axis)


def _ratio(d: np.ndarray, d_before: np.ndarray) -> float:
    """The projection of a period's change on the change before it, relative to the latter."""
    den = float(np.dot(d_before, d_before))
    return float(np.dot(d, d_before)) / den if den > 0.0 else float("nan")
