"""What a single-scale sliding run depends on and what it returns (plain data).

:class:`SlidingSpec` is everything a run's result depends on (the campaign store hashes it);
:class:`SlidingResult` is what the run returns.  The element-size rule, the refined fallback spec
and the automatic normal penalty's modulus are functions of the spec alone, so they live here.
"""

from __future__ import annotations

import hashlib
import math
import numbers
from dataclasses import dataclass, field, replace

import numpy as np

from rubberfriction.driver.sliding.sinusoid import effective_modulus
from rubberfriction.driver.sliding.temperature import surface_temperature
from rubberfriction.meshes.block import polyline_element_size
from rubberfriction.meshes.common import contact_divisions
from rubberfriction.meshes.grading import geometric_sizes


@dataclass(frozen=True, eq=False)
class InitialState:
    """Where a run starts instead of from rest: the final state of an earlier run on the same
    mesh (the thermal loop's warm start, ``driver.multiscale.thermal_loop``).  The run skips the
    initial contact and the compression and slides on from this state under its own load,
    temperatures and friction; its first period then counts in the window rule (no run-in from
    rest, ``window.converged_window``).  Plain arrays, hashed into the run's key by their bytes.

    ``source``: the store key of the run it comes from (provenance); ``w``: the full solution
    array (displacements and cell pressures); ``history``, ``sbar``: the Prony histories H^k and
    DEV{Sbar} of the last converged step (``forms.viscoelastic.ViscoelasticHistory``);
    ``offset``: the road's offset then, in [0, period); ``mesh``: the sha256 of the mesh's node
    coordinates (:func:`mesh_digest`): a state fits only the mesh it was computed on;
    ``elastic_gap``: the contact's committed tangential elastic gap per slave node (the stick
    history of a frictional run, ``fe.contact.Contact.elastic_gap``; empty: none); ``refine``:
    the mesh refinement of the attempt that computed it (``refined``; > 1: that run converged
    only on a fallback's finer mesh, so the run sliding on from it starts there)."""

    source: str
    w: np.ndarray
    history: np.ndarray
    sbar: np.ndarray
    offset: float = 0.0
    mesh: str = ""
    elastic_gap: np.ndarray = field(default_factory=lambda: np.zeros(0))
    refine: int = 1

    @classmethod
    def stored(cls, fields: dict, source: str) -> "InitialState":
        """The state a store kept (``runtime.store.Store.load_state``) of the run ``source``."""
        return cls(**{**fields, "source": source, "refine": int(fields.get("refine", 1))})


def mesh_digest(node_X: np.ndarray) -> str:
    """sha256 of a mesh's node coordinates (``InitialState.mesh``)."""
    return hashlib.sha256(np.ascontiguousarray(node_X, dtype=float).tobytes()).hexdigest()


@dataclass(frozen=True)
class SlidingSpec:
    """Everything a sliding run depends on (plain data; hashed by the campaign store).

    Lengths mm, pressure MPa, velocity mm/s, time s, temperature K.
    """

    surface_x: np.ndarray  # master polyline vertices (one period if periodic), z = surface_h
    surface_h: np.ndarray
    period: float  # > 0: periodic master and periodic cell of this length
    pressure: float
    velocity: float
    compound: object  # rubberfriction.forms.compound.Compound
    block_length: float = 0.0  # 0: = period (micro cell)
    block_height: float = 0.0  # 0: = block_length (thesis 6.2.2)
    edge_radius: float = 0.0  # rounded leading (+x, front when sliding) edge of a finite block, mm
    temperature: float | None = None  # K; None: the WLF reference temperature
    # stepwise constant temperature over the block height (thesis 8.3.3,
    # driver.sliding.temperature): (thickness mm, T K) layers from the contact face upwards,
    # `temperature` above the last
    temperature_layers: tuple[tuple[float, float], ...] = ()
    friction: object = None  # None (frictionless), a float mu, or a friction law object
    element: str = "Q1P0"
    contact: str = "mortar"  # "nts" or "surface" (periodic samples; driver.fe.contact.Contact)
    # "master": every node's frame is the road's normal (Contact(frame=))
    contact_frame: str = "slave"
    h_contact: float = 0.0  # contact-face element size; 0: from the surface (see mesh_size)
    elements_per_wavelength: int = 16
    grading: float = 1.15  # growth ratio of element height away from the contact face
    slide_distance: float = 0.0  # 0: 3 periods (or 3 block lengths)
    step_length: float = 0.0  # sliding distance per step; 0: h_contact / 2
    compression_time: float = 0.0  # s; 0: cell length / (2 pi v), see the module docstring
    compression_steps: int = 10
    window_start: float = 1.0 / 3.0  # fraction of the sliding distance before averaging (run-in)
    # converged time homogenisation (driver.sliding.window): > 0 slides whole periods of a
    # periodic cell until the mean mu of its last w periods and of the w before differ by at
    # most this (relative; driver.sliding.window.converged_window);
    # slide_distance is then the budget.  0: the fixed window above (thesis 6.2.3)
    converge_tol: float = 0.0
    window_periods: int = 2  # converged rule: fewest periods averaged (window.converged_window)
    # what the converged rule waits for: "mu" (the friction coefficient the run passes up),
    # "contact" (the contact fraction, the reciprocal of the pooled pressure of eq. 6.11 that a
    # pressure-branch run passes down) or "both" (mu and the contact fraction of eq. 7.4 where the
    # real contact area enters adhesion; window.WINDOW_QUANTITIES)
    window_quantity: str = "mu"
    # periodic extrapolation of the Prony histories at the end of every period of a periodic
    # cell (forms.viscoelastic.ViscoelasticHistory.extrapolate_periodic): the static part of the
    # load is relaxed at once instead of creeping for tau_max / T periods
    steady_state: bool = False
    # with steady_state, a frictionless cell's state is extrapolated along its slow modes where
    # the period changes are geometric (driver.sliding.slowmode)
    period_extrapolation: bool = False
    # the linear viscoelastic closed form replaces the FE run where driver.sliding.shortcut
    # admits it (frictionless, full contact, small slopes)
    shortcut: bool = False
    penalty: float = 0.0  # 0: automatic, c_N = penalty_alpha |E*_eff(omega)| / h_contact
    penalty_alpha: float = 100.0  # see PENALTY_ALPHA
    # tangential penalty c_T = tangential_penalty x c_N: the stick compliance; a slipping node's
    # traction is mu p whatever c_T (see SOFT_TANGENT, the frictional fallback); the default is
    # fe.contact.DEFAULT_TANGENTIAL_FRACTION (not imported: this module stays free of PETSc)
    tangential_penalty: float = 0.1
    max_cutbacks: int = 8
    # globalisation of the Newton solves: "line-search" (driver.fe.newton), "trust-region"
    # (driver.fe.trust_region: minimises the step's incremental potential; exact for frictionless
    # node-to-surface contact, a merit function otherwise) or "hybrid" (line-search, the trust
    # region for a sub-step where it fails)
    newton: str = "line-search"
    # Newton's convergence test: reduced residual norm <= newton_rtol x p L (the load per unit
    # depth); what a looser test trades is measured in docs/performance.md
    newton_rtol: float = 1e-8
    # viscous stabilisation of a sub-step that fails after STABILISE_AFTER cut-backs (or at the
    # last one): beta of driver.fe.stabilisation, tried as beta x STABILISATION_LADDER; 0: off
    stabilisation: float = 0.1
    # a converged state with a quadrature point whose det F is at most this is refused like an
    # inverted one (cut back, stabilise, fall back): a Q1P0 element constrains only its mean
    # dilatation and can be squeezed to zero area, and its second Piola-Kirchhoff history grows
    # like 1 / det F^2 (measured on a micro2 run at 29 MPa: det F 1e-14, history stress 6e13 MPa,
    # then residuals of 1e12).  Runs that converge with a consistent mu reach 0.0036 and 0.0095
    # (default scene micro1 at 15 MPa, micro2 at 7.6 MPa), the collapsed one 1e-5 .. 1e-14 in
    # its last states; 0: inversion only
    min_jacobian: float = 1e-3
    # a warm start (InitialState): the run slides on from an earlier run's final state; None: from
    # rest (initial contact, compression, then sliding)
    initial_state: InitialState | None = None
    # keep the final state with the result (SlidingResult.final_state) so that a later run can
    # start from it: the thermal loop's next homogenisation point (periodic cells only)
    keep_state: bool = False


@dataclass
class SlidingResult:
    status: str  # "ok" or "failed"
    reason: str = ""
    t_reached: float = 0.0
    series: dict[str, np.ndarray] = field(default_factory=dict)
    mu_force: float = float("nan")
    mu_energy: float = float("nan")
    # what the contact interface takes up itself over the window (road's work minus frictional
    # dissipation minus the trapezoidal work on the rubber), in the measure of mu (energy over
    # F_z times the window's length; docs/notes-energy.md)
    mu_interface: float = float("nan")
    mean_pressure: float = float("nan")  # eq. (6.11), pooled over the window (run.py)
    contact_fraction: float = float("nan")  # time-averaged contact length / block length (7.4)
    # (2nd half - 1st half) / mean of the window's mu (one period: against the period before)
    window_drift: float = float("nan")
    mu_error: float = float("nan")  # estimated |window mean - steady mu| / mu (window.py)
    # the same two for the contact fraction (7.4), whose reciprocal is the pooled pressure (6.11)
    contact_drift: float = float("nan")
    contact_error: float = float("nan")
    converged: float = float("nan")  # converged rule: 1 reached, 0 budget exhausted; fixed: nan
    # the largest of the stabilising dashpots' share of the window's friction work, of its mean
    # friction force and of the load p l in the stabilised steps (0: no stabilised sub-step in
    # the window; driver.fe.stabilisation, run.stabilisation_share)
    stabilisation_share: float = float("nan")
    # smallest det F at a quadrature point over the accepted states (how distorted the mesh got;
    # SlidingSpec.min_jacobian refuses states at or below the limit)
    min_det_F: float = float("nan")
    # deepest road vertex inside the rubber face over the sliding steps, in contact element
    # lengths (periodic cells on the rigid road; driver.sliding.intrusion): >= 1 is unresolved
    road_intrusion: float = float("nan")
    # fewest contact elements in contact over the window (contact length / h_contact): below
    # about 2 the load rests on single nodes, the contact is narrower than the mesh resolves
    # (driver.multiscale.statistics.UNRESOLVED_CONTACT)
    contact_elements: float = float("nan")
    dissipation_by_depth: tuple[np.ndarray, np.ndarray] | None = None
    stats: dict[str, float] = field(default_factory=dict)
    final_state: InitialState | None = None  # with spec.keep_state, after a finished slide

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def default_h_contact(spec: SlidingSpec) -> float:
    """Contact-face element size of the spec's road (``meshes.block.polyline_element_size``)."""
    return polyline_element_size(spec.surface_x, spec.surface_h, spec.period,
                                 spec.elements_per_wavelength)


def rms_slope(spec: SlidingSpec) -> float:
    """Root-mean-square slope of the rigid surface (the periodic closing segment included)."""
    x, h = np.asarray(spec.surface_x, float), np.asarray(spec.surface_h, float)
    if spec.period > 0:
        x, h = np.append(x, x[0] + spec.period), np.append(h, h[0])
    return float(np.sqrt(np.mean((np.diff(h) / np.diff(x)) ** 2))) if x.size > 1 else 0.0


def cost_model(spec: SlidingSpec) -> float:
    """Model cost of a run in arbitrary units, for time estimates: nodes of the block mesh times
    time steps of the first attempt times a difficulty factor,
    (n_x + 1) (n_z + 1) (n_slide + compression_steps) (1 + rms slope).

    n_x = L / h_contact elements along the contact face and n_z graded rows up to the block
    height (``meshes.block.rubber_block``), n_slide = sliding distance / step length (as in
    ``SlidingRun._attempt``).  Steep samples need more Newton iterations and cut-backs
    (README "Status": active-set cycling above rms slope ~1.5); 1 + rms slope brings the model
    of the default scene's scales (rms slope 0.8, 0.5, 2.0, 4.0) to 1 : 2.1 : 2.3 : 13.7 per run
    against the measured 1 : 2.0 : 1.8 : 17.8 (nodes x steps alone: 1 : 2.6 : 1.4 : 4.8).  Only
    ratios mean something; finished runs of the same scale estimate better
    (``driver.runtime.progress.CostEstimate``).
    """
    L = spec.block_length or spec.period
    H = spec.block_height or L
    hc = spec.h_contact or default_h_contact(spec)
    n_x = contact_divisions(L, None, hc)
    n_z = geometric_sizes(H, hc, spec.grading)[0].size
    distance = spec.slide_distance or 3.0 * L
    n_slide = math.ceil(distance / (spec.step_length or 0.5 * hc) - 1e-9)
    nodes_steps = (n_x + 1) * (n_z + 1) * (n_slide + spec.compression_steps)
    return float(nodes_steps * (1.0 + rms_slope(spec)))


#: contact elements of the refined fallback attempts are this many times shorter
MESH_REFINEMENT = 2


#: the frictional runs' fallback multiplies c_T by this (SlidingRun.attempts).  With c_T = 0.1 c_N
#: at alpha = 100 the first sliding step puts every contact node far outside the stick cone (trial
#: traction ~ c_T x step >> mu p) and Newton cycles between stick and slip sets; ten times softer,
#: the stick zone stays resolved (measured: the 20 x 7 mm m3 block of thesis 8.5.1 at mu 0.9 and
#: 0.3 MPa stagnates at its first sliding step with 0.1 and slides with 0.01).  Steady sliding
#: friction does not depend on c_T (full slip: t_T = mu p); the stick phase gets a tangential
#: contact compliance of h / (0.01 alpha E) per unit length, ~1 % of a macro block's shear
#: compliance.
SOFT_TANGENT = 0.1

#: cut-backs of a sliding or compression step before a failing sub-step is retried with the
#: viscous stabilisation (a sub-step at the cut-back floor is always retried).  Measured on the
#: failing micro2 input f280d52c, side by side: after 1 cut-back 15 728 Newton iterations, 111
#: stabilised sub-steps, mu 0.25590, share 0.82 %; after 3: 24 533, 357, 0.25583, 0.71 %
STABILISE_AFTER = 1
#: the stabilisation's beta ladder, in units of SlidingSpec.stabilisation
STABILISATION_LADDER = (1.0, 10.0, 100.0)
#: Newton limits of a stabilised sub-step: a damped step still crosses contact kinks, where the
#: strict line search halves the residual per iteration (linear convergence, measured on the
#: failing micro2 input 6b9a9635: 1e-1 -> 3e-3 in 5 halvings, then a new kink); the plain limits
#: (25 iterations, stop when 8 do not halve the best residual) stop it while it still converges
STABILISED_ITERATIONS = 80
STABILISED_STAGNATION = 20


def has_friction(spec: SlidingSpec) -> bool:
    """A frictional run: a friction law or a nonzero mu."""
    f = spec.friction
    return f is not None and not (isinstance(f, numbers.Real) and float(f) == 0.0)


def softened(spec: SlidingSpec, factor: float) -> SlidingSpec:
    """The same run with c_T `factor` times the spec's (the frictional fallback)."""
    return spec if factor == 1.0 else replace(spec,
                                              tangential_penalty=spec.tangential_penalty * factor)


def refined(spec: SlidingSpec, factor: int) -> SlidingSpec:
    """The same run with contact elements `factor` times shorter (sliding steps follow them; the
    penalty's excitation frequency v / (elements_per_wavelength h_contact) is unchanged)."""
    if factor == 1:
        return spec
    hc = spec.h_contact or default_h_contact(spec)
    return replace(spec, h_contact=hc / factor,
                   elements_per_wavelength=spec.elements_per_wavelength * factor,
                   step_length=spec.step_length / factor)


#: automatic normal penalty c_N = alpha |E*_eff(omega)| / h_contact
#: (ContactInterface::set_auto_penalty): the contact compliance h/(alpha E) is then ~1/alpha of
#: the rubber's compliance at the element scale
PENALTY_ALPHA = 100.0


def penalty_modulus(spec: SlidingSpec) -> float:
    """|E*_eff| of the rubber at the run's excitation frequency omega = 2 pi v / lambda_min.

    The stiffness the contact works against is the dynamic modulus at the frequency the shortest
    resolved wavelength (elements_per_wavelength contact elements) imposes; the glassy modulus
    would make the penalty up to E0/E_inf ~ 300 times stiffer than needed at low speed and the
    active-set iteration needlessly ill-conditioned, the long-term one too soft at high speed.
    """
    hc = spec.h_contact or default_h_contact(spec)
    omega = 2.0 * np.pi * spec.velocity / (spec.elements_per_wavelength * hc)
    T = surface_temperature(spec.temperature_layers, spec.temperature)  # the contact face's
    return float(abs(effective_modulus(spec.compound, omega, T)))
