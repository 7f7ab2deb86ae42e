"""Material data of the rubber compounds and the road (thesis ch. 3.3.1, 3.3.3, app. A and C).

Plain, validated, immutable value objects; the finite-element forms consume them.  Units are the
project's: mm, s, t, N, MPa, mJ, K (so densities in t/mm^3, specific heats in mJ/(t K), thermal
conductivities in mW/(mm K), relaxation times in s, frequencies omega in rad/s, temperatures in
kelvin).  Files may state temperatures in degC; they are converted on loading, nowhere else.

Model (thesis ch. 3.3.1 and 3.3.4, fig. 3.5 b): a hyperelastic equilibrium spring (EQ), here a
Mooney-Rivlin model, in parallel with n Maxwell elements (NEQ, the Prony series).

* The Mooney-Rivlin constants describe the LONG-TERM (equilibrium, "rubbery") response: the thesis
  fits them to preconditioned quasi-static tension/compression tests (ch. 3.3.3, 6.5.1).  Hence
  ``Compound.E_inf`` (eq. 3.35, omega -> 0) is the small-strain Young's modulus of the
  Mooney-Rivlin model, and the instantaneous (glassy) modulus follows from the Prony series as
  ``E0 = E_inf / gamma_inf`` with ``gamma_inf = 1 - sum(gamma_k)`` (eqs. 3.35, 3.36).
* The dimensionless moduli gamma_k = E_k/E0 = G_k/G0 (eq. 3.36) are shared by tension and shear;
  in the ABAQUS-type model (eq. 3.77) they relax the isochoric stress only, the volumetric part
  (bulk modulus K = 2/D1) stays elastic.
* Temperature enters through the WLF shift (eq. 3.33) of the relaxation times, tau(T) =
  a(T) tau_ref (eq. 3.37): the response at frequency omega and temperature T equals the response at
  omega * a(T) at the reference temperature.

Data files live in ``forms/data/*.toml`` (format: ``forms/data/README.md``); load them with
:func:`load_compound` and :func:`load_road`.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

DATA_DIR = Path(__file__).resolve().parent / "data"
ZERO_CELSIUS = 273.15  # K
DEFAULT_COMPOUND = "tread_default"

# --------------------------------------------------------------------------------------------
# validation helpers: every error names the field, the value and what is expected
# --------------------------------------------------------------------------------------------


def _real(owner: str, name: str, value: Any, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{owner}.{name} = {value!r}: expected a real number in {unit}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{owner}.{name} = {value!r}: expected a finite number in {unit}")
    return value


def _positive(owner: str, name: str, value: Any, unit: str) -> float:
    value = _real(owner, name, value, unit)
    if value <= 0.0:
        raise ValueError(f"{owner}.{name} = {value!r}: expected a value > 0 in {unit}")
    return value


def _nonnegative(owner: str, name: str, value: Any, unit: str) -> float:
    value = _real(owner, name, value, unit)
    if value < 0.0:
        raise ValueError(f"{owner}.{name} = {value!r}: expected a value >= 0 in {unit}")
    return value


def _text(owner: str, name: str, value: Any, *, empty_ok: bool = True) -> str:
    if not isinstance(value, str) or (not empty_ok and not value.strip()):
        raise ValueError(f"{owner}.{name} = {value!r}: expected a "
                         f"{'' if empty_ok else 'non-empty '}string")
    return value


def _instance(owner: str, name: str, value: Any, cls: type, optional: bool = False) -> Any:
    if value is None and optional:
        return None
    if not isinstance(value, cls):
        raise ValueError(f"{owner}.{name} = {value!r}: expected a {cls.__name__}"
                         + (" or None" if optional else ""))
    return value


def _float_array(owner: str, name: str, value: Any, unit: str) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        raise ValueError(f"{owner}.{name} = {value!r}: expected a 1-D array of numbers "
                         f"({unit})") from None
    if arr.ndim != 1:
        raise ValueError(f"{owner}.{name}: expected a 1-D array ({unit}), got shape {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"{owner}.{name}[{i}] = {arr[i]!r}: expected finite values ({unit})")
    return arr


def _finite_nd(owner: str, name: str, value: Any, unit: str) -> np.ndarray:
    """A finite float array of any shape (0-d for a scalar)."""
    arr = _float_array(owner, name, value, unit) if np.ndim(value) <= 1 else None
    if arr is None:
        arr = np.asarray(value, dtype=float)
        if not np.isfinite(arr).all():
            raise ValueError(f"{owner}.{name}: expected finite values ({unit})")
    return arr.reshape(np.shape(value))


def _as_output(x: Any) -> float | np.ndarray:
    """A float for 0-d results, the array otherwise."""
    return float(x) if np.ndim(x) == 0 else np.asarray(x)


# --------------------------------------------------------------------------------------------
# hyperelastic equilibrium part
# --------------------------------------------------------------------------------------------

MR_FORMS = ("split", "feap")


@dataclass(frozen=True)
class MooneyRivlin:
    """Mooney-Rivlin equilibrium (long-term) spring; C10, C01 in MPa, D1 in 1/MPa.

    ``form="split"`` (ABAQUS, eq. 3.58 with J_th = 1, thesis tables 6.1, 7.1, C.2)::

        Psi = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1

    The thesis prints ``- C01 (I2bar - 3)`` in eq. (3.58).  We use ``+ C01``: it is the standard
    ABAQUS form, and only with ``+`` is the initial shear modulus mu = 2 (C10 + C01) (eq. A.8)
    and the Blatz-Ko mapping (eqs. 3.60, A.9) with 0 <= f <= 1 consistent; with ``-`` the
    tabulated positive C01 would soften the material, mu = 2 (C10 - C01), which for compound c1
    (C10 = 0.136, C01 = 0.518) would even be negative.

    ``form="feap"`` (eq. 3.53, no volumetric/isochoric split), used here as::

        Psi = mu1/2 (I_b - 3 - 2 ln J) + mu2/2 (II_b - 3 - 4 ln J) + lambda/4 (J^2 - 1 - 2 ln J)

    with ``mu1 = 2 C10``, ``mu2 = 2 C01``, ``lambda = K - 2/3 mu - 2 mu2`` (:attr:`mu1`,
    :attr:`mu2`, :attr:`lam`).  Linearising the stress (3.54) gives the shear modulus
    mu1 + mu2 = mu and the first Lamé constant lambda + 2 mu2, i.e. the bulk modulus K = 2/D1:
    the same small-strain moduli as the split form.  The thesis prints ``- mu2/2 (II_b ...)``
    (the same sign issue as in 3.58); that is this energy with mu2 -> -mu2 (a negative mu2 in
    the printed convention).  ``forms/hyperelastic.py`` uses this "+ mu2" convention.  The
    constants are stored as C10, C01, D1 in both forms; ``form`` only tells the finite-element
    forms which strain energy to build.

    Interpretation: these constants describe the LONG-TERM (equilibrium) response; the thesis
    fits them to quasi-static tests (ch. 3.3.3).  Validation: C10 > 0, C01 >= 0 (C01 = 0 is
    neo-Hooke; negative C01 is rejected as a sufficient condition for stability), D1 > 0.
    """

    C10: float
    C01: float
    D1: float
    form: str = "split"

    def __post_init__(self) -> None:
        object.__setattr__(self, "C10", _positive("MooneyRivlin", "C10", self.C10, "MPa"))
        object.__setattr__(self, "C01", _nonnegative("MooneyRivlin", "C01", self.C01, "MPa"))
        object.__setattr__(self, "D1", _positive("MooneyRivlin", "D1", self.D1, "1/MPa"))
        if self.form not in MR_FORMS:
            raise ValueError(f"MooneyRivlin.form = {self.form!r}: expected one of {MR_FORMS}")

    @classmethod
    def neo_hooke(cls, mu: float, K: float, form: str = "split") -> MooneyRivlin:
        """Neo-Hooke as the special case C01 = 0: C10 = mu/2, D1 = 2/K (eq. A.8)."""
        mu = _positive("MooneyRivlin.neo_hooke", "mu", mu, "MPa")
        K = _positive("MooneyRivlin.neo_hooke", "K", K, "MPa")
        return cls(C10=mu / 2.0, C01=0.0, D1=2.0 / K, form=form)

    @classmethod
    def from_blatz_ko(cls, E: float, nu: float, f: float, form: str = "split") -> MooneyRivlin:
        """Thesis eq. (3.60): C10 = E f / (4(1+nu)), C01 = E (1-f) / (4(1+nu)), D1 = 6(1-2nu)/E."""
        E = _positive("MooneyRivlin.from_blatz_ko", "E", E, "MPa")
        nu = _real("MooneyRivlin.from_blatz_ko", "nu", nu, "-")
        f = _real("MooneyRivlin.from_blatz_ko", "f", f, "-")
        if not -1.0 < nu < 0.5:
            raise ValueError(f"MooneyRivlin.from_blatz_ko.nu = {nu!r}: expected -1 < nu < 0.5")
        if not 0.0 < f <= 1.0:
            raise ValueError(f"MooneyRivlin.from_blatz_ko.f = {f!r}: expected 0 < f <= 1")
        return cls(E * f / (4 * (1 + nu)), E * (1 - f) / (4 * (1 + nu)), 6 * (1 - 2 * nu) / E, form)

    @classmethod
    def from_feap(cls, mu1: float, mu2: float, lam: float) -> MooneyRivlin:
        """Inverse of the FEAP mapping ("+ mu2" convention).

        C10 = mu1/2, C01 = mu2/2, K = lam + 2/3 (mu1 + mu2) + 2 mu2.
        """
        mu1 = _positive("MooneyRivlin.from_feap", "mu1", mu1, "MPa")
        mu2 = _nonnegative("MooneyRivlin.from_feap", "mu2", mu2, "MPa")
        lam = _real("MooneyRivlin.from_feap", "lam", lam, "MPa")
        K = lam + 2.0 * (mu1 + mu2) / 3.0 + 2.0 * mu2
        if K <= 0:
            raise ValueError(f"MooneyRivlin.from_feap.lam = {lam!r} gives a bulk modulus K = "
                             f"{K!r}; expected K > 0")
        return cls(C10=mu1 / 2.0, C01=mu2 / 2.0, D1=2.0 / K, form="feap")

    @property
    def mu(self) -> float:
        """Initial (long-term) shear modulus mu = 2 (C10 + C01), MPa (eq. A.8)."""
        return 2.0 * (self.C10 + self.C01)

    @property
    def K(self) -> float:
        """Bulk modulus K = 2 / D1, MPa (eq. A.8)."""
        return 2.0 / self.D1

    @property
    def E(self) -> float:
        """Small-strain Young's modulus E = 9 K mu / (3K + mu), MPa (from eq. A.7)."""
        return 9.0 * self.K * self.mu / (3.0 * self.K + self.mu)

    @property
    def nu(self) -> float:
        """Small-strain Poisson ratio (3K - 2mu) / (2 (3K + mu)) (from eq. A.7)."""
        return (3.0 * self.K - 2.0 * self.mu) / (2.0 * (3.0 * self.K + self.mu))

    @property
    def lame_lambda(self) -> float:
        """First Lamé constant of the linearised model, K - 2/3 mu, MPa (eq. A.7)."""
        return self.K - 2.0 * self.mu / 3.0

    @property
    def mu1(self) -> float:
        """FEAP form (eq. 3.53): mu1 = 2 C10, MPa."""
        return 2.0 * self.C10

    @property
    def mu2(self) -> float:
        """FEAP form (eq. 3.53, "+ mu2" convention): mu2 = 2 C01, MPa (mu1 + mu2 = mu)."""
        return 2.0 * self.C01

    @property
    def lam(self) -> float:
        """FEAP form (eq. 3.53): lambda = K - 2/3 mu - 2 mu2, MPa (linearised bulk modulus K)."""
        return self.K - 2.0 * self.mu / 3.0 - 2.0 * self.mu2


# --------------------------------------------------------------------------------------------
# viscoelastic part: Prony series and WLF shift
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class PronySeries:
    """Prony series of n Maxwell elements (thesis eqs. 3.34-3.36), at the reference temperature.

    ``gamma[k] = E_k / E0`` (dimensionless, eq. 3.36), ``tau[k]`` relaxation times in s.  The
    moduli need a long-term modulus E_inf (MPa), which the compound takes from its hyperelastic
    (equilibrium) part: ``E0 = E_inf / gamma_inf``, ``E_k = gamma_k E0``.  Terms are stored
    sorted by tau (the pairs are permuted together).  Zero gamma_k are allowed (see
    :meth:`pruned`), the sum must stay below 1 so that an equilibrium spring remains.
    """

    gamma: np.ndarray
    tau: np.ndarray

    def __post_init__(self) -> None:
        gamma = _float_array("PronySeries", "gamma", self.gamma, "-")
        tau = _float_array("PronySeries", "tau", self.tau, "s")
        if gamma.shape != tau.shape:
            raise ValueError(f"PronySeries.gamma has {gamma.size} terms but PronySeries.tau has "
                             f"{tau.size}: expected one relaxation time per modulus")
        checks = (("gamma", gamma, gamma < 0, ">= 0"), ("tau", tau, tau <= 0, "> 0 s"))
        for name, arr, cond, expect in checks:
            if cond.any():
                i = int(np.argmax(cond))
                raise ValueError(f"PronySeries.{name}[{i}] = {arr[i]!r}: expected {expect}")
        if gamma.sum() >= 1.0:
            raise ValueError(f"PronySeries.gamma: sum(gamma) = {gamma.sum()!r}: expected < 1 "
                             "(gamma_inf = 1 - sum(gamma) must stay > 0, eq. 3.35/3.36)")
        if np.unique(tau).size != tau.size:
            raise ValueError(f"PronySeries.tau = {tau}: expected distinct relaxation times")
        order = np.argsort(tau, kind="stable")
        for name, arr in (("gamma", gamma[order]), ("tau", tau[order])):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PronySeries):
            return NotImplemented
        return np.array_equal(self.gamma, other.gamma) and np.array_equal(self.tau, other.tau)

    __hash__ = None  # type: ignore[assignment]

    def __len__(self) -> int:
        return int(self.tau.size)

    @classmethod
    def from_moduli(cls, E_inf: float, E_k: Any, tau_k: Any) -> PronySeries:
        """From absolute moduli (eq. 3.35): E0 = E_inf + sum E_k, gamma_k = E_k / E0."""
        E_inf = _positive("PronySeries.from_moduli", "E_inf", E_inf, "MPa")
        E_k = _float_array("PronySeries.from_moduli", "E_k", E_k, "MPa")
        if (E_k < 0).any():
            i = int(np.argmax(E_k < 0))
            raise ValueError(f"PronySeries.from_moduli.E_k[{i}] = {E_k[i]!r}: expected >= 0 MPa")
        return cls(gamma=E_k / (E_inf + E_k.sum()), tau=tau_k)

    @property
    def gamma_inf(self) -> float:
        """Long-term relative modulus gamma_inf = 1 - sum(gamma_k) = E_inf / E0."""
        return float(1.0 - self.gamma.sum())

    def E0(self, E_inf: float) -> float:
        """Instantaneous (glassy) modulus E0 = E_inf / gamma_inf (eq. 3.35), MPa."""
        return _positive("PronySeries", "E_inf", E_inf, "MPa") / self.gamma_inf

    def moduli(self, E_inf: float) -> np.ndarray:
        """Absolute moduli E_k = gamma_k E0 of the Maxwell springs, MPa."""
        return self.gamma * self.E0(E_inf)

    def complex_modulus(self, omega: Any, E_inf: float) -> complex | np.ndarray:
        """E*(omega) = E' + i E'' (eq. 3.34); omega in rad/s (>= 0), result in MPa."""
        wt = np.multiply.outer(_omega(omega), self.tau)
        Ek = self.moduli(E_inf)
        value = E_inf + (wt**2 / (1 + wt**2)) @ Ek + 1j * ((wt / (1 + wt**2)) @ Ek)
        return complex(value) if np.ndim(value) == 0 else value

    def storage(self, omega: Any, E_inf: float) -> float | np.ndarray:
        """Storage modulus E'(omega) = E_inf + sum E_k (w tau)^2 / (1 + (w tau)^2) (eq. 3.34)."""
        return _as_output(np.real(self.complex_modulus(omega, E_inf)))

    def loss(self, omega: Any, E_inf: float) -> float | np.ndarray:
        """Loss modulus E''(omega) = sum E_k w tau / (1 + (w tau)^2) (eq. 3.34)."""
        return _as_output(np.imag(self.complex_modulus(omega, E_inf)))

    def relaxation(self, t: Any, E_inf: float) -> float | np.ndarray:
        """Relaxation modulus E(t) = E0 (gamma_inf + sum gamma_k exp(-t / tau_k)), t >= 0 in s."""
        tt = _finite_nd("PronySeries.relaxation", "t", t, "s")
        if (tt < 0).any():
            raise ValueError(f"PronySeries.relaxation.t: min {tt.min()!r}: expected t >= 0 s")
        decay = np.exp(-np.divide.outer(tt, self.tau)) @ self.gamma
        return _as_output(self.E0(E_inf) * (self.gamma_inf + decay))

    def shifted(self, factor: float) -> PronySeries:
        """The same spectrum with every tau multiplied by ``factor`` (e.g. a(T), eq. 3.37)."""
        factor = _positive("PronySeries.shifted", "factor", factor, "-")
        return PronySeries(self.gamma, self.tau * factor)

    def pruned(self) -> PronySeries:
        """Drop terms with gamma_k == 0 (they carry no stress but cost internal variables)."""
        keep = self.gamma > 0
        return PronySeries(self.gamma[keep], self.tau[keep])


def _omega(omega: Any) -> np.ndarray:
    w = _finite_nd("complex_modulus", "omega", omega, "rad/s")
    if (w < 0).any():
        raise ValueError(f"complex_modulus.omega: min {w.min()!r}: expected omega >= 0 rad/s")
    return w


@dataclass(frozen=True)
class WLF:
    """Williams-Landel-Ferry shift (thesis eq. 3.33, 3.37); c1 (-), c2 (K), T_ref (K).

    ``log10 a(T) = -c1 (T - T_ref) / (c2 + T - T_ref)``, ``tau(T) = a(T) tau_ref``.  A frequency
    omega at temperature T is equivalent to omega * a(T) at T_ref.  Defined for T > T_ref - c2
    only (the WLF singularity); c2 is a temperature difference, so it has the same value in K and
    degC.
    """

    c1: float
    c2: float
    T_ref: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "c1", _positive("WLF", "c1", self.c1, "- (dimensionless)"))
        object.__setattr__(self, "c2", _positive("WLF", "c2", self.c2, "K"))
        T_ref = _positive("WLF", "T_ref", self.T_ref, "K (absolute temperature)")
        object.__setattr__(self, "T_ref", T_ref)

    @classmethod
    def from_celsius(cls, c1: float, c2: float, T_ref_C: float) -> WLF:
        """Convenience: the reference temperature given in degC."""
        return cls(c1, c2, _real("WLF.from_celsius", "T_ref_C", T_ref_C, "degC") + ZERO_CELSIUS)

    @property
    def T_singular(self) -> float:
        """T_ref - c2 in K: the WLF equation diverges there."""
        return self.T_ref - self.c2

    def log10_aT(self, T: Any) -> float | np.ndarray:
        """log10 a(T) (eq. 3.33), vectorised; T in K, T > T_ref - c2."""
        TT = _finite_nd("WLF.log10_aT", "T", T, "K")
        if (TT <= self.T_singular).any():
            bad = float(TT[TT <= self.T_singular].flat[0])
            raise ValueError(f"WLF.log10_aT: T = {bad!r} K is at or below the WLF singularity "
                             f"T_ref - c2 = {self.T_singular!r} K; expected T > "
                             f"{self.T_singular!r} K")
        dT = TT - self.T_ref
        return _as_output(-self.c1 * dT / (self.c2 + dT) + 0.0)  # + 0.0: no "-0" at T_ref

    def aT(self, T: Any) -> float | np.ndarray:
        """Shift factor a(T) = 10**log10_aT(T)."""
        return _as_output(np.power(10.0, self.log10_aT(T)))

    def shift_tau(self, tau: Any, T: Any) -> float | np.ndarray:
        """tau(T) = a(T) tau_ref (eq. 3.37); tau in s at T_ref, T in K."""
        tau_arr = _finite_nd("WLF.shift_tau", "tau", tau, "s")
        if (tau_arr <= 0).any():
            raise ValueError(f"WLF.shift_tau.tau: min {tau_arr.min()!r}: expected tau > 0 s")
        return _as_output(np.multiply(self.aT(T), tau_arr))


# --------------------------------------------------------------------------------------------
# thermal data, compound, road
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Thermal:
    """Thermal data: rho in t/mm^3, c in mJ/(t K), k in mW/(mm K) (thesis tables C.1, C.3)."""

    rho: float
    c: float
    k: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "rho", _positive("Thermal", "rho", self.rho, "t/mm^3"))
        object.__setattr__(self, "c", _positive("Thermal", "c", self.c, "mJ/(t K)"))
        object.__setattr__(self, "k", _positive("Thermal", "k", self.k, "mW/(mm K)"))

    @property
    def diffusivity(self) -> float:
        """Thermal diffusivity k / (rho c) in mm^2/s."""
        return self.k / (self.rho * self.c)


@dataclass(frozen=True)
class Compound:
    """A rubber compound: Mooney-Rivlin equilibrium part, Prony series, WLF shift, thermal data.

    ``E_inf`` is the long-term Young's modulus of the Mooney-Rivlin constants; the Prony series
    scales it to ``E0 = E_inf / gamma_inf``.  ``complex_modulus(omega, T)`` evaluates eq. (3.34)
    with the WLF shift (eq. 3.33, 3.37).  ``prony``, ``wlf`` and ``thermal`` may be None when the
    source has none (e.g. compound m3 has no WLF constants in table C.3).
    """

    name: str
    hyperelastic: MooneyRivlin
    prony: PronySeries | None
    wlf: WLF | None
    thermal: Thermal | None
    description: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        _text("Compound", "name", self.name, empty_ok=False)
        _instance("Compound", "hyperelastic", self.hyperelastic, MooneyRivlin)
        _instance("Compound", "prony", self.prony, PronySeries, optional=True)
        _instance("Compound", "wlf", self.wlf, WLF, optional=True)
        _instance("Compound", "thermal", self.thermal, Thermal, optional=True)
        _text("Compound", "description", self.description)
        _text("Compound", "source", self.source)

    @property
    def E_inf(self) -> float:
        """Long-term Young's modulus from the Mooney-Rivlin constants, MPa."""
        return self.hyperelastic.E

    @property
    def gamma_inf(self) -> float:
        return 1.0 if self.prony is None else self.prony.gamma_inf

    @property
    def E0(self) -> float:
        """Instantaneous (glassy) Young's modulus E_inf / gamma_inf, MPa (eq. 3.35)."""
        return self.E_inf / self.gamma_inf

    @property
    def G0(self) -> float:
        """Instantaneous shear modulus mu / gamma_inf (eq. 3.36: gamma_k = G_k / G0), MPa."""
        return self.hyperelastic.mu / self.gamma_inf

    @property
    def nu0(self) -> float:
        """Instantaneous Poisson ratio implied by E0 and K = 2/D1: nu0 = (3K - E0) / (6K).

        Below -1 (E0 > 9K) no isotropic elastic solid has this pair of moduli: then the glassy
        Young's modulus of the Prony series cannot be reproduced by a model with the bulk modulus
        K = 2/D1 (see :meth:`summary`).
        """
        K = self.hyperelastic.K
        return (3.0 * K - self.E0) / (6.0 * K)

    @property
    def nu0_fe(self) -> float:
        """Instantaneous Poisson ratio of the FE model (shear G0, elastic bulk K, eq. 3.77)."""
        K, G = self.hyperelastic.K, self.G0
        return (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))

    @property
    def E0_fe(self) -> float:
        """Instantaneous Young's modulus of the FE model, 9 K G0 / (3K + G0), MPa."""
        K, G = self.hyperelastic.K, self.G0
        return 9.0 * K * G / (3.0 * K + G)

    def reduced_omega(self, omega: Any, T: float | None = None) -> Any:
        """omega * a(T): the frequency at T_ref equivalent to omega at T (eq. 3.33, 3.37)."""
        if T is None:
            return omega
        if self.wlf is None:
            raise ValueError(f"Compound {self.name!r}: T = {T!r} K given but the compound has no "
                             "WLF data; expected T=None (reference temperature)")
        return np.multiply(omega, self.wlf.aT(_positive("Compound", "T", T, "K")))

    def complex_modulus(self, omega: Any, T: float | None = None) -> complex | np.ndarray:
        """E*(omega, T) in MPa (eq. 3.34); omega in rad/s, T in K (None: reference temperature)."""
        w = self.reduced_omega(omega, T)
        if self.prony is None:
            value = np.full(np.shape(_omega(w)), self.E_inf, dtype=complex)
            return complex(value) if value.ndim == 0 else value
        return self.prony.complex_modulus(w, self.E_inf)

    def summary(self) -> str:
        """Human-readable description of the compound, with consistency warnings."""
        return "\n".join(_compound_summary_lines(self))


def _compound_summary_lines(c: Compound) -> list[str]:
    mr = c.hyperelastic
    lines = [f"compound {c.name}: {c.description}".rstrip(": "), f"  source: {c.source}",
             f"  Mooney-Rivlin ({mr.form}, long-term/equilibrium): C10 = {mr.C10:g} MPa, "
             f"C01 = {mr.C01:g} MPa, D1 = {mr.D1:g} 1/MPa",
             f"    mu = 2(C10+C01) = {mr.mu:.4g} MPa, K = 2/D1 = {mr.K:.4g} MPa, "
             f"E_inf = {c.E_inf:.4g} MPa, nu_inf = {mr.nu:.4f}"]
    if mr.form == "feap":
        lines.append(f"    FEAP (eq. 3.53): mu1 = {mr.mu1:.4g}, mu2 = {mr.mu2:.4g}, lambda = "
                     f"{mr.lam:.4g} MPa")
    lines += _prony_summary_lines(c)
    if c.wlf is None:
        lines.append("  WLF: none (no temperature shift available)")
    else:
        w = c.wlf
        lines.append(f"  WLF: c1 = {w.c1:g}, c2 = {w.c2:g} K, T_ref = {w.T_ref:g} K "
                     f"({w.T_ref - ZERO_CELSIUS:g} degC); singular at "
                     f"{w.T_singular - ZERO_CELSIUS:g} degC")
    if c.thermal is None:
        lines.append("  thermal: none")
    else:
        t = c.thermal
        lines.append(_thermal_line(t))
    return lines


def _prony_summary_lines(c: Compound) -> list[str]:
    if c.prony is None:
        return ["  Prony series: none (purely hyperelastic)"]
    p, K = c.prony, c.hyperelastic.K
    lines = [f"  Prony series: {len(p)} terms, tau = {p.tau.min():.3g} .. {p.tau.max():.3g} s, "
             f"gamma_inf = {p.gamma_inf:.5g}",
             f"    E0 = E_inf/gamma_inf = {c.E0:.5g} MPa, G0 = mu/gamma_inf = {c.G0:.5g} MPa",
             f"    instantaneous Poisson ratio from E0 and K: nu0 = (3K - E0)/(6K) = {c.nu0:.4f}"]
    if c.nu0 < 0.0:
        lines.append(f"    WARNING: nu0 < 0{' and < -1' if c.nu0 < -1 else ''}: the glassy modulus "
                     f"E0 = {c.E0:.4g} MPa exceeds {'9K' if c.nu0 < -1 else '3K'} with "
                     f"K = {K:.4g} MPa (D1 of the quasi-static fit).")
        lines.append("    The FE model (viscous isochoric part, elastic bulk K, eq. 3.77) has at "
                     f"t = 0 G0 = {c.G0:.4g} MPa > K: nu0 = {c.nu0_fe:.4f}, E0 = {c.E0_fe:.4g} MPa "
                     f"({100 * c.E0_fe / c.E0:.3g} % of the Prony E0).")
    return lines


def _thermal_line(t: Thermal) -> str:
    return (f"  thermal: rho = {t.rho:g} t/mm^3, c = {t.c:g} mJ/(t K), k = {t.k:g} mW/(mm K), "
            f"diffusivity = {t.diffusivity:.4g} mm^2/s")


@dataclass(frozen=True)
class Road:
    """Road (counter-surface) material, linear elastic: E in MPa, nu (-), thermal (table C.1)."""

    name: str
    E: float
    nu: float
    thermal: Thermal | None
    description: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        _text("Road", "name", self.name, empty_ok=False)
        object.__setattr__(self, "E", _positive("Road", "E", self.E, "MPa"))
        nu = _real("Road", "nu", self.nu, "-")
        if not -1.0 < nu < 0.5:
            raise ValueError(f"Road.nu = {nu!r}: expected -1 < nu < 0.5")
        object.__setattr__(self, "nu", nu)
        _instance("Road", "thermal", self.thermal, Thermal, optional=True)
        _text("Road", "description", self.description)
        _text("Road", "source", self.source)

    @property
    def mu(self) -> float:
        """Shear modulus E / (2 (1 + nu)), MPa (eq. A.7)."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def K(self) -> float:
        """Bulk modulus E / (3 (1 - 2 nu)), MPa (eq. A.7)."""
        return self.E / (3.0 * (1.0 - 2.0 * self.nu))

    @property
    def lame_lambda(self) -> float:
        """First Lamé constant E nu / ((1 + nu)(1 - 2 nu)), MPa (eq. A.7)."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    def summary(self) -> str:
        lines = [f"road {self.name}: {self.description}".rstrip(": "), f"  source: {self.source}",
                 f"  E = {self.E:g} MPa, nu = {self.nu:g} (mu = {self.mu:.5g} MPa, K = "
                 f"{self.K:.5g} MPa)"]
        if self.thermal is not None:
            t = self.thermal
            lines.append(_thermal_line(t))
        return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# TOML files
# --------------------------------------------------------------------------------------------

# Every file states these units in a [units] table; only the project units are accepted (a
# file in other units must be converted), except temperature: "K" or "degC".
BASE_UNITS = {"length": ("mm",), "time": ("s",), "mass": ("t",), "force": ("N",),
              "stress": ("MPa",), "energy": ("mJ",), "temperature": ("K", "degC")}
THERMAL_UNITS = {"density": ("t/mm^3",), "specific_heat": ("mJ/(tK)",),
                 "conductivity": ("mW/(mmK)",)}


def resolve_data_path(name_or_path: str | Path) -> Path:
    """A bare name resolves to ``forms/data/<name>.toml``; anything else is a file path."""
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or text.endswith(".toml") or "/" in text or "\\" in text:
        path = Path(name_or_path).expanduser()
    else:
        path = DATA_DIR / f"{text}.toml"
    if not path.is_file():
        known = ", ".join(available()) or "none"
        raise ValueError(f"material file {text!r} not found (looked at {path}); shipped names: "
                         f"{known}")
    return path


def available(kind: str | None = None) -> list[str]:
    """Names of the shipped data files (optionally only ``kind`` = "compound" or "road")."""
    names = []
    for path in sorted(DATA_DIR.glob("*.toml")):
        with path.open("rb") as fh:
            if kind is None or tomllib.load(fh).get("kind") == kind:
                names.append(path.stem)
    return names


def _read_toml(path: Path) -> dict[str, Any]:
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"{path}: not valid TOML: {err}") from None


def _check_keys(where: str, table: Any, allowed: set[str],
                required: set[str] = frozenset()) -> dict:
    if not isinstance(table, dict):
        raise ValueError(f"{where}: expected a table, got {table!r}")
    unknown = set(table) - allowed
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}; expected some of "
                         f"{sorted(allowed)}")
    missing = required - set(table)
    if missing:
        raise ValueError(f"{where}: missing key(s) {sorted(missing)}")
    return table


def _check_units(path: Path, doc: dict, thermal: bool) -> str:
    """Validate the [units] table; return the temperature unit ("K" or "degC")."""
    if "units" not in doc:
        raise ValueError(f"{path}: missing [units] table; every material file must state its units "
                         f"({', '.join(f'{k} = {v[0]!r}' for k, v in BASE_UNITS.items())})")
    expected = dict(BASE_UNITS, **(THERMAL_UNITS if thermal else {}))
    units = _check_keys(f"{path} [units]", doc["units"], set(BASE_UNITS) | set(THERMAL_UNITS),
                        set(expected))
    for key, accepted in expected.items():
        value = str(units[key]).replace(" ", "")
        if value not in accepted:
            expect = " or ".join(map(repr, accepted))
            raise ValueError(f"{path} [units].{key} = {units[key]!r}: expected {expect} "
                             "(convert the data to the project units)")
    return str(units["temperature"])


def _to_kelvin(value: Any, unit: str, where: str) -> float:
    value = _real(where, "temperature", value, unit)
    return value + ZERO_CELSIUS if unit == "degC" else value


def _kind(path: Path, doc: dict, expected: str) -> None:
    if doc.get("kind") != expected:
        raise ValueError(f"{path}: kind = {doc.get('kind')!r}; expected kind = {expected!r}")


COMPOUND_KEYS = {"kind", "name", "description", "source", "units", "hyperelastic", "prony", "wlf",
                 "thermal"}


def load_compound(name_or_path: str | Path, _seen: tuple[Path, ...] = ()) -> Compound:
    """Load a compound from a TOML file (``forms/data/<name>.toml`` for a bare name).

    Sections: ``[units]`` (required), ``[hyperelastic]`` (Mooney-Rivlin C10, C01, D1, form),
    ``[prony]``, ``[wlf]``, ``[thermal]``.  The Prony series is given in one of three ways:

    * inline: ``gamma = [...]``, ``tau = [...]`` (tau in s at the WLF reference temperature);
    * by reference: ``same_as = "tread_default"`` uses that compound's gamma and tau (gamma is
      dimensionless, so E0 = E_inf / gamma_inf follows from this compound's own E_inf);
    * from a DMA master curve: ``fit_from = "my_dma.csv"`` (relative to the TOML file) with fit
      options ``n_terms``, ``columns`` (three column names or indices: frequency, E', E''),
      ``freq_unit`` ("Hz" or "rad/s"), ``T`` (temperature of the master curve, in the file's
      temperature unit) and ``E_inf`` ("fit": fitted as an unknown, only gamma is used;
      "hyperelastic": fixed to the Mooney-Rivlin E_inf).  The fitted relaxation times are
      shifted from T to the WLF reference temperature.  Replacing the default spectrum by a
      user's DMA data is thus the one-line change ``fit_from = "path.csv"``.

    ``[wlf]`` gives ``c1``, ``c2`` (K), ``T_ref`` or ``same_as = "<compound>"``.
    """
    path = resolve_data_path(name_or_path).resolve()
    if path in _seen:
        raise ValueError(f"{path}: circular same_as reference "
                         f"({' -> '.join(p.stem for p in _seen)})")
    doc = _read_toml(path)
    _kind(path, doc, "compound")
    T_unit = _check_units(path, doc, "thermal" in doc)
    _check_keys(str(path), doc, COMPOUND_KEYS, {"kind", "name", "units", "hyperelastic", "source"})
    hyper = _load_hyperelastic(path, doc["hyperelastic"])
    wlf, wlf_note = _load_wlf(path, doc.get("wlf"), T_unit, _seen + (path,))
    prony, note = _load_prony(path, doc.get("prony"), T_unit, hyper, wlf, _seen + (path,))
    thermal = _load_thermal(path, doc["thermal"]) if "thermal" in doc else None
    return Compound(name=_text(str(path), "name", doc["name"], empty_ok=False), hyperelastic=hyper,
                    prony=prony, wlf=wlf, thermal=thermal,
                    description=_text(str(path), "description", doc.get("description", "")),
                    source=_text(str(path), "source", doc["source"]) + note + wlf_note)


def _load_hyperelastic(path: Path, table: Any) -> MooneyRivlin:
    t = _check_keys(f"{path} [hyperelastic]", table, {"model", "form", "C10", "C01", "D1", "note"},
                    {"model", "C10", "C01", "D1"})
    if t["model"] != "mooney_rivlin":
        raise ValueError(f"{path} [hyperelastic].model = {t['model']!r}: expected 'mooney_rivlin'")
    return MooneyRivlin(t["C10"], t["C01"], t["D1"], t.get("form", "split"))


def _load_wlf(path: Path, table: Any, T_unit: str,
              seen: tuple[Path, ...]) -> tuple[WLF | None, str]:
    if table is None:
        return None, ""
    t = _check_keys(f"{path} [wlf]", table, {"c1", "c2", "T_ref", "same_as", "note"})
    if "same_as" in t:
        _check_keys(f"{path} [wlf]", t, {"same_as", "note"})
        ref = load_compound(_sibling(path, t["same_as"]), seen)
        if ref.wlf is None:
            raise ValueError(f"{path} [wlf].same_as = {t['same_as']!r}: that compound has "
                             "no WLF data")
        return ref.wlf, f" [WLF: same as {ref.name}]"
    _check_keys(f"{path} [wlf]", t, set(t), {"c1", "c2", "T_ref"})
    return WLF(t["c1"], t["c2"], _to_kelvin(t["T_ref"], T_unit, f"{path} [wlf].T_ref")), ""


def _sibling(path: Path, ref: Any) -> str | Path:
    """A same_as reference: a bare name resolves next to the referring file."""
    ref = _text(str(path), "same_as", ref, empty_ok=False)
    candidate = path.parent / f"{ref}.toml"
    return candidate if "/" not in ref and candidate.is_file() else ref


PRONY_KEYS = {"gamma", "tau", "same_as", "fit_from", "n_terms", "columns", "freq_unit", "T",
              "E_inf", "note", "generator"}


def _load_prony(path: Path, table: Any, T_unit: str, hyper: MooneyRivlin, wlf: WLF | None,
                seen: tuple[Path, ...]) -> tuple[PronySeries | None, str]:
    if table is None:
        return None, ""
    t = _check_keys(f"{path} [prony]", table, PRONY_KEYS)
    ways = [k for k in ("gamma", "same_as", "fit_from") if k in t]
    if len(ways) != 1:
        raise ValueError(f"{path} [prony]: give exactly one of gamma/tau (inline), same_as, "
                         f"fit_from; got {ways}")
    if "gamma" in t:
        _check_keys(f"{path} [prony]", t, {"gamma", "tau", "note", "generator"}, {"gamma", "tau"})
        return PronySeries(t["gamma"], t["tau"]), ""
    if "same_as" in t:
        _check_keys(f"{path} [prony]", t, {"same_as", "note"})
        ref = load_compound(_sibling(path, t["same_as"]), seen)
        if ref.prony is None:
            raise ValueError(f"{path} [prony].same_as = {t['same_as']!r}: that compound has no "
                             "Prony series")
        return ref.prony, f" [Prony series: same gamma_k, tau_k as {ref.name}]"
    return _fit_prony_from_file(path, t, T_unit, hyper, wlf)


def _fit_prony_from_file(path: Path, t: dict, T_unit: str, hyper: MooneyRivlin,
                         wlf: WLF | None) -> tuple[PronySeries, str]:
    from rubberfriction.forms.prony import fit_prony, read_dma_csv

    where = f"{path} [prony]"
    _check_keys(where, t, {"fit_from", "n_terms", "columns", "freq_unit", "T", "E_inf", "note"},
                {"fit_from", "freq_unit", "T"})
    csv = Path(_text(where, "fit_from", t["fit_from"], empty_ok=False)).expanduser()
    csv = csv if csv.is_absolute() else path.parent / csv
    columns = tuple(t.get("columns", ("f", "E_stor", "E_loss")))
    omega, E1, E2 = read_dma_csv(csv, freq_unit=t["freq_unit"], columns=columns)
    mode = t.get("E_inf", "fit")
    if mode not in ("fit", "hyperelastic"):
        raise ValueError(f"{where}.E_inf = {mode!r}: expected 'fit' or 'hyperelastic'")
    fixed = hyper.E if mode == "hyperelastic" else None
    fit = fit_prony(omega, E1, E2, n_terms=t.get("n_terms"), E_inf=fixed)
    T_data = _to_kelvin(t["T"], T_unit, f"{where}.T")
    series = fit.series
    if wlf is not None and T_data != wlf.T_ref:
        series = series.shifted(1.0 / float(wlf.aT(T_data)))  # tau_ref = tau(T) / a(T), eq. 3.37
    note = (f" [Prony series fitted from {csv.name} at {T_data:g} K: "
            f"E_inf(fit) = {fit.E_inf:.4g} MPa vs E_inf(MR) = {hyper.E:.4g} MPa; "
            f"max rel. error E' {fit.rel_error_storage.max:.2%}, "
            f"E'' {fit.rel_error_loss.max:.2%}]")
    return series, note


def _load_thermal(path: Path, table: Any) -> Thermal:
    t = _check_keys(f"{path} [thermal]", table, {"rho", "c", "k", "note"}, {"rho", "c", "k"})
    return Thermal(t["rho"], t["c"], t["k"])


ROAD_KEYS = {"kind", "name", "description", "source", "units", "elastic", "thermal"}


def load_road(name_or_path: str | Path) -> Road:
    """Load a road material (``kind = "road"``): ``[elastic]`` E (MPa), nu; ``[thermal]``."""
    path = resolve_data_path(name_or_path).resolve()
    doc = _read_toml(path)
    _kind(path, doc, "road")
    _check_units(path, doc, "thermal" in doc)
    _check_keys(str(path), doc, ROAD_KEYS, {"kind", "name", "units", "elastic", "source"})
    el = _check_keys(f"{path} [elastic]", doc["elastic"], {"E", "nu", "note"}, {"E", "nu"})
    thermal = _load_thermal(path, doc["thermal"]) if "thermal" in doc else None
    return Road(name=doc["name"], E=el["E"], nu=el["nu"], thermal=thermal,
                description=doc.get("description", ""), source=doc["source"])


# --------------------------------------------------------------------------------------------
# the default viscoelastic spectrum (tread_default.toml): reproducible generator
# --------------------------------------------------------------------------------------------

GENERATOR_KEYS = {"model", "E_glassy", "alpha", "beta", "Tg", "f_Tg_Hz", "tau_min", "tau_max",
                  "n_terms", "points_per_decade"}


@dataclass(frozen=True)
class SpectrumGenerator:
    """Smooth target spectrum for the illustrative default compound (``tread_default.toml``).

    A Havriliak-Negami modulus function (see :func:`rubberfriction.forms.prony.havriliak_negami`)
    between the long-term modulus E_inf (from the Mooney-Rivlin constants) and a glassy plateau
    ``E_glassy``, with shape exponents ``alpha`` (low-frequency slope of E'') and ``alpha*beta``
    (high-frequency slope).  Its loss-modulus peak is placed with the WLF shift: a glass
    transition at ``Tg`` (K) observed in a DMA temperature sweep at ``f_Tg_Hz`` puts the E''
    peak at the reference temperature at f_peak = f_Tg * a(Tg) (eq. 3.33).  The Prony series is
    the non-negative least-squares fit (:func:`rubberfriction.forms.prony.fit_prony`, E_inf
    fixed) of this target on ``n_terms`` log-spaced relaxation times ``tau_min .. tau_max`` over
    omega = 1/tau_max .. 1/tau_min, ``points_per_decade`` points per decade.
    """

    E_glassy: float
    alpha: float
    beta: float
    Tg: float
    f_Tg_Hz: float
    tau_min: float
    tau_max: float
    n_terms: int
    points_per_decade: int = 20

    def __post_init__(self) -> None:
        own = "SpectrumGenerator"
        for name, unit in (("E_glassy", "MPa"), ("Tg", "K"), ("f_Tg_Hz", "Hz"), ("tau_min", "s"),
                           ("tau_max", "s")):
            object.__setattr__(self, name, _positive(own, name, getattr(self, name), unit))
        for name in ("alpha", "beta"):
            value = _positive(own, name, getattr(self, name), "-")
            if value > 1.0:
                raise ValueError(f"{own}.{name} = {value!r}: expected 0 < {name} <= 1")
        if self.tau_max <= self.tau_min:
            raise ValueError(f"{own}.tau_max = {self.tau_max!r}: expected > tau_min = "
                             f"{self.tau_min!r}")
        for name in ("n_terms", "points_per_decade"):
            if not isinstance(getattr(self, name), int) or getattr(self, name) < 2:
                raise ValueError(f"{own}.{name} = {getattr(self, name)!r}: expected an "
                                 "integer >= 2")

    def peak_frequency_Hz(self, wlf: WLF) -> float:
        """Target E'' peak frequency at T_ref: f_Tg * a(Tg), Hz."""
        return self.f_Tg_Hz * float(wlf.aT(self.Tg))

    def tau_hn(self, wlf: WLF) -> float:
        """Havriliak-Negami time constant placing the E'' maximum at :meth:`peak_frequency_Hz`."""
        from rubberfriction.forms.prony import hn_loss_peak_omega

        w_peak = 2 * np.pi * self.peak_frequency_Hz(wlf)
        return hn_loss_peak_omega(1.0, self.alpha, self.beta) / w_peak

    def target(self, omega: Any, E_inf: float, wlf: WLF) -> np.ndarray:
        """The smooth target E*(omega) at T_ref, MPa."""
        from rubberfriction.forms.prony import havriliak_negami

        return havriliak_negami(omega, E_inf, self.E_glassy, self.tau_hn(wlf), self.alpha,
                                self.beta)

    def fit(self, E_inf: float, wlf: WLF) -> Any:
        """Fit the Prony series to the target (a :class:`~rubberfriction.forms.prony.PronyFit`)."""
        from rubberfriction.forms.prony import fit_prony

        decades = np.log10(self.tau_max / self.tau_min)
        omega = np.logspace(-np.log10(self.tau_max), -np.log10(self.tau_min),
                            int(round(decades * self.points_per_decade)) + 1)
        tau = np.geomspace(self.tau_min, self.tau_max, self.n_terms)
        target = self.target(omega, E_inf, wlf)
        return fit_prony(omega, target.real, target.imag, tau=tau, E_inf=E_inf)


def spectrum_generator(
        name_or_path: str | Path = DEFAULT_COMPOUND) -> tuple[SpectrumGenerator, Compound]:
    """Read ``[prony.generator]`` of a compound file (default: tread_default) and the compound."""
    path = resolve_data_path(name_or_path).resolve()
    doc = _read_toml(path)
    gen = doc.get("prony", {}).get("generator")
    if gen is None:
        raise ValueError(f"{path}: no [prony.generator] table")
    gen = _check_keys(f"{path} [prony.generator]", dict(gen), GENERATOR_KEYS,
                      GENERATOR_KEYS - {"points_per_decade"})
    if gen.pop("model") != "havriliak_negami":
        raise ValueError(f"{path} [prony.generator].model: expected 'havriliak_negami'")
    T_unit = _check_units(path, doc, "thermal" in doc)
    gen["Tg"] = _to_kelvin(gen["Tg"], T_unit, f"{path} [prony.generator].Tg")
    return SpectrumGenerator(**gen), load_compound(path)


def regenerate_prony_toml(name_or_path: str | Path = DEFAULT_COMPOUND) -> str:
    """Re-run the generator of a compound file and return its ``gamma``/``tau`` TOML lines.

    ``print(rubberfriction.forms.materials.regenerate_prony_toml())``
    reproduces the numbers stored in ``forms/data/tread_default.toml``.
    """
    from rubberfriction.forms.prony import prony_toml

    gen, compound = spectrum_generator(name_or_path)
    if compound.wlf is None:
        raise ValueError(f"{compound.name}: the generator needs the compound's [wlf] table")
    return prony_toml(gen.fit(compound.E_inf, compound.wlf).series)
