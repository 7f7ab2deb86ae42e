"""The default viscoelastic spectrum (``tread_default.toml``): a reproducible generator.

The illustrative default compound's Prony series is not measured: it is fitted to a smooth
Havriliak-Negami target whose parameters the compound file keeps in ``[prony.generator]``, so the
stored numbers can be regenerated (:func:`regenerate_prony_toml`) and checked by a test.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rubberfriction import validation as V
from rubberfriction.forms.compound import WLF, Compound
from rubberfriction.forms.material_files import (
    DEFAULT_COMPOUND,
    check_units,
    read_toml,
    to_kelvin,
    load_compound,
    resolve_data_path,
)
from rubberfriction.forms.prony import fit_prony, havriliak_negami, hn_loss_peak_omega, prony_toml


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
            object.__setattr__(self, name, V.positive(f"{own}.{name}", getattr(self, name), unit))
        for name in ("alpha", "beta"):
            value = V.positive(f"{own}.{name}", getattr(self, name), "-")
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
        w_peak = 2 * np.pi * self.peak_frequency_Hz(wlf)
        return hn_loss_peak_omega(1.0, self.alpha, self.beta) / w_peak

    def target(self, omega: Any, E_inf: float, wlf: WLF) -> np.ndarray:
        """The smooth target E*(omega) at T_ref, MPa."""
        return havriliak_negami(omega, E_inf, self.E_glassy, self.tau_hn(wlf), self.alpha,
                                self.beta)

    def fit(self, E_inf: float, wlf: WLF) -> Any:
        """Fit the Prony series to the target (a :class:`~rubberfriction.forms.prony.PronyFit`)."""
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
    doc = read_toml(path)
    gen = doc.get("prony", {}).get("generator")
    if gen is None:
        raise ValueError(f"{path}: no [prony.generator] table")
    gen = V.table(f"{path} [prony.generator]", dict(gen), GENERATOR_KEYS,
                  GENERATOR_KEYS - {"points_per_decade"})
    if gen.pop("model") != "havriliak_negami":
        raise ValueError(f"{path} [prony.generator].model: expected 'havriliak_negami'")
    T_unit = check_units(path, doc, "thermal" in doc)
    gen["Tg"] = to_kelvin(gen["Tg"], T_unit, f"{path} [prony.generator].Tg")
    return SpectrumGenerator(**gen), load_compound(path)


def regenerate_prony_toml(name_or_path: str | Path = DEFAULT_COMPOUND) -> str:
    """Re-run the generator of a compound file and return its ``gamma``/``tau`` TOML lines.

    ``print(rubberfriction.forms.spectrum.regenerate_prony_toml())``
    reproduces the numbers stored in ``forms/data/tread_default.toml``.
    """
    gen, compound = spectrum_generator(name_or_path)
    if compound.wlf is None:
        raise ValueError(f"{compound.name}: the generator needs the compound's [wlf] table")
    return prony_toml(gen.fit(compound.E_inf, compound.wlf).series)
