"""Thermomechanical macro run: the rubber block sliding over the road with frictional heating
(thesis 8.3.1, 8.5.1), staggered.

Each converged sliding step of the mechanical run (``driver.sliding.run.SlidingRun``, non-periodic
block, rigid road) is followed by one heat step of block and road (``conduction.TwoBodyHeat``)
with the nodal frictional power of that step, P_i = |t_T| dgamma/dt A_i (zero in stick; scaled
so that sum_i P_i dt is the step's frictional dissipation, also over cut-back sub-steps); the new
block surface temperature enters mu(p, v, T) of the next step per slave node
(``Contact.set_slave_temperatures``).  The road is rigid for the mechanics (E_road / E_rubber
~ 1e4, thesis 8.4.1) and Eulerian for the heat (road moving at -v under the block).

Why staggered: the mechanical run keeps its Newton, cut-backs and fallbacks unchanged, the heat
problem is linear and its factorisation is reused for every step of equal length, and the
coupling is one-way within a step (mu depends on T, T on the frictional power).  The lag of one
step is the scheme's error; its measure is the largest change of the contact temperature per
step (stats ``max_step_dT``), and halving the sliding step shows it
(``tests/test_thermal_macro.py``).

Thermo-viscoelastic bulk: after each heat step the temperature of every cell of the mechanical
block (bilinear from the heat block's grid at the cell centroid) shifts its relaxation times by
WLF (``SolidProblem.set_temperature``, ``MacroSettings.bulk_wlf``), for the next step: the same
one-step lag.  The bulk's own viscous dissipation is not a heat source (thesis 8.3.2: negligible
on the macro scale against the frictional heat).

Repeated slides with pauses (thesis 8.5.2): ``run_thermal_slides``.  An elastic road instead of
the rigid one: ``MacroSettings.road_elastic`` (``road_deflection``: its surface deflection under
the contact forces moves the road polyline, staggered like the heat).

Rough road (a spec whose surface is the macro band of a road, ``thermal_scene.macro_inputs``): the
mechanics sees the rough polyline; the heat problem keeps its rectangles, the road's in coordinates
flattened along its surface (depth measured down from the road surface at the same x) and the
block's undeformed.  The transport along x is then exact (a road point keeps its depth below the
surface as it moves at -v) and so is the heat capacity (the shear map x, z -> x, z - h(x) keeps
volumes); the conduction drops the metric terms of the map: a flux per unit x enters an area
sqrt(1 + h'^2) times larger, so surface temperature rises are overestimated by about h'^2 / 2 at a
contact spot of slope h' (contact sits near asperity tops, where h' is small).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sps

from rubberfriction import validation as V
from rubberfriction.driver.fe.contact import RigidMaster, ThermalSettings
from rubberfriction.driver.sliding.bodies import block_mesh, sliding_contact
from rubberfriction.driver.sliding.run import SlidingRun
from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec
from rubberfriction.driver.thermal.conduction import (
    FIRST_LAYER,
    HeatGeometry,
    TwoBodyHeat,
    geometric_steps,
)
from rubberfriction.driver.thermal.road_deflection import ElasticRoad
from rubberfriction.forms.compound import Road, Thermal


#: the interface of thesis 8.3.1: all frictional heat to the rubber, h_c = 1e6 mW/(mm^2 K)
THESIS_INTERFACE = ThermalSettings(h0=1.0e6, kappa=1.0)


@dataclass(frozen=True)
class MacroSettings:
    """Thermal part of a macro run: the interface (heat share kappa to the rubber, constant
    conductance h_c = h0 where in contact), initial and block-top temperature T0 (K), the road's
    thermal data, road extents in the block frame (mm: depth, ahead of and behind the block), first
    element height and growth ratio, and probe points (x, z) in the block frame (mm).
    bulk_wlf: the rubber's relaxation times follow the current temperature cell by cell (WLF,
    eqs. 3.33, 3.37) where the compound is viscoelastic with WLF data; False keeps the bulk at T0.
    road_elastic: the road material (its E and nu) of a linear elastic road whose deflection under
    the contact forces moves the road surface each step (``road_deflection``); None: a rigid road
    (thesis 8.4.1).
    Defaults: thesis 8.3.1 (``THESIS_INTERFACE``: kappa = 1, h_c = 1e6)."""

    road: Thermal
    T0: float = 293.15
    interface: ThermalSettings = THESIS_INTERFACE
    road_depth: float = 10.0
    road_ahead: float = 2.0
    road_behind: float = 10.0
    first_layer: float = FIRST_LAYER
    grading: float = 1.2
    probes: tuple[tuple[float, float], ...] = ()
    bulk_wlf: bool = True
    road_elastic: Road | None = None  # elastic road of this material (road_deflection); None: rigid

    def __post_init__(self) -> None:
        V.instance("thermal.road", self.road, Thermal)
        V.positive("thermal.T0", self.T0, "K")
        V.instance("thermal.interface", self.interface, ThermalSettings)
        i = self.interface
        k = V.real("thermal.interface.kappa", i.kappa)
        if not 0.0 <= k <= 1.0:
            raise V.InputError(f"thermal.interface.kappa = {i.kappa!r}: expected a heat share in "
                               "[0, 1]")
        V.nonnegative("thermal.interface.h0", i.h0, "mW/(mm^2 K)")
        if i.h1 != 0.0 or i.master_temperature is not None:
            raise V.InputError(f"thermal.interface: h1 = {i.h1!r}, master_temperature = "
                               f"{i.master_temperature!r}: the macro scale takes a constant "
                               "conductance h0 between block and road (expected h1 = 0, None)")
        for name in ("road_depth", "first_layer"):
            V.positive(f"thermal.{name}", getattr(self, name), "mm")
        for name in ("road_ahead", "road_behind"):
            V.nonnegative(f"thermal.{name}", getattr(self, name), "mm")
        V.instance("thermal.road_elastic", self.road_elastic, Road, optional=True)


@dataclass
class ThermalMacroResult:
    """The mechanical result plus the thermal series (one row per sliding step): t, s, mu,
    T_contact (pressure-weighted mean block surface temperature over contact nodes), T_surface
    (mean over the whole block surface), T_max
    (hottest block surface node), T_road_behind (road surface one element behind the block),
    heat_block, heat_road (stored, mJ/mm), friction_energy (cumulative heat input, mJ/mm),
    contact_dissipation (the contact's cumulative frictional dissipation, mJ/mm), road_sink (mean
    road surface deflection u_z under the contact, pressure-weighted, mm; 0 on a rigid road),
    T_active (eq. 8.1 at the surface: the plain mean of the block surface temperature over
    the heat interface nodes in contact, K), probes (K); the final profiles along the interface;
    stats."""

    sliding: SlidingResult
    series: dict[str, np.ndarray] = field(default_factory=dict)
    profiles: dict[str, np.ndarray] = field(default_factory=dict)
    stats: dict[str, float] = field(default_factory=dict)
    heat: TwoBodyHeat | None = None  # the heat problem at the end (fields for output)
    # surface temperatures over time: x_block (n_b,), x_road (n_r,) in the block frame (mm),
    # T_block (steps, n_b) of the rubber surface, T_road (steps, n_r) of the road surface, K;
    # rows = series rows
    surface_history: dict[str, np.ndarray] = field(default_factory=dict)
    probe_dofs: list[int] = field(default_factory=list)  # heat dofs of settings.probes
    # the friction law's view of the contact per step (rows = series rows): T (steps, n_slave)
    # the slave nodes' temperature, K; load (steps, n_slave) their normal force, N/mm (0 where
    # not in contact); for the share of the load beyond a law's temperature range
    contact_loads: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.sliding.ok and "thermal_error" not in self.stats


class ThermalCoupler:
    """Observer of a SlidingRun that carries the heat problem along (see the module doc)."""

    def __init__(self, rubber: Thermal, settings: MacroSettings,
                 initial_block: np.ndarray | None = None) -> None:
        self.rubber, self.settings = rubber, settings
        # block temperatures carried from an earlier slide (or None: T0)
        self.initial_block = initial_block
        self.error: str | None = None
        self.heat: TwoBodyHeat | None = None
        self.bulk_map: sps.csr_matrix | None = None  # heat block grid -> mechanical cell centroids

    def on_start(self, run) -> None:
        """A new attempt starts sliding (the run's fallbacks restart it): a fresh heat problem at
        T0, with the carried block field of an earlier slide where there is one."""
        self.error = None
        s = self.settings
        slave = run.contact.slave
        X = slave.X
        z_face = float(X[:, 1].min())
        tol = 1e-9 * max(1.0, float(np.ptp(X[:, 0])))
        # the flat face (an arc rises above it)
        flat = np.sort(X[np.abs(X[:, 1] - z_face) < tol, 0])
        h_x = float(np.diff(flat).mean())
        if np.ptp(np.diff(flat)) > 1e-9 * h_x:
            raise RuntimeError("thermal macro run: the block's flat contact face must have equal "
                               "elements")
        self.x0 = float(X[:, 0].min())
        length = float(X[:, 0].max()) - self.x0
        if abs(length / h_x - round(length / h_x)) > 1e-6:
            raise V.InputError(f"thermal macro run: block length {length:g} mm is not a whole "
                               f"number of contact elements {h_x:g} mm (with a rounded edge: make "
                               "edge_radius a multiple of h_contact)")
        whole = lambda d: h_x * math.ceil(d / h_x - 1e-9)  # noqa: E731
        geo = HeatGeometry(block_length=h_x * round(length / h_x), block_height=float(run.H),
                           road_depth=s.road_depth, road_ahead=whole(s.road_ahead),
                           road_behind=whole(s.road_behind), h_x=h_x, first_layer=s.first_layer,
                           grading=s.grading)
        self.heat = TwoBodyHeat(geo, self.rubber, s.road, T0=s.T0, kappa=s.interface.kappa,
                                h_c=s.interface.h0, road_velocity=-float(run.spec.velocity),
                                top_temperature=s.T0)
        itf = self.heat.interface
        # slave node a -> interface node node_of[a] (nearest in x): one to one on a square block;
        # nodes of a rounded edge share the interface node below them (the heat block is square)
        self.slave_x = X[:, 0] - self.x0
        self.node_of = np.clip(np.searchsorted(0.5 * (itf.x[1:] + itf.x[:-1]), self.slave_x), 0,
                               len(itf.x) - 1)
        self.lump = sps.csr_matrix((np.ones(len(X)), (self.node_of, np.arange(len(X)))),
                                   shape=(len(itf.x), len(X)))
        self.count = np.asarray(self.lump.sum(axis=1)).ravel()
        on_face = np.abs(X[:, 1] - z_face) < tol
        if np.abs(itf.x[self.node_of[on_face]] - self.slave_x[on_face]).max() > tol:
            raise RuntimeError("thermal macro run: slave nodes and heat interface nodes do not "
                               "match")
        if self.initial_block is not None:
            if len(self.initial_block) != len(self.heat.block_dofs):
                raise RuntimeError("thermal macro run: the carried block temperature field does "
                                   "not fit the mesh")
            self.heat.T.x.array[self.heat.block_dofs] = self.initial_block
        self.probe_dofs = [self.heat.nearest_dof(px - self.x0, pz) for px, pz in s.probes]
        xr, _ = self.heat.road_surface()
        # road surface node one element behind the block
        self.behind = int(np.argmin(np.abs(xr + h_x)))
        self.rows: list[tuple] = []
        # per step: block and road surface T
        self.surface_rows: list[tuple[np.ndarray, np.ndarray]] = []
        self.load_rows: list[tuple[np.ndarray, np.ndarray]] = []  # (slave T, slave load) per step
        self.energy = self.dissipation = 0.0
        self.cpu_heat = 0.0
        self.max_rescale = 0.0  # largest |scale - 1| of the nodal power (0 without cut-backs)
        self.max_step_dT = 0.0
        self.T_active_max = float("nan")  # hottest contact node the friction law saw, K
        Tb, _ = self.heat.interface_temperatures()
        self._T_prev = Tb
        run.contact.set_slave_temperatures(self._slave_temperatures(Tb))
        self.road = None
        self.road_sink = 0.0
        if s.road_elastic is not None:
            self._start_elastic_road(run, h_x, length)
        history = getattr(run.sp, "history", None)
        self.bulk_map = None  # bilinear, built only where the bulk follows the temperature
        if (s.bulk_wlf and history is not None
                and getattr(run.spec.compound, "wlf", None) is not None):
            c = run.sp.cell_centroids()
            self.bulk_map = _bilinear_map(*self.heat.block_grid()[:2], c[:, 0] - self.x0,
                                          c[:, 1] - z_face)
            self._update_bulk(run)

    def on_step(self, run, k: int, t: float) -> None:
        if self.error is not None:
            return
        try:
            self._step(run, t)
        except Exception as err:  # noqa: BLE001 -- reported as a failed thermal run
            self.error = f"{type(err).__name__}: {err}"

    def interface_active(self, state: dict) -> np.ndarray:
        """Contact mask per heat interface node: in contact where any slave node lumped onto it
        is."""
        return (self.lump @ state["active"].astype(float)) > 0.0

    def _slave_temperatures(self, Tb: np.ndarray) -> np.ndarray:
        """Interface temperatures at the slave nodes (linear in x; exact on the flat face)."""
        return np.interp(self.slave_x, self.heat.interface.x, Tb)

    def _step(self, run, t: float) -> None:
        st = run.contact.state()
        L = self.lump
        power = L @ (st["friction_power_density"] * st["weight"])  # mW/mm per interface node
        active = self.interface_active(st)
        dt = float(run.dt_slide)
        # a step cut back into sub-steps: the state is the last sub-step's; scale its power so the
        # heat of the step is the frictional dissipation of all its sub-steps
        # (run.step_friction_energy)
        step_energy = float(run.step_friction_energy)
        if power.sum() > 0.0 and step_energy > 0.0:
            scale = step_energy / (float(power.sum()) * dt)
            self.max_rescale = max(self.max_rescale, abs(scale - 1.0))
            power = power * scale
        t_heat = time.process_time()
        self.heat.step(dt, power, active)
        self.cpu_heat += time.process_time() - t_heat
        self.energy += float(power.sum()) * dt
        self.dissipation += step_energy
        Tb, _ = self.heat.interface_temperatures()
        slave_T = self._slave_temperatures(Tb)
        run.contact.set_slave_temperatures(slave_T)
        if self.bulk_map is not None:
            self._update_bulk(run)
        if self.road is not None:
            self._deflect_road(run, st, t)
        p = st["pressure"] * st["weight"] * st["active"]
        T_contact = float(p @ slave_T / p.sum()) if p.sum() > 0 else float("nan")
        T_active = float(Tb[active].mean()) if active.any() else float("nan")  # eq. (8.1), z = 0
        if np.any(st["active"] > 0):
            self.T_active_max = float(np.fmax(self.T_active_max,
                                              np.max(slave_T[st["active"] > 0])))
        self.max_step_dT = max(self.max_step_dT, float(np.max(np.abs(Tb - self._T_prev))))
        self._T_prev = Tb
        _, Tr = self.heat.road_surface()
        eb, er = self.heat.heat_content()
        mu = -st["Fx"] / st["Fz"] if st["Fz"] else float("nan")
        self.surface_rows.append((Tb, Tr))
        self.load_rows.append((slave_T, p))
        self.rows.append((t, float(run.spec.velocity) * (t - run.t_start), mu, T_contact,
                          float(Tb.mean()), float(Tb.max()), float(Tr[self.behind]), eb, er,
                          self.energy, self.dissipation, self.road_sink, T_active,
                          *[float(self.heat.T.x.array[d]) for d in self.probe_dofs]))
        mean = lambda v: (L @ v) / np.maximum(self.count, 1.0)  # noqa: E731 -- per interface node
        self._last = {"x": self.heat.interface.x + self.x0, "T_block": Tb,
                      "pressure": mean(st["pressure"]),
                      "power": power / self.heat.interface.weights, "mu": mean(st["mu"])}

    def _start_elastic_road(self, run, h_x: float, length: float) -> None:
        """The elastic road (``road_deflection``) under the block and the road's master polyline
        refined to h_x / 2 (the deflection needs vertices to move); loaded by the compressed
        state."""
        s = self.settings
        margin = s.road_depth  # the clamped ends stay a road depth away from the block
        self.road = ElasticRoad(self.x0 - s.road_behind - margin,
                                self.x0 + length + s.road_ahead + margin, s.road_depth,
                                s.road_elastic, h_x=h_x, first_layer=s.first_layer,
                                grading=s.grading)
        m = run.contact.master
        x = np.union1d(m.vertices[:, 0], np.arange(m.vertices[0, 0], m.vertices[-1, 0], 0.5 * h_x))
        self.master_base = np.column_stack([x, np.interp(x, m.vertices[:, 0], m.vertices[:, 1])])
        self._deflect_road(run, run.contact.state(), run.t_start)

    def _deflect_road(self, run, st: dict, t: float) -> None:
        """Road deflection under the reversed slave nodal contact forces at the slave's current x;
        the master moves with it for the next step (offset of the step's end, -v (t + dt - t_s))."""
        n, p, w = st["normal"], st["pressure"], st["weight"]
        tangent = np.column_stack([n[:, 1], -n[:, 0]])
        f_slave = w[:, None] * (-p[:, None] * n + st["tangential_traction"][:, None] * tangent)
        # open or unpaired nodes carry nothing (their frame may be undefined)
        f_slave[~st["active"]] = 0.0
        d = run.contact.slave.dofs
        x = run.contact.slave.X[:, 0] + run.sp.w.x.array[d[:, 0]]
        self.road.deflect(x, -f_slave)
        on = st["active"] & (p > 0)
        sink = (float((p * w)[on] @ self.road.at(x[on])[:, 1] / (p * w)[on].sum()) if on.any()
                else 0.0)
        # the block follows the road's sink rigidly (Newton's start only): a road that moved away
        # by more than the penalty penetration would leave a load-controlled block without contact
        run.sp.w.x.array[run.sp.displacement_dofs()[:, 1]] += sink - self.road_sink
        self.road_sink = sink
        offset = -float(run.spec.velocity) * (t + float(run.dt_slide) - float(run.t_start))
        base = self.master_base
        moved = base + self.road.at(base[:, 0] + offset)
        run.contact.set_rigid_master(RigidMaster(moved, run.contact.master.period))

    def _update_bulk(self, run) -> None:
        """Cell temperatures of the mechanical block from the heat field (WLF shift per cell)."""
        T_cell = self.bulk_map @ self.heat.block_grid()[2].ravel()
        run.sp.set_temperature(T_cell)
        self.bulk_T_max = float(T_cell.max())


def _bilinear_map(xs: np.ndarray, zs: np.ndarray, x: np.ndarray, z: np.ndarray) -> sps.csr_matrix:
    """Sparse (n_points, n_x n_z) bilinear interpolation on the tensor grid xs x zs (flat index
    i n_z + j) at the points (x, z), clipped into the grid; exact for bilinear fields."""
    def cell(grid, v):
        i = np.clip(np.searchsorted(grid, v, side="right") - 1, 0, len(grid) - 2)
        t = np.clip((v - grid[i]) / (grid[i + 1] - grid[i]), 0.0, 1.0)
        return i, t
    i, tx = cell(xs, x)
    j, tz = cell(zs, z)
    nz, n = len(zs), len(x)
    rows = np.repeat(np.arange(n), 4)
    cols = np.column_stack([i * nz + j, (i + 1) * nz + j, i * nz + j + 1,
                            (i + 1) * nz + j + 1]).ravel()
    w = np.column_stack([(1 - tx) * (1 - tz), tx * (1 - tz), (1 - tx) * tz, tx * tz]).ravel()
    return sps.csr_matrix((w, (rows, cols)), shape=(n, len(xs) * nz))


def run_thermal_macro(spec: SlidingSpec, rubber: Thermal, settings: MacroSettings, *,
                      observers=(), wall_limit: float = 0.0,
                      initial_block: np.ndarray | None = None,
                      coupler: ThermalCoupler | None = None, progress=None) -> ThermalMacroResult:
    """One thermomechanical macro run (see the module doc).  The spec must be non-periodic
    (period = 0: a finite block over a road longer than the slide).  Bulk and contact start at
    ``settings.T0``; then the heat field sets the contact temperature and, with
    ``settings.bulk_wlf``, the WLF shift of every cell (stats ``bulk_wlf``, ``bulk_T_max``).
    ``coupler``: a ThermalCoupler of these settings made by the caller (observers after it may
    read its heat problem, as the thermal loop does); default: a new one.  ``progress(k, n)``:
    called after sliding step k of n (long slides)."""
    V.instance("rubber thermal data", rubber, Thermal)
    if spec.period > 0:
        raise V.InputError("thermal macro run: the block must be finite (period = 0)")
    if spec.temperature != settings.T0:
        # bulk (WLF shift) and contact start at T0; the heat solver then owns the contact
        # temperature
        spec = replace(spec, temperature=float(settings.T0))
    if coupler is None:
        coupler = ThermalCoupler(rubber, settings, initial_block)
    run = SlidingRun(spec, block_mesh, sliding_contact, progress=progress,
                     observers=(coupler, *observers), wall_limit=wall_limit)
    res = run.run()
    out = ThermalMacroResult(res)
    if coupler.error is not None:
        out.stats["thermal_error"] = coupler.error
        return out
    if coupler.heat is None:
        return out
    cols = ["t", "s", "mu", "T_contact", "T_surface", "T_max", "T_road_behind", "heat_block",
            "heat_road", "friction_energy", "contact_dissipation", "road_sink", "T_active"]
    cols += [f"probe_{i}" for i in range(len(settings.probes))]
    arr = np.array(coupler.rows, float).reshape(-1, len(cols))
    out.series = {c: arr[:, i] for i, c in enumerate(cols)}
    out.profiles = getattr(coupler, "_last", {})
    if coupler.load_rows:
        out.contact_loads = {"T": np.array([r[0] for r in coupler.load_rows]),
                             "load": np.array([r[1] for r in coupler.load_rows])}
    if coupler.surface_rows:
        xr, _ = coupler.heat.road_surface()
        out.surface_history = {"x_block": coupler.heat.interface.x + coupler.x0,
                               "x_road": xr + coupler.x0,
                               "T_block": np.array([r[0] for r in coupler.surface_rows]),
                               "T_road": np.array([r[1] for r in coupler.surface_rows])}
    out.heat = coupler.heat
    out.probe_dofs = coupler.probe_dofs
    out.stats.update({"max_step_dT": coupler.max_step_dT, "heat_dofs": float(len(coupler.heat.X)),
                      "cpu_heat": coupler.cpu_heat, "max_power_rescale": coupler.max_rescale,
                      "heat_description": coupler.heat.describe(),
                      "bulk_wlf": float(coupler.bulk_map is not None),
                      "bulk_T_max": getattr(coupler, "bulk_T_max", float("nan")),
                      "T_contact_max": coupler.T_active_max})
    return out


@dataclass
class ThermalSlidesResult:
    """Repeated slides (thesis 8.5.2): one result per slide, and the history of the whole sequence
    (global time, slide number (0 in a pause), mean rubber surface temperature, probes)."""

    slides: list[ThermalMacroResult]
    history: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return len(self.slides) > 0 and all(r.ok for r in self.slides)


def run_thermal_slides(spec: SlidingSpec, rubber: Thermal, settings: MacroSettings,
                       pauses: tuple[float, ...] = (), *, pause_steps: int = 40,
                       wall_limit: float = 0.0, progress=None) -> ThermalSlidesResult:
    """Slides of ``spec`` one after another with a pause (s) between two (len(pauses) + 1 slides),
    as the bulk study of thesis 8.5.2: the block is lifted during a pause (no contact, conduction
    only, top at T0) and keeps its temperature field into the next slide; the road under it is
    fresh at T0 each slide (as the thesis resets the road).  Pause steps grow geometrically (the
    surface cools fastest first).  History times count sliding and pauses (the compression before
    each slide is not counted).  Stops at the first failed slide.  ``progress(slide, k, n)``: called
    after sliding step k of n of a slide."""
    pauses = tuple(V.nonnegative("pause", p, "s") for p in pauses)
    slides, rows, carried, t_global = [], [], None, 0.0
    for i in range(len(pauses) + 1):
        res = run_thermal_macro(spec, rubber, settings, wall_limit=wall_limit,
                                initial_block=carried,
                                progress=None if progress is None
                                else (lambda k, n, i=i: progress(i + 1, k, n)))
        slides.append(res)
        if not res.ok or res.heat is None:
            break
        s = res.series
        t_slide = s["s"] / spec.velocity  # time since this slide's sliding started
        probe_cols = [k for k in s if k.startswith("probe_")]
        for k in range(len(t_slide)):
            rows.append((t_global + t_slide[k], i + 1, s["T_surface"][k],
                         *[s[c][k] for c in probe_cols]))
        t_global += float(t_slide[-1])
        heat = res.heat
        if i < len(pauses) and pauses[i] > 0:
            for dt in geometric_steps(pauses[i], pause_steps):
                heat.step(float(dt), 0.0, False)
                t_global += float(dt)
                Tb, _ = heat.interface_temperatures()
                rows.append((t_global, 0, float(Tb.mean()),
                             *[float(heat.T.x.array[d]) for d in res.probe_dofs]))
        carried = heat.T.x.array[heat.block_dofs].copy()
    cols = ["t", "slide", "T_surface"] + [f"probe_{j}" for j in range(len(settings.probes))]
    arr = np.array(rows, float).reshape(-1, len(cols))
    return ThermalSlidesResult(slides, {c: arr[:, j] for j, c in enumerate(cols)})


def flat_road_spec(compound, *, pressure: float, velocity: float, friction, block_length: float,
                   block_height: float, slide_distance: float, h_contact: float, T0: float,
                   step_per_element: float = 0.5, **numerics) -> SlidingSpec:
    """The mechanical spec of a macro block sliding over a flat rigid road long enough for the
    slide (non-periodic); ``numerics``: further SlidingSpec fields (element, contact, ...)."""
    span = slide_distance + block_length
    return SlidingSpec(surface_x=np.array([-span, 2.0 * span]), surface_h=np.zeros(2), period=0.0,
                       pressure=pressure, velocity=velocity, compound=compound,
                       block_length=block_length, block_height=block_height, temperature=T0,
                       friction=friction, h_contact=h_contact, slide_distance=slide_distance,
                       step_length=step_per_element * h_contact, **numerics)
