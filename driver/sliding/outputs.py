"""What a single-scale sliding run returns besides its numbers: fields, series, plots and depth
profiles.

Observers of :class:`rubberfriction.driver.sliding.run.SlidingRun` (passed as
``run_sliding(spec, observers=[...])``) see the run after each converged sliding step; the
run retries failed attempts with fallbacks (mortar -> nts -> smaller steps) and calls
``on_start`` / ``on_finish`` for every attempt, so each observer starts afresh in ``on_start``
and what it holds after the run belongs to the last attempt (the returned result).

* :class:`FieldWriter`: XDMF/HDF5 time series for ParaView (displacement, hydrostatic pressure,
  von Mises stress, viscous dissipation per cell, temperature) and the contact pressure along the
  contact face as CSV.
* :class:`DissipationByDepth`: the viscous energy of the homogenisation window binned by depth
  below the contact face (thesis fig. 6.29 c, "local relative dissipated energy"; dissipation
  concentrates near the surface, thesis 8.1).
* :func:`write_series_csv` / :func:`read_series_csv`, :func:`plot_mu`, :func:`write_run_outputs`.

Units: mm, s, N, MPa, mJ, K; plane strain, so forces are N per mm depth and energies mJ per mm
depth.  Viscous energy is the time integral of the Prony dashpots' dissipation density over the
reference volume (thesis eq. 2.7, the dissipation of ``forms.viscoelastic``); its sum over the
window divided by F_z and the sliding distance is the energy-based mu (eq. 2.8).
"""

from __future__ import annotations

import csv
import json
import math
import warnings
from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.io import XDMFFile

from rubberfriction.forms import jit
from rubberfriction.forms.kinematics import deformation_gradient

#: columns of SlidingResult.series and their units (CSV header "name [unit]")
SERIES_UNITS: dict[str, str] = {
    "t": "s",
    "s": "mm",
    "Fx": "N/mm",
    "Fz": "N/mm",
    "contact_length": "mm",
    "viscous_energy": "mJ/mm",
    "friction_energy": "mJ/mm",
    "mean_pressure": "MPa",
    "stabilisation_energy": "mJ/mm",
    "stabilisation_impulse": "N s/mm",
    "interface_energy": "mJ/mm",
    "mu_force": "1",
}


# --- helpers shared by the observers ----------------------------------------------------------
def slide_distance(spec, block_length: float) -> float:
    """Total sliding distance of a run (mm): ``spec.slide_distance`` or 3 periods (3 block lengths
    for a non-periodic surface), as in ``SlidingRun._attempt``."""
    if spec.slide_distance:
        return float(spec.slide_distance)
    return 3.0 * float(spec.period if spec.period > 0 else block_length)


def window_mask(result, spec, block_length: float) -> np.ndarray:
    """Steps of the homogenisation window the run averaged over, s > stats ``window_start`` (as
    in ``result.window``: the fixed rule's window_start x distance, or the converged rule's
    last whole periods); without those stats the fixed rule."""
    s = np.asarray(result.series.get("s", np.zeros(0)), dtype=float)
    stats = getattr(result, "stats", None) or {}
    if "window_start" in stats:
        lo, hi = float(stats["window_start"]), float(stats.get("window_end", 1.0))
        return s > lo + 1e-9 * max(hi, 1.0)
    return s > spec.window_start * slide_distance(spec, block_length)


def _step_lengths(s: np.ndarray) -> np.ndarray:
    """Sliding distance of each step (ds_k = s_k - s_{k-1}, s_0 = 0)."""
    return np.diff(np.concatenate([[0.0], np.asarray(s, dtype=float)]))


def _point_weights(sp) -> np.ndarray:
    """(n_cells, n_points) reference-volume weight |det J| w_q of each bulk quadrature point."""

    mesh = sp.mesh
    ncell = mesh.topology.index_map(mesh.topology.dim).size_local
    cells = np.arange(ncell, dtype=np.int32)
    x = ufl.SpatialCoordinate(mesh)
    detJ = jit.expression(abs(ufl.JacobianDeterminant(mesh)) + 0.0 * x[0], sp.rule.points)
    return detJ.eval(cells).reshape(ncell, -1) * sp.rule.weights[None, :]


def _point_coordinates(sp) -> np.ndarray:
    """(n_cells * n_points, 2) reference coordinates of the bulk quadrature points, cell-major
    (the ordering of ``ViscoelasticHistory`` arrays)."""

    mesh = sp.mesh
    ncell = mesh.topology.index_map(mesh.topology.dim).size_local
    expr = jit.expression(ufl.SpatialCoordinate(mesh), sp.rule.points)
    return expr.eval(np.arange(ncell, dtype=np.int32)).reshape(-1, 2)


def _dissipated_points(sp) -> np.ndarray | None:
    """Viscous energy dissipated so far per quadrature point (mJ/mm); None for an elastic body."""
    hist = getattr(sp, "history", None)
    if hist is None:
        return None
    return np.array(hist.dissipated_points, dtype=float)


# --- fields for ParaView ----------------------------------------------------------------------
class FieldWriter:
    """Observer writing fields of every ``every``-th sliding step to ``folder/fields.xdmf`` (+ .h5).

    Functions (time-stamped by t in s, on the reference mesh; warp by ``displacement`` in ParaView):

    * ``displacement`` [mm], P1;
    * ``hydrostatic_pressure`` [MPa], DG0: -tr(sigma)/3 of the Cauchy stress
      sigma = F S F^T / J (thesis 3.1), cell average, positive in compression;
    * ``von_mises`` [MPa], DG0: sqrt(3/2 dev(sigma) : dev(sigma)), cell average (3D, incl. sigma_33
      of plane strain);
    * ``viscous_dissipation`` [mJ/mm^3], DG0: viscous energy dissipated per unit reference volume
      since the previous output (eq. 2.7 per cell; with every=1, the step's);
    * ``dissipation_rate`` [MPa/s = mW/mm^3], DG0: the mean dissipation rate of the last step
      (``ViscoelasticHistory.rate``, exact at finite strain), cell average;
    * ``temperature`` [K], DG0: only if the body has a temperature (WLF shift per cell).

    ``contact_pressure.csv`` (if ``contact_csv``): one row per contact-face node and output step,
    with reference and current position, pressure [MPa] and contact status (0 open, 1 stick,
    2 slip).
    """

    def __init__(self, folder, every: int = 1, contact_csv: bool = True, name: str = "fields"):
        if every < 1:
            raise ValueError(f"every: must be >= 1, got {every}")
        self.folder = Path(folder)
        self.every = int(every)
        self.contact_csv = bool(contact_csv)
        self.name = name
        self.xdmf_path = self.folder / f"{name}.xdmf"
        self.contact_path = self.folder / "contact_pressure.csv"
        self.times: list[float] = []
        self._xdmf = None
        self._csv = None

    # --- observer interface ----------------------------------------------------------------
    def on_start(self, run) -> None:
        """Open the files afresh (a retried attempt overwrites the previous one's output)."""

        self.close()
        self.folder.mkdir(parents=True, exist_ok=True)
        sp = self.sp = run.sp
        mesh = sp.mesh
        self.times = []
        self._xdmf = XDMFFile(mesh.comm, str(self.xdmf_path), "w")
        self._xdmf.write_mesh(mesh)
        self._u = fem.Function(sp.V, name="displacement")
        self._dg0 = fem.FunctionSpace(mesh, ("DG", 0))
        ncell = mesh.topology.index_map(mesh.topology.dim).size_local
        self._cell_dof = np.asarray(self._dg0.dofmap.list.array, dtype=np.int32)[:ncell]
        self._cells = np.arange(ncell, dtype=np.int32)
        names = ["hydrostatic_pressure", "von_mises", "viscous_dissipation", "dissipation_rate"]
        hist = getattr(sp, "history", None)
        self._has_T = hist is not None and getattr(hist, "T_cell", None) is not None
        if self._has_T:
            names.append("temperature")
        self._f = {n: fem.Function(self._dg0, name=n) for n in names}
        self._wq = _point_weights(sp)
        self.cell_volume = self._wq.sum(axis=1)  # reference area per cell (mm^2, x 1 mm depth)
        self._stress = self._stress_expression(sp)
        self._D_last = _dissipated_points(sp)
        if self.contact_csv:
            self._csv = open(self.contact_path, "w", newline="")
            self._csv_w = csv.writer(self._csv)
            self._csv_w.writerow(["step", "t [s]", "s [mm]", "X [mm]", "x [mm]", "z [mm]",
                                  "pressure [MPa]", "status"])

    def on_step(self, run, k: int, t: float) -> None:
        """Write the fields of step k (every ``every``-th step)."""
        if self._xdmf is None or k % self.every:
            return
        sp = self.sp
        self._u.x.array[:] = sp.w.x.array[np.asarray(sp.umap)]
        self._u.x.scatter_forward()
        vals = self._stress.eval(self._cells).reshape(self._cells.size, -1, 2)
        mean = np.einsum("cq,cqi->ci", self._wq, vals) / self.cell_volume[:, None]
        self._set("hydrostatic_pressure", mean[:, 0])
        self._set("von_mises", mean[:, 1])
        D = _dissipated_points(sp)
        if D is None:
            self._set("viscous_dissipation", np.zeros(self._cells.size))
            self._set("dissipation_rate", np.zeros(self._cells.size))
        else:
            dE = (D - self._D_last).reshape(self._cells.size, -1).sum(axis=1)
            self._D_last = D
            self._set("viscous_dissipation", dE / self.cell_volume)
            rate = sp.history.rate.reshape(self._cells.size, -1)
            self._set("dissipation_rate", np.sum(rate * self._wq, axis=1) / self.cell_volume)
        if self._has_T:
            self._set("temperature", np.asarray(sp.history.T_cell, dtype=float))
        self._xdmf.write_function(self._u, t)
        for f in self._f.values():
            self._xdmf.write_function(f, t)
        self.times.append(float(t))
        if self._csv is not None:
            self._write_contact(run, k, t)

    def on_finish(self, run, result) -> None:
        self.close()

    def close(self) -> None:
        """Close the XDMF and CSV files (safe to call twice)."""
        if self._xdmf is not None:
            self._xdmf.close()
            self._xdmf = None
        if self._csv is not None:
            self._csv.close()
            self._csv = None

    # --- pieces ------------------------------------------------------------------------------
    def _set(self, name: str, cell_values: np.ndarray) -> None:
        f = self._f[name]
        f.x.array[self._cell_dof] = cell_values
        f.x.scatter_forward()

    @staticmethod
    def _stress_expression(sp):
        """fem.Expression of (-tr(sigma)/3, von Mises) at the bulk quadrature points."""
        u, _ = sp.split()
        F = deformation_gradient(u)
        J = ufl.det(F)
        sigma = F * sp.second_piola() * F.T / J
        p = -ufl.tr(sigma) / 3.0
        s = sigma + p * ufl.Identity(3)
        vm = ufl.sqrt(1.5 * ufl.inner(s, s))
        return jit.expression(ufl.as_vector([p, vm]), sp.rule.points)

    def _write_contact(self, run, k: int, t: float) -> None:
        contact = run.contact
        st = contact.state()
        slave = getattr(contact, "slave", None)
        if slave is None or "pressure" not in st:
            return
        X = np.asarray(slave.X, dtype=float)
        x = X + self.sp.w.x.array[np.asarray(slave.dofs)]
        offset = getattr(contact, "offset", None)
        s = -float(offset[0]) if offset is not None else math.nan
        status = np.asarray(st.get("status", np.zeros(X.shape[0])))
        for i in np.argsort(X[:, 0]):
            self._csv_w.writerow([k, repr(float(t)), repr(s), repr(float(X[i, 0])),
                                  repr(float(x[i, 0])), repr(float(x[i, 1])),
                                  repr(float(st["pressure"][i])), int(status[i])])


# --- dissipation by depth ---------------------------------------------------------------------
class DissipationByDepth:
    """Observer: viscous energy of the homogenisation window binned by depth below the contact face.

    Depth d = Z - Z_bottom of each bulk quadrature point in the reference configuration (the
    block's bottom face is the contact face).  Bins: ``edges`` (mm, from 0) if given, else
    ``bins`` equal bins over the block height, else one bin per element row of the (graded,
    structured) block, so each bin integrates whole cells.

    Per step k the energy per bin E_b,k (mJ/mm) is the change of the history's per-point
    dissipated energy (eq. 2.7; it sums to the step's ``viscous_energy``).  After the run, over the
    window steps W (s_k > window_start x distance, the steps of mu_energy, eq. 2.8):

        values_b = sum_{k in W} E_b,k / (L  dd_b  s_W)      [mJ/mm^3 per mm slid]

    the mean dissipated energy per unit volume at that depth per mm slid (L block length, dd_b bin
    height, s_W the window's sliding distance), so  sum_b values_b dd_b L s_W  is the window's
    viscous energy.  ``result.dissipation_by_depth = (bin centres [mm], values)`` when the result
    is ok; ``edges``, ``energy`` (E_b over the window, mJ/mm), ``window_distance`` and ``relative``
    (energy fraction per bin, thesis fig. 6.29 c) stay on the observer.

    Dissipation concentrates within about one wavelength of the contact face.  For full contact on
    a sinusoid of wavenumber k the deviatoric stress of a (nearly) incompressible half-space is
    ~ kz exp(-kz), so the density ~ (kz)^2 exp(-2kz) peaks at depth 1/k, not at the surface
    (checked in ``tests/test_sliding_output.py``).
    """

    def __init__(self, edges=None, bins: int | None = None):
        self._edges_in = None if edges is None else np.asarray(edges, dtype=float)
        self._bins = bins
        self.edges: np.ndarray | None = None
        self.energy: np.ndarray | None = None
        self.values: np.ndarray | None = None
        self.relative: np.ndarray | None = None
        self.window_distance = math.nan
        self.block_length = math.nan
        self._rows: list[np.ndarray] = []

    @property
    def centres(self) -> np.ndarray | None:
        return None if self.edges is None else 0.5 * (self.edges[1:] + self.edges[:-1])

    def on_start(self, run) -> None:
        sp = run.sp
        Z = _point_coordinates(sp)[:, 1]
        z_bottom = float(np.min(sp.mesh.geometry.x[:, 1]))
        H = float(np.max(sp.mesh.geometry.x[:, 1])) - z_bottom
        depth = Z - z_bottom
        if self._edges_in is not None:
            edges = self._edges_in
        elif self._bins:
            edges = np.linspace(0.0, H, int(self._bins) + 1)
        else:  # element rows of the structured block: the distinct node heights
            levels = np.unique(np.round(sp.mesh.geometry.x[:, 1] - z_bottom, 12))
            edges = levels
        if edges.size < 2 or np.any(np.diff(edges) <= 0.0):
            raise ValueError("depth bins: edges must increase and give at least one bin")
        self.edges = np.asarray(edges, dtype=float)
        idx = np.searchsorted(self.edges, depth, side="right") - 1
        self._bin = np.clip(idx, 0, self.edges.size - 2)
        self.block_length = float(run.L)
        self._D_last = _dissipated_points(sp)
        self._rows = []
        self.energy = self.values = self.relative = None
        self.window_distance = math.nan

    def on_step(self, run, k: int, t: float) -> None:
        nb = self.edges.size - 1
        D = _dissipated_points(run.sp)
        if D is None:
            self._rows.append(np.zeros(nb))
            return
        dE = D - self._D_last
        self._D_last = D
        self._rows.append(np.bincount(self._bin, weights=dE, minlength=nb))

    def on_finish(self, run, result) -> None:
        if not result.ok or self.edges is None:
            return
        s = np.asarray(result.series["s"], dtype=float)
        if len(self._rows) != s.size:  # an observer must not fail the run: warn, leave None
            warnings.warn(f"dissipation by depth: {len(self._rows)} steps observed, {s.size} in "
                          "the series; result.dissipation_by_depth left unset", stacklevel=2)
            return
        win = window_mask(result, run.spec, self.block_length)
        rows = np.array(self._rows).reshape(s.size, -1)
        self.window_distance = float(_step_lengths(s)[win].sum())
        self.energy = rows[win].sum(axis=0)
        dd = np.diff(self.edges)
        with np.errstate(divide="ignore", invalid="ignore"):
            self.values = self.energy / (self.block_length * dd * self.window_distance)
            total = self.energy.sum()
            self.relative = self.energy / total if total > 0 else np.zeros_like(self.energy)
        result.dissipation_by_depth = (self.centres, self.values)


# --- series, plots, summaries -----------------------------------------------------------------
def _series_columns(result) -> list[str]:
    known = [c for c in SERIES_UNITS if c in result.series]
    return known + [c for c in result.series if c not in SERIES_UNITS]


def write_series_csv(result, path) -> Path:
    """Time series of a run as CSV: header ``name [unit]``, one row per sliding step, values with
    full precision (``repr``), so :func:`read_series_csv` round-trips them exactly."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    cols = _series_columns(result) or list(SERIES_UNITS)  # a failed set-up has no series
    n = len(result.series[cols[0]]) if cols[0] in result.series else 0
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([f"{c} [{SERIES_UNITS.get(c, '')}]" for c in cols])
        for i in range(n):
            w.writerow([repr(float(result.series[c][i])) for c in cols])
    return path


def read_series_csv(path) -> dict[str, np.ndarray]:
    """Series dict back from :func:`write_series_csv` (units dropped from the names)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = [h.split(" [")[0] for h in rows[0]]
    data = np.array(rows[1:], dtype=float).reshape(len(rows) - 1, len(names))
    return {n: data[:, i] for i, n in enumerate(names)}


def write_dissipation_csv(result, path) -> Path | None:
    """``result.dissipation_by_depth`` as CSV (depth of the bin centre, mJ/mm^3 per mm slid)."""
    if result.dissipation_by_depth is None:
        return None
    depth, values = result.dissipation_by_depth
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["depth [mm]", "dissipation [mJ/mm^3 per mm slid]"])
        for d, v in zip(depth, values):
            w.writerow([repr(float(d)), repr(float(v))])
    return path


def mu_energy_per_step(result) -> np.ndarray:
    """mu of each step from its dissipated energy, (viscous + friction) / (F_z ds) (eq. 2.8)."""
    ser = result.series
    ds = _step_lengths(ser["s"])
    with np.errstate(divide="ignore", invalid="ignore"):
        return (ser["viscous_energy"] + ser["friction_energy"]) / (ser["Fz"] * ds)


def plot_mu(result, spec, path) -> Path:
    """mu(s) per step (force-based, eq. 6.2, and energy-based, eq. 2.8) over the sliding distance,
    the homogenisation window shaded and the window averages mu_force, mu_energy as lines (PNG,
    drawn with the Agg canvas; pyplot's global backend is left alone)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    L = spec.block_length or spec.period
    distance = slide_distance(spec, L)
    fig = Figure(figsize=(7.0, 4.0))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ser = result.series
    if ser.get("s") is not None and len(ser["s"]):
        ax.plot(ser["s"], ser["mu_force"], "o-", ms=3, color="C0", label="mu force (6.2), per step")
        ax.plot(ser["s"], mu_energy_per_step(result), "s--", ms=2, lw=0.8, color="C1",
                label="mu energy (2.8), per step")
    else:
        ax.text(0.5, 0.5, "no sliding step", transform=ax.transAxes, ha="center")
    if distance > 0:
        ax.axvspan(spec.window_start * distance, distance, color="0.88", zorder=0,
                   label="homogenisation window")
        ax.set_xlim(0.0, distance)
    w0 = spec.window_start * distance
    if math.isfinite(result.mu_force):
        ax.hlines(result.mu_force, w0, distance, color="C0", lw=1.8,
                  label=f"mu_force = {result.mu_force:.4g} (window average)")
    if math.isfinite(result.mu_energy):
        ax.hlines(result.mu_energy, w0, distance, color="C1", lw=1.8, ls=":",
                  label=f"mu_energy = {result.mu_energy:.4g} (window average)")
    ax.set_xlabel("sliding distance s [mm]")
    ax.set_ylabel("coefficient of friction mu [-]")
    ax.set_title(f"sliding run: {result.status}"
                 + (f" ({result.reason})" if result.reason else ""), fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path


def _finite(x):
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def run_summary(result, spec) -> dict:
    """Scalars of a run and its spec as a JSON-ready dict (NaN -> null)."""
    L = spec.block_length or spec.period
    distance = slide_distance(spec, L)
    keys = ("period", "pressure", "velocity", "block_length", "block_height", "temperature",
            "element", "contact", "h_contact", "elements_per_wavelength", "slide_distance",
            "step_length", "window_start")
    spec_d = {k: getattr(spec, k) for k in keys}
    spec_d["compound"] = getattr(spec.compound, "name", str(spec.compound))
    hyper = getattr(spec.compound, "hyperelastic", None)
    if hyper is not None:
        spec_d["volumetric"] = hyper.volumetric
    spec_d["friction"] = spec.friction if isinstance(spec.friction, (int, float, type(None))) \
        else type(spec.friction).__name__
    return _finite({
        "status": result.status, "reason": result.reason, "t_reached": result.t_reached,
        "mu_force": result.mu_force, "mu_energy": result.mu_energy,
        "mean_pressure": result.mean_pressure, "contact_fraction": result.contact_fraction,
        "window_drift": result.window_drift, "mu_error": result.mu_error,
        "contact_drift": result.contact_drift, "contact_error": result.contact_error,
        "converged": result.converged, "stabilisation_share": result.stabilisation_share,
        "min_det_F": result.min_det_F, "road_intrusion": result.road_intrusion,
        "contact_elements": result.contact_elements,
        "window_mm": [result.stats.get("window_start", spec.window_start * distance),
                      result.stats.get("window_end", distance)],
        "steps": len(result.series.get("t", [])),
        "stats": dict(result.stats), "spec": spec_d,
        "units": {"mean_pressure": "MPa", "t_reached": "s", "window_mm": "mm",
                  "road_intrusion": "contact elements", "contact_elements": "contact elements"},
    })


def write_run_outputs(result, spec, folder) -> dict[str, Path]:
    """``series.csv``, ``mu.png``, ``summary.json`` and, if present, ``dissipation_by_depth.csv``
    in ``folder``; returns the paths written by name."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = {"series": write_series_csv(result, folder / "series.csv"),
           "plot": plot_mu(result, spec, folder / "mu.png")}
    diss = write_dissipation_csv(result, folder / "dissipation_by_depth.csv")
    if diss is not None:
        out["dissipation_by_depth"] = diss
    summary = run_summary(result, spec)
    summary["files"] = {k: p.name for k, p in out.items()}
    out["summary"] = folder / "summary.json"
    with open(out["summary"], "w") as f:
        json.dump(summary, f, indent=2)
    return out


__all__ = [
    "DissipationByDepth",
    "FieldWriter",
    "SERIES_UNITS",
    "mu_energy_per_step",
    "plot_mu",
    "read_series_csv",
    "run_summary",
    "slide_distance",
    "window_mask",
    "write_dissipation_csv",
    "write_run_outputs",
    "write_series_csv",
]
