"""Python face of the C++ contact module (``rubberfriction._contact``).

A :class:`Contact` joins one deformable slave surface (the rubber block's contact face) to one
master: a rigid polyline (a road-profile sample, optionally periodic with period L, moved rigidly
by an offset set per step) or the boundary of a second deformable body.  Search, projection,
mortar integration, the friction and thermal laws and the assembly into PETSc all run in C++;
Python passes plain arrays once and calls :meth:`Contact.assemble` (or :meth:`Contact.hook`)
every Newton iteration.  Python never loops over segments.

Conventions
-----------
* Units mm, s, t, N, MPa, mJ, K.  Plane strain x-z stored as (x, y).  Forces are per mm depth.
* Residual R(u) = F_int - F_ext; the contact ADDS dPi_c/du into b and its consistent (not
  symmetric) tangent into A with ADD_VALUES at global dof indices; Newton solves J du = -R.
* Orientation, slave and deformable master: segments (a, b) run counter-clockwise around their
  own body (body on the left, outward normal n = (t_z, -t_x)/|t|): the bottom face of a block
  runs in +x with n = -z.  ``SolidProblem.boundary(tag)`` returns segments in this order.
  Rigid polyline: the rigid body lies on the right of the vertex order (a road profile given with
  increasing x, material below, n = +z).
* Gap g >= 0 open; pressure p = c_N <-g> >= 0.  Mortar (thesis 5.38): g_A = (gbar_A . n_A)/A_A
  with the nodal weight A_A = Int M_A da, so c_N has units MPa/mm like node-to-segment.
* Friction: tangential penalty c_T and Coulomb return mapping (4.17, 4.18) per slave node;
  history (elastic tangential gap, positions of the last converged step) changes only in
  :meth:`Contact.commit`.  Sliding velocity v = |slip increment|/dt.
* Forces reported by :meth:`Contact.state` act ON THE SLAVE body: F_z > 0 when the road pushes
  the block up, F_x < 0 when the block slides in +x relative to the road.
* Thermal (4.24-4.26, 5.44, 5.45): conductance h_c(p) = h0 + h1 p^beta across the thermal gap
  where the node is in contact; frictional heat w = |t_T| dgamma/dt split kappa (slave) and
  1 - kappa (master).

Penalty rule (automatic, default)
---------------------------------
c_N = alpha E_eff / h_min with alpha = DEFAULT_ALPHA, E_eff the plane-strain modulus of the
slave body (instantaneous for viscoelastic rubber, passed by the caller) and h_min the shortest
reference slave (and deformable-master) segment; c_T = DEFAULT_TANGENTIAL_FRACTION * c_N.
The penalty gap p/c_N is then p h_min/(alpha E_eff): a fraction 1/alpha of the element size per
unit strain p/E_eff.  Why alpha = 10 and c_T = 0.1 c_N: the verification cases (Hertz, Westergaard,
sliding block) stay within their tolerances with it (the patch test is exact for any penalty),
while stiffer choices (alpha = 50, c_T = 0.5 c_N) made Newton stall in frictional sliding over
rough profiles (``rubberfriction bench contact``): a very narrow stick cone makes nodes switch
between stick and slip from one iteration to the next.  Both can be overridden;
:meth:`Contact.report` states the choice.

Parallel: each run is serial on its own communicator (MPI farming); a communicator or PETSc
object with more than one rank is refused with a clear message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from petsc4py import PETSc

from rubberfriction import _contact
from rubberfriction.driver.fe.friction_law import as_cpp_law

#: Automatic normal penalty factor alpha in c_N = alpha E_eff / h_min.
DEFAULT_ALPHA = 10.0
#: Automatic tangential penalty c_T = fraction * c_N.
DEFAULT_TANGENTIAL_FRACTION = 0.1
#: Contact methods by the names Contact accepts (value: the canonical name).
METHODS = {"mortar": "mortar", "nts": "nts", "node_to_segment": "nts", "surface": "surface",
           "node_to_surface": "surface"}
#: Gauss points per mortar integration segment (exact for the patch test from 2 on).
DEFAULT_GAUSS_POINTS = 4
#: contact frames (``Contact(frame=...)``): the averaged slave normal, or the master's normal
FRAMES = ("slave", "master")


@dataclass(frozen=True)
class PenaltySettings:
    """Penalty choice: automatic (alpha, tangential_fraction) unless c_N is given."""

    alpha: float = DEFAULT_ALPHA
    tangential_fraction: float = DEFAULT_TANGENTIAL_FRACTION
    c_N: float | None = None  # MPa/mm; overrides the automatic rule
    c_T: float | None = None  # MPa/mm; default tangential_fraction * c_N


@dataclass(frozen=True)
class ThermalSettings:
    """The thermal interface (eqs. 4.24-4.26): conductance h_c(p) = h0 + h1 p^beta
    [mW/(mm^2 K)] where in contact, frictional heat share kappa to the slave (the rubber).

    One type for the contact here and the thermal macro scale (``thermal.macro.MacroSettings``,
    constant h_c = h0).  kappa has no default: every caller states its heat share.
    """

    h0: float
    kappa: float
    h1: float = 0.0
    beta: float = 1.0
    master_temperature: float | None = None  # K, rigid master only (None: no conduction)


@dataclass
class SlaveSurface:
    """Slave surface arrays: X (n, 2) reference coordinates, dofs (n, 2) global (u_x, u_z) dofs,
    segments (m, 2) node pairs (counter-clockwise around the body), optional temperature dofs (n,)
    and optional interior points (m, 2), one point inside the body per segment, to check the
    orientation.  ``periodic_seam``: the chain's two ends are one point of a periodic cell (tied by
    its constraint, eq. 6.5) and keep the one-sided slave normal; any other chain end is a vertex
    of the body and takes the master's normal (``contact_interface.cpp``, nodal_kinematics)."""

    X: np.ndarray
    dofs: np.ndarray
    segments: np.ndarray
    temperature_dofs: np.ndarray | None = None
    interior_points: np.ndarray | None = None
    periodic_seam: bool = False

    @classmethod
    def from_boundary(cls, boundary, temperature_dofs=None,
                      periodic_seam: bool = False) -> "SlaveSurface":
        """From ``SolidProblem.boundary(tag)`` (``BoundaryNodes``: X, dofs, segments)."""
        return cls(np.asarray(boundary.X, float), np.asarray(boundary.dofs),
                   np.asarray(boundary.segments),
                   None if temperature_dofs is None else np.asarray(temperature_dofs),
                   periodic_seam=periodic_seam)


@dataclass
class RigidMaster:
    """Rigid polyline: vertices (k, 2); period L > 0 for a periodic sample (one period given,
    the segment from the last vertex to the first shifted by L closes it; a duplicated closing
    vertex is dropped), 0 for an open polyline."""

    vertices: np.ndarray
    period: float = 0.0


@dataclass
class DeformableMaster:
    """Boundary of a second deformable body (same layout and orientation rule as the slave)."""

    X: np.ndarray
    dofs: np.ndarray
    segments: np.ndarray
    temperature_dofs: np.ndarray | None = None
    interior_points: np.ndarray | None = None

    @classmethod
    def from_boundary(cls, boundary, temperature_dofs=None) -> "DeformableMaster":
        return cls(np.asarray(boundary.X, float), np.asarray(boundary.dofs),
                   np.asarray(boundary.segments),
                   None if temperature_dofs is None else np.asarray(temperature_dofs))


def _check_serial(comm) -> None:
    if comm is not None and comm.size > 1:
        raise ValueError(
            f"contact: the communicator has {comm.size} ranks; the contact module runs serially on "
            "its own communicator (farm runs over ranks with MPI.COMM_SELF per run). Distributed "
            "meshes are not supported.")


class Contact:
    """One contact interface (see the module docstring for conventions).

    Parameters
    ----------
    slave: SlaveSurface.  master: RigidMaster or DeformableMaster.
    method: "mortar" (segment-to-segment, default), "nts" (node-to-segment: the same interface
        collocated at the slave nodes, cheaper, the fallback when a mortar run fails) or
        "surface" (node-to-surface: slave nodes against the C2 periodic spline through a rigid
        periodic master sampled at uniform x; the penalty force is the gradient of a potential,
        so a step has an equilibrium however sharp the road's peaks are against the elements;
        ``cpp_contact/height_field.hpp``).
    friction: None (frictionless), a number mu, a SplineLaw or a ``_contact.FrictionLaw``.
    E_eff: plane-strain modulus of the slave body [MPa] for the automatic penalty.
    penalty: PenaltySettings.  thermal: ThermalSettings or None.
    search_radius: normal distance within which slave and master are paired [mm]
        (default 2 x the longest slave segment).
    fixed_dofs: dofs whose rows and columns the contact skips (Dirichlet dofs handled by the FE
        side); leave empty when constraints are condensed afterwards (P^T A P).
    allow_new_nonzeros: do not error on couplings missing from the matrix pattern (PETSc then
        mallocs; the count is reported by :meth:`assemble`).
    frame: "slave" (the averaged slave normal of eq. 5.36 at every node but a chain end, whose frame
        is the master's) or "master" (every node's frame is the master's normal averaged over its
        support: pressure along the road's normal, friction along its tangent however the slave
        bends; the sharp-cornered block, ``verify sliding-block --edge-radius 0``).
    comm: the run's communicator (must have one rank).
    """

    def __init__(self, slave: SlaveSurface, master, *, method: str = "mortar", friction=None,
                 E_eff: float | None = None, penalty: PenaltySettings | None = None,
                 thermal: ThermalSettings | None = None, search_radius: float | None = None,
                 gauss_points: int = DEFAULT_GAUSS_POINTS, fixed_dofs=None,
                 allow_new_nonzeros: bool = False, frame: str = "slave", comm=None):
        _check_serial(comm)
        if method not in METHODS:
            raise ValueError(f"method: got {method!r}, expected one of "
                             f"{sorted(set(METHODS.values()))}")
        self.method = METHODS[method]
        self.slave = slave
        self.master = master
        self._c = _contact.ContactInterface(
            np.asarray(slave.X, float), np.asarray(slave.dofs, np.int64),
            np.asarray(slave.segments, np.int64),
            None if slave.temperature_dofs is None
            else np.asarray(slave.temperature_dofs, np.int64),
            None if slave.interior_points is None else np.asarray(slave.interior_points, float),
            self.method)  # the binding takes the short names
        self._c.set_periodic_seam(bool(slave.periodic_seam))
        if frame not in FRAMES:
            raise ValueError(f"frame: got {frame!r}, expected one of {FRAMES}")
        self.frame = frame
        self._c.set_master_frame(frame == "master")
        if isinstance(master, RigidMaster):
            self._c.set_rigid_master(np.asarray(master.vertices, float), float(master.period))
        elif isinstance(master, DeformableMaster):
            self._c.set_deformable_master(
                np.asarray(master.X, float), np.asarray(master.dofs, np.int64),
                np.asarray(master.segments, np.int64),
                None if master.temperature_dofs is None
                else np.asarray(master.temperature_dofs, np.int64),
                None if master.interior_points is None
                else np.asarray(master.interior_points, float))
        else:
            raise TypeError("master: expected RigidMaster or DeformableMaster, got "
                            f"{type(master)!r}")
        self.penalty = penalty or PenaltySettings()
        self._set_penalty(self.penalty, E_eff)
        self.friction = friction
        self._c.set_friction(as_cpp_law(friction))
        self.thermal = thermal
        if thermal is not None:
            Tm = (math.nan if thermal.master_temperature is None
                  else float(thermal.master_temperature))
            self._c.set_thermal(thermal.h0, thermal.h1, thermal.beta, thermal.kappa, Tm)
        if search_radius is not None:
            self._c.set_search_radius(float(search_radius))
        self._c.set_gauss_points(int(gauss_points))
        if fixed_dofs is not None:
            self._c.set_fixed_dofs(np.asarray(fixed_dofs, np.int64))
        self._c.set_allow_new_nonzeros(bool(allow_new_nonzeros))
        self.offset = (0.0, 0.0)
        self.dt = 0.0
        self.temperature = math.nan
        self.last_assembly: dict = {}

    def _set_penalty(self, pen: PenaltySettings, E_eff) -> None:
        if pen.c_N is not None:
            cT = pen.c_T if pen.c_T is not None else pen.tangential_fraction * pen.c_N
            self._c.set_penalty(float(pen.c_N), float(cT))
            return
        if E_eff is None:
            raise ValueError("E_eff: the automatic penalty c_N = alpha E_eff / h_min needs the "
                             "plane-strain modulus of the slave body (or give "
                             "PenaltySettings(c_N=...))")
        self._c.set_auto_penalty(float(E_eff), float(pen.alpha), float(pen.tangential_fraction))

    # --- per step ------------------------------------------------------------------------------
    def set_master_offset(self, dx: float, dz: float = 0.0) -> None:
        """Rigid translation of the rigid master for the current step [mm]."""
        self.offset = (float(dx), float(dz))

    def set_rigid_master(self, master: RigidMaster) -> None:
        """New geometry of the rigid master from the next evaluation on (same interface, slip
        history kept): a road surface that deforms between steps
        (``driver.thermal.road_deflection``)."""
        if not isinstance(self.master, RigidMaster) or not isinstance(master, RigidMaster):
            raise TypeError("set_rigid_master: the interface and the new master must both be rigid")
        self.master = master
        self._c.set_rigid_master(np.asarray(master.vertices, float), float(master.period))

    def set_time_step(self, dt: float) -> None:
        self.dt = float(dt)

    def set_friction(self, friction) -> None:
        """A new friction law (None, a float mu or a law object) from the next evaluation on; the
        slip history stays (the thermal loop hands a new mu to a running macro scale)."""
        self.friction = friction
        self._c.set_friction(as_cpp_law(friction))

    def set_temperature(self, T: float) -> None:
        """Contact temperature [K] for mu(p, v, T) when the slave has no temperature dofs."""
        self.temperature = float(T)

    def set_slave_temperatures(self, T: np.ndarray | None) -> None:
        """Temperature [K] of each slave node for mu(p, v, T), overriding ``set_temperature``
        (staggered thermomechanical coupling: the heat solver owns the field); None: back to the
        one contact temperature."""
        self._c.set_slave_temperatures(None if T is None else np.asarray(T, float))

    def _kw(self, offset, dt, temperature) -> dict:
        return {"offset": self.offset if offset is None else (float(offset[0]), float(offset[1])),
                "dt": self.dt if dt is None else float(dt),
                "temperature": self.temperature if temperature is None else float(temperature)}

    # --- per Newton iteration ------------------------------------------------------------------
    def assemble(self, u: np.ndarray, A=None, b=None, *, offset=None, dt=None,
                 temperature=None) -> dict:
        """Search, project and ADD the contact residual into b and tangent into A at u.

        u: full local solution array (float64) indexed by the dof indices.  A, b: petsc4py Mat/Vec
        or None to skip (any other type, an integer handle too, raises TypeError).
        offset/dt/temperature default to the values set with set_master_offset / set_time_step /
        set_temperature.  Returns {'mallocs', 'entries'}; A still needs the caller's final
        MatAssembly.
        """
        self.last_assembly = self._c.assemble(np.ascontiguousarray(u, dtype=float), A, b,
                                              **self._kw(offset, dt, temperature))
        return self.last_assembly

    def hook(self, x: np.ndarray, A, b) -> None:
        """Newton hook signature ``hook(x, A, b)`` of ``driver.fe.newton``."""
        self.assemble(x, A, b)

    def evaluate(self, u: np.ndarray, *, offset=None, dt=None, temperature=None) -> dict:
        """Evaluate at u without assembling; returns :meth:`state`."""
        self._c.evaluate(np.ascontiguousarray(u, dtype=float), **self._kw(offset, dt, temperature))
        return self.state()

    def local_system(self, u: np.ndarray, *, offset=None, dt=None, temperature=None):
        """(res_rows, res_vals, J_rows, J_cols, J_vals) COO triplets (sum duplicates)."""
        return self._c.local_system(np.ascontiguousarray(u, dtype=float),
                                    **self._kw(offset, dt, temperature))

    def slave_forces(self, u: np.ndarray) -> np.ndarray:
        """The force the master exerts on each slave node at u, (n_slave, 2) [N/mm]: minus the
        contact residual at the slave's (u_x, u_z) dofs, with the offset, time step and history
        set now (the mortar distribution D_AB P_A of the nodal tractions, not a lumped one)."""
        rows, vals = self.local_system(u)[:2]
        r = np.zeros(np.asarray(u).size)
        np.add.at(r, np.asarray(rows, dtype=np.int64), np.asarray(vals, dtype=float))
        return -r[np.asarray(self.slave.dofs, dtype=np.int64)]

    def commit(self, u: np.ndarray | None = None) -> None:
        """Accept the step: re-evaluate at u if given, then store the history (elastic tangential
        gaps, positions, master offset)."""
        if u is not None:
            self.evaluate(u)
        self._c.commit()

    def reset_history(self, u: np.ndarray, offset=(0.0, 0.0),
                      elastic_gap: np.ndarray | None = None) -> None:
        """Take u and offset as the last converged state; the tangential history (committed
        elastic gaps per slave node, :meth:`elastic_gap`) is ``elastic_gap``, or none."""
        self._c.reset_history(np.ascontiguousarray(u, dtype=float),
                              (float(offset[0]), float(offset[1])))
        if elastic_gap is not None:
            self._c.set_elastic_gap(np.asarray(elastic_gap, dtype=float))

    def elastic_gap(self) -> np.ndarray:
        """The committed tangential elastic gap of every slave node (0 where open): the stick
        history a run that slides on from this state needs (:meth:`reset_history`)."""
        return np.asarray(self._c.committed_elastic_gap(), dtype=float).copy()

    # --- outputs -------------------------------------------------------------------------------
    def state(self) -> dict:
        """Results of the last evaluation.

        Per slave node (arrays): status (0 open, 1 stick, 2 slip), active, paired, gap (NaN where
        no master within the search radius), pressure, tangential_traction, slip_increment,
        tangential_increment, slip_velocity, mu, weight (A_A), heat_flux_slave/master, normal,
        friction_power_density (|t_T| dgamma/dt, mW/mm^2; times weight: the node's frictional
        power).
        Scalars: contact_length (sum of A_A over active nodes, the contact area per unit depth),
        force_x/Fx, force_z/Fz (on the slave), mean_pressure (weighted over active nodes),
        dissipation (frictional, this step, mJ/mm), friction_power, heat_slave/master (mW/mm),
        counts and timings.
        """
        s = self._c.state()
        active = s["status"] > 0
        s["active"] = active
        s["Fx"], s["Fz"] = s["force_x"], s["force_z"]
        w = s["weight"][active]
        s["mean_pressure"] = (float(np.sum(w * s["pressure"][active]) / w.sum())
                              if w.size and w.sum() > 0 else 0.0)
        return s

    def couplings(self, margin: float | None = None, u: np.ndarray | None = None) -> list:
        """Every coupling the contact may write, as ``[(rows, cols)]`` element-wise pair arrays --
        the ``extra_couplings`` of ``driver.fe.newton``.  Rigid master: slave dofs within chain
        distance 3 (static).  Deformable master: plus master nodes within `margin` (default 2 x
        search radius) of the slave at u; sliding beyond that needs a new pattern or
        ``allow_new_nonzeros``."""
        return [self.sparsity_pairs(margin, u)]

    def coupling_blocks(self, margin: float | None = None, u: np.ndarray | None = None) -> list:
        """The same couplings as a list of dense (rows, cols) blocks (one or two per slave node)."""
        return [(r, c) for r, c in self._c.sparsity_blocks(
            None if u is None else np.asarray(u, float),
            -1.0 if margin is None else float(margin))]

    def sparsity_pairs(self, margin: float | None = None, u: np.ndarray | None = None):
        """(rows, cols) arrays (PETSc.IntType) of every entry the contact may write."""
        r, c = self._c.sparsity_pairs(None if u is None else np.asarray(u, float),
                                      -1.0 if margin is None else float(margin))
        return r.astype(PETSc.IntType), c.astype(PETSc.IntType)

    def report(self) -> dict:
        """The set-up as a dict (method, penalty choice, friction, thermal, search, surfaces)."""
        return self._c.report()

    def report_text(self) -> str:
        r = self.report()
        p = r["penalty"]
        if p["automatic"]:
            pen = (f"c_N = alpha E_eff / h_min = {p['alpha']:g} x {p['E_eff']:.6g} MPa / "
                   f"{p['h_min']:.6g} mm = {p['c_N']:.6g} MPa/mm (automatic), c_T = "
                   f"{p['tangential_fraction']:g} c_N = {p['c_T']:.6g} MPa/mm")
        else:
            pen = f"c_N = {p['c_N']:.6g} MPa/mm, c_T = {p['c_T']:.6g} MPa/mm (user)"
        m = r["master"]
        master = (f"rigid polyline, {m['segments']} segments"
                  + (f", periodic L = {m['period']:g} mm" if m["period"] > 0 else "")
                  if m["type"] == "rigid" else f"deformable surface, {m['segments']} segments")
        lines = [f"contact: {r['method']}, slave {r['slave']['segments']} segments, "
                 f"master {master}",
                 f"  penalty: {pen}",
                 f"  friction: {r['friction'] or 'none'}",
                 f"  thermal: {r['thermal'] or 'none'}",
                 f"  search radius {r['search_radius']:.6g} mm, {r['gauss_points']} Gauss points "
                 "per segment"]
        return "\n".join(lines)

    @property
    def cpp(self) -> _contact.ContactInterface:
        return self._c
