"""Material value objects of the rubber compounds and the road (thesis ch. 3.3.1, 3.3.3, app. A
and C).

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
:func:`rubberfriction.forms.material_files.load_compound` and ``load_road``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rubberfriction import validation as V

ZERO_CELSIUS = 273.15  # K


def _as_output(x: Any) -> float | np.ndarray:
    """A float for 0-d results, the array otherwise."""
    return float(x) if np.ndim(x) == 0 else np.asarray(x)


# --------------------------------------------------------------------------------------------
# hyperelastic equilibrium part
# --------------------------------------------------------------------------------------------

MR_FORMS = ("split", "feap")
#: volumetric energies of the split form, Psi_vol = K/2 g(J)^2 (``forms/hyperelastic.py``)
VOLUMETRIC_FORMS = ("quadratic", "logarithmic")


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

    ``volumetric`` (split form only) chooses the volumetric energy with the same small-strain K:
    ``"quadratic"`` is (J - 1)^2 / D1 above (eq. 3.78, the default); ``"logarithmic"`` is
    (ln J)^2 / D1, whose pressure grows without bound as J -> 0 where the quadratic one cannot
    exceed K (``forms/hyperelastic.py``).  It matters where the rubber's hydrostatic pressure
    approaches K: the lowest scales of a rough-road cascade.

    Interpretation: these constants describe the LONG-TERM (equilibrium) response; the thesis
    fits them to quasi-static tests (ch. 3.3.3).  Validation: C10 > 0, C01 >= 0 (C01 = 0 is
    neo-Hooke; negative C01 is rejected as a sufficient condition for stability), D1 > 0.
    """

    C10: float
    C01: float
    D1: float
    form: str = "split"
    volumetric: str = "quadratic"

    def __post_init__(self) -> None:
        object.__setattr__(self, "C10", V.positive("MooneyRivlin.C10", self.C10, "MPa"))
        object.__setattr__(self, "C01", V.nonnegative("MooneyRivlin.C01", self.C01, "MPa"))
        object.__setattr__(self, "D1", V.positive("MooneyRivlin.D1", self.D1, "1/MPa"))
        if self.form not in MR_FORMS:
            raise ValueError(f"MooneyRivlin.form = {self.form!r}: expected one of {MR_FORMS}")
        if self.volumetric not in VOLUMETRIC_FORMS:
            raise ValueError(f"MooneyRivlin.volumetric = {self.volumetric!r}: expected one of "
                             f"{VOLUMETRIC_FORMS}")
        if self.form == "feap" and self.volumetric != "quadratic":
            raise ValueError("MooneyRivlin.volumetric applies to the split form; the feap form "
                             "(eq. 3.53) has its own volumetric term")

    @classmethod
    def neo_hooke(cls, mu: float, K: float, form: str = "split") -> MooneyRivlin:
        """Neo-Hooke as the special case C01 = 0: C10 = mu/2, D1 = 2/K (eq. A.8)."""
        mu = V.positive("MooneyRivlin.neo_hooke.mu", mu, "MPa")
        K = V.positive("MooneyRivlin.neo_hooke.K", K, "MPa")
        return cls(C10=mu / 2.0, C01=0.0, D1=2.0 / K, form=form)

    @classmethod
    def from_blatz_ko(cls, E: float, nu: float, f: float, form: str = "split") -> MooneyRivlin:
        """Thesis eq. (3.60): C10 = E f / (4(1+nu)), C01 = E (1-f) / (4(1+nu)), D1 = 6(1-2nu)/E."""
        E = V.positive("MooneyRivlin.from_blatz_ko.E", E, "MPa")
        nu = V.real("MooneyRivlin.from_blatz_ko.nu", nu, "-")
        f = V.real("MooneyRivlin.from_blatz_ko.f", f, "-")
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
        mu1 = V.positive("MooneyRivlin.from_feap.mu1", mu1, "MPa")
        mu2 = V.nonnegative("MooneyRivlin.from_feap.mu2", mu2, "MPa")
        lam = V.real("MooneyRivlin.from_feap.lam", lam, "MPa")
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
        gamma = V.float_array("PronySeries.gamma", self.gamma, "-")
        tau = V.float_array("PronySeries.tau", self.tau, "s")
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
        E_inf = V.positive("PronySeries.from_moduli.E_inf", E_inf, "MPa")
        E_k = V.float_array("PronySeries.from_moduli.E_k", E_k, "MPa")
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
        return V.positive("PronySeries.E_inf", E_inf, "MPa") / self.gamma_inf

    def moduli(self, E_inf: float) -> np.ndarray:
        """Absolute moduli E_k = gamma_k E0 of the Maxwell springs, MPa."""
        return self.gamma * self.E0(E_inf)

    def complex_modulus(self, omega: Any, E_inf: float) -> complex | np.ndarray:
        """E*(omega) = E' + i E'' (eq. 3.34); omega in rad/s (>= 0), result in MPa.

        With the shear modulus G_inf in place of E_inf it gives G*(omega) (gamma_k = G_k/G0).
        """
        value = prony_complex_modulus(_omega(omega), E_inf, self.moduli(E_inf), self.tau)
        return complex(value) if np.ndim(value) == 0 else value

    def storage(self, omega: Any, E_inf: float) -> float | np.ndarray:
        """Storage modulus E'(omega) = E_inf + sum E_k (w tau)^2 / (1 + (w tau)^2) (eq. 3.34)."""
        return _as_output(np.real(self.complex_modulus(omega, E_inf)))

    def loss(self, omega: Any, E_inf: float) -> float | np.ndarray:
        """Loss modulus E''(omega) = sum E_k w tau / (1 + (w tau)^2) (eq. 3.34)."""
        return _as_output(np.imag(self.complex_modulus(omega, E_inf)))

    def relaxation(self, t: Any, E_inf: float) -> float | np.ndarray:
        """Relaxation modulus E(t) = E0 (gamma_inf + sum gamma_k exp(-t / tau_k)), t >= 0 in s."""
        tt = V.finite_array("PronySeries.relaxation.t", t, "s")
        if (tt < 0).any():
            raise ValueError(f"PronySeries.relaxation.t: min {tt.min()!r}: expected t >= 0 s")
        decay = np.exp(-np.divide.outer(tt, self.tau)) @ self.gamma
        return _as_output(self.E0(E_inf) * (self.gamma_inf + decay))

    def shifted(self, factor: float) -> PronySeries:
        """The same spectrum with every tau multiplied by ``factor`` (e.g. a(T), eq. 3.37)."""
        factor = V.positive("PronySeries.shifted.factor", factor, "-")
        return PronySeries(self.gamma, self.tau * factor)

    def pruned(self) -> PronySeries:
        """Drop terms with gamma_k == 0 (they carry no stress but cost internal variables)."""
        keep = self.gamma > 0
        return PronySeries(self.gamma[keep], self.tau[keep])


def prony_complex_modulus(omega: Any, M_inf: float, M_k: Any, tau: Any) -> np.ndarray:
    """M*(omega) = M_inf + sum_k M_k i omega tau_k / (1 + i omega tau_k) (eq. 3.34), complex.

    The one evaluation of a Prony series in the frequency domain: Young's (E_inf, E_k) or shear
    (G_inf, G_k) moduli alike, MPa; omega (rad/s, >= 0, any shape), tau_k in s.  Written in real
    arithmetic, M' = M_inf + sum M_k x^2 d and M'' = sum M_k x d with x = omega tau_k and
    d = 1 / (1 + x^2) (faster than complex division).  No input checks: callers validate once.
    """
    w = np.asarray(omega, dtype=float)
    x = w.reshape(-1, 1) * np.asarray(tau, dtype=float)
    d = 1.0 / (1.0 + x * x)
    M_k = np.asarray(M_k, dtype=float)
    return (M_inf + (x * x * d) @ M_k + 1j * ((x * d) @ M_k)).reshape(w.shape)


def _omega(omega: Any) -> np.ndarray:
    w = V.finite_array("complex_modulus.omega", omega, "rad/s")
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
        object.__setattr__(self, "c1", V.positive("WLF.c1", self.c1, "- (dimensionless)"))
        object.__setattr__(self, "c2", V.positive("WLF.c2", self.c2, "K"))
        T_ref = V.positive("WLF.T_ref", self.T_ref, "K (absolute temperature)")
        object.__setattr__(self, "T_ref", T_ref)

    @classmethod
    def from_celsius(cls, c1: float, c2: float, T_ref_C: float) -> WLF:
        """Convenience: the reference temperature given in degC."""
        return cls(c1, c2, V.real("WLF.from_celsius.T_ref_C", T_ref_C, "degC") + ZERO_CELSIUS)

    @property
    def T_singular(self) -> float:
        """T_ref - c2 in K: the WLF equation diverges there."""
        return self.T_ref - self.c2

    def log10_aT(self, T: Any) -> float | np.ndarray:
        """log10 a(T) (eq. 3.33), vectorised; T in K, T > T_ref - c2."""
        TT = V.finite_array("WLF.log10_aT.T", T, "K")
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
        tau_arr = V.finite_array("WLF.shift_tau.tau", tau, "s")
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
        object.__setattr__(self, "rho", V.positive("Thermal.rho", self.rho, "t/mm^3"))
        object.__setattr__(self, "c", V.positive("Thermal.c", self.c, "mJ/(t K)"))
        object.__setattr__(self, "k", V.positive("Thermal.k", self.k, "mW/(mm K)"))

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
        V.text("Compound.name", self.name, empty_ok=False)
        V.instance("Compound.hyperelastic", self.hyperelastic, MooneyRivlin)
        V.instance("Compound.prony", self.prony, PronySeries, optional=True)
        V.instance("Compound.wlf", self.wlf, WLF, optional=True)
        V.instance("Compound.thermal", self.thermal, Thermal, optional=True)
        V.text("Compound.description", self.description)
        V.text("Compound.source", self.source)

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
        return np.multiply(omega, self.wlf.aT(V.positive("Compound.T", T, "K")))

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
             f"C01 = {mr.C01:g} MPa, D1 = {mr.D1:g} 1/MPa"
             + (f", {mr.volumetric} volumetric energy" if mr.form == "split" else ""),
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
        V.text("Road.name", self.name, empty_ok=False)
        object.__setattr__(self, "E", V.positive("Road.E", self.E, "MPa"))
        nu = V.real("Road.nu", self.nu, "-")
        if not -1.0 < nu < 0.5:
            raise ValueError(f"Road.nu = {nu!r}: expected -1 < nu < 0.5")
        object.__setattr__(self, "nu", nu)
        V.instance("Road.thermal", self.thermal, Thermal, optional=True)
        V.text("Road.description", self.description)
        V.text("Road.source", self.source)

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
