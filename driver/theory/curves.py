"""mu(v) curves of all analytical theories from one profile PSD, and their plots.

This is the glue the ``rubberfriction theory`` command, the benchmark and the multiscale report
use: one measured (or generated) profile PSD C1D, one rubber, one pressure, a list of speeds ->
one :class:`TheoryCurve` per model:

* ``"persson-1d"``: Persson's theory for line roughness (plane strain), fed with C1D directly:
  the fair comparison with the 2D FE (:mod:`.persson`);
* ``"persson-2d"``: eq. (2.10) for an isotropic surface with the same profile statistics; the 2D
  PSD comes from C1D by the exact inverse Abel transform
  (:func:`rubberfriction.driver.surfaces.psd_iso_from_1d`) of the log-binned C1D (negative
  values from noisy bins are clipped to 0 and reported);
* ``"kluppel-heinrich"``: eq. (2.9) with descriptors fitted to C1D over the same range
  (:mod:`.kluppel`).

With a bell law (eq. 7.6) the Persson curves add ``alpha mu_A`` with ``A/A0 = P(q_max)``
(eqs. 2.11, 7.3).  Every curve carries its plausibility flags (:mod:`.validity`: mu above 3,
a contact fraction outside [0, 1], an assumption of the theory broken), computed where the curve
is made; the plots draw a flagged curve faded with "(outside validity)" in its label.  All
speeds in mm/s, pressure in MPa, temperatures in K.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.surfaces.psd import log_bin, psd_iso_from_1d
from rubberfriction.driver.theory.adhesion import BellLaw
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.flash import FlashOptions
from rubberfriction.driver.theory.kluppel import descriptors_from_psd, kluppel_heinrich_friction
from rubberfriction.driver.theory.persson import PerssonOptions, persson_friction
from rubberfriction.driver.theory.rubber import Rubber
from rubberfriction.driver.theory.spectrum import DEFAULT_NODES, Spectrum, spectrum_from_psd
from rubberfriction.driver.theory.validity import ValidityFlag, validity_flags

MODELS: tuple[str, ...] = ("persson-1d", "persson-2d", "kluppel-heinrich")
LABELS = {
    "persson-1d": "Persson, line roughness (plane strain)",
    "persson-2d": "Persson eq. (2.10), isotropic",
    "kluppel-heinrich": "Klüppel-Heinrich eq. (2.9)",
}
#: Legend suffix and line opacity of a curve with validity flags.
OUTSIDE_LABEL = " (outside validity)"
OUTSIDE_ALPHA = 0.35


@dataclass
class TheoryCurve:
    """One model's mu(v); arrays over ``v`` (mm/s)."""

    model: str
    label: str
    v: np.ndarray
    mu: np.ndarray                          #: total: mu_H + alpha mu_A
    mu_hysteresis: np.ndarray               #: mu_H
    mu_adhesion: np.ndarray | None = None   #: mu_A (without alpha)
    area: np.ndarray | None = None          #: A/A0 (Persson: P(q_max))
    flash_dT: np.ndarray | None = None      #: T(q_max) - T0 (K), with flash temperature
    extra: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    #: the theory's assumptions this curve violates (:func:`.validity.validity_flags`)
    flags: list[ValidityFlag] = field(default_factory=list)

    def flagged(self) -> "TheoryCurve":
        """This curve with its validity flags computed (replacing any held); returns self."""
        self.flags = validity_flags(self)
        return self

    @property
    def plot_label(self) -> str:
        """The legend label: ``label``, plus "(outside validity)" when flagged."""
        return self.label + (OUTSIDE_LABEL if self.flags else "")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (lists instead of arrays)."""
        def arr(x: np.ndarray | None) -> list[float] | None:
            return None if x is None else [float(a) for a in np.asarray(x)]

        return {
            "model": self.model, "label": self.label, "v_mm_s": arr(self.v), "mu": arr(self.mu),
            "mu_hysteresis": arr(self.mu_hysteresis), "mu_adhesion": arr(self.mu_adhesion),
            "area_ratio": arr(self.area), "flash_dT_K": arr(self.flash_dT),
            "extra": {k: (arr(v) if isinstance(v, np.ndarray) else v)
                      for k, v in self.extra.items()},
            "notes": list(self.notes),
            "flags": [f.to_dict() for f in self.flags],
        }


def iso_psd_from_profile_psd(q: np.ndarray, C1D: np.ndarray, bins_per_decade: int = 20
                             ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Isotropic 2D PSD (Persson convention) from a profile PSD by the inverse Abel transform."""
    q = np.asarray(q, dtype=float)
    C1D = np.asarray(C1D, dtype=float)
    ok = (q > 0) & (C1D > 0)
    qb, cb, _ = log_bin(q[ok], C1D[ok], bins_per_decade=bins_per_decade)
    with np.errstate(over="ignore"):          # cosh overflow in the far power-law tail -> 0
        C2 = psd_iso_from_1d(qb, cb, None)
    notes = []
    neg = C2 < 0
    if np.any(neg):
        notes.append(f"2D PSD: {int(neg.sum())} of {neg.size} log bins came out negative from the "
                     "Abel transform of noisy C1D and were set to 0")
        C2 = np.where(neg, 0.0, C2)
    # the bin centres lie inside the data range: extend to its ends along the end slopes
    q_lo, q_hi = float(q[ok][0]), float(q[ok][-1])
    if qb.size >= 2 and np.all(C2[:2] > 0) and np.all(C2[-2:] > 0):
        s_lo = math.log(C2[1] / C2[0]) / math.log(qb[1] / qb[0])
        s_hi = math.log(C2[-1] / C2[-2]) / math.log(qb[-1] / qb[-2])
        if q_lo < qb[0]:
            qb, C2 = np.insert(qb, 0, q_lo), np.insert(C2, 0, C2[0] * (q_lo / qb[0]) ** s_lo)
        if q_hi > qb[-1]:
            qb, C2 = np.append(qb, q_hi), np.append(C2, C2[-1] * (q_hi / qb[-1]) ** s_hi)
    return qb, C2, notes


def theory_curves(
    q: np.ndarray,
    C1D: np.ndarray,
    rubber: Rubber,
    pressure: float,
    velocities: Sequence[float] | np.ndarray,
    *,
    T0: float | None = None,
    models: Sequence[str] = MODELS,
    qmin: float | None = None,
    qmax: float | None = None,
    flash: bool | FlashOptions = False,
    adhesion: BellLaw | None = None,
    alpha: float = 1.0,
    options: PerssonOptions | None = None,
    n_nodes: int = DEFAULT_NODES,
) -> list[TheoryCurve]:
    """mu(v) of the requested models from one profile PSD (q in 1/mm, C1D in mm^3).

    ``qmin``/``qmax`` (1/mm) restrict the wavenumber range of all models; default: the PSD's.
    """
    unknown = [m for m in models if m not in MODELS]
    if unknown:
        raise TheoryInputError(f"unknown model(s) {unknown}; expected some of {list(MODELS)}")
    q = np.asarray(q, dtype=float)
    C1D = np.asarray(C1D, dtype=float)
    pos = q > 0
    if not np.any(pos):
        raise TheoryInputError("the PSD has no wavenumbers q > 0")
    lo = float(q[pos][0]) if qmin is None else float(qmin)
    hi = float(q[pos][-1]) if qmax is None else float(qmax)
    v = np.asarray(velocities, dtype=float)
    curves: list[TheoryCurve] = []
    for model in models:
        if model in ("persson-1d", "persson-2d"):
            notes: list[str] = []
            if model == "persson-1d":
                spec = spectrum_from_psd(q, C1D, 1, lo, hi, n_nodes=n_nodes, source="profile PSD")
            else:
                q2, C2, notes = iso_psd_from_profile_psd(q, C1D)
                lo2, hi2 = max(lo, q2[0]), min(hi, q2[-1])
                if (lo2 > lo * 1.0001) or (hi2 < hi * 0.9999):
                    notes.append(f"2D PSD range {lo2:.4g}..{hi2:.4g} 1/mm (log-bin centres) is "
                                 f"narrower than the requested {lo:.4g}..{hi:.4g} 1/mm")
                spec = spectrum_from_psd(q2, C2, 2, lo2, hi2, n_nodes=n_nodes,
                                         source="Abel transform of the profile PSD")
            curves.append(persson_curve(spec, rubber, pressure, v, T0=T0, options=options,
                                        flash=flash, adhesion=adhesion, alpha=alpha, notes=notes))
        else:
            desc = descriptors_from_psd(q, C1D, lo, hi)
            kh = kluppel_heinrich_friction(desc, 2 * math.pi / hi, rubber, pressure, v, T0=T0)
            notes = ["isothermal (no flash temperature in eq. 2.9)"] if flash else []
            mu_a = None
            mu = kh.mu
            if adhesion is not None:
                notes.append("no contact area in the KH model: adhesion not added")
            curves.append(TheoryCurve(
                model=model, label=LABELS[model], v=kh.v, mu=mu, mu_hysteresis=kh.mu,
                mu_adhesion=mu_a, area=None,
                extra={"xi_par_mm": desc.xi_par, "xi_perp_mm": desc.xi_perp, "H": desc.H,
                       "lambda_min_mm": kh.lambda_min, "z_p_mm": kh.z_p},
                notes=notes).flagged())
    return curves


def persson_curve(
    spec: Spectrum,
    rubber: Rubber,
    pressure: float,
    velocities: Sequence[float] | np.ndarray,
    *,
    T0: float | None = None,
    options: PerssonOptions | None = None,
    flash: bool | FlashOptions = False,
    adhesion: BellLaw | None = None,
    alpha: float = 1.0,
    notes: list[str] | None = None,
) -> TheoryCurve:
    """Persson's mu(v) (variant by ``spec.dim``) as a :class:`TheoryCurve`; works for line
    spectra too (e.g. the sine-wave scenes, where the 1D theory in full contact is exact)."""
    model = "persson-1d" if spec.dim == 1 else "persson-2d"
    notes = list(notes or [])
    res = persson_friction(spec, rubber, pressure, np.asarray(velocities, dtype=float), T0=T0,
                           options=options, flash=flash, adhesion=adhesion, alpha=alpha)
    if res.converged is not None and not np.all(res.converged):
        notes.append("flash-temperature iteration did not converge at v = "
                     + ", ".join(f"{x:g}" for x in res.v[~res.converged]) + " mm/s")
    return TheoryCurve(
        model=model, label=LABELS[model], v=res.v, mu=res.mu_total, mu_hysteresis=res.mu,
        mu_adhesion=res.mu_adhesion, area=res.area, flash_dT=res.flash_temperature,
        extra={"q_range_1_mm": [spec.q_min, spec.q_max], "h_rms_mm": spec.h_rms,
               "slope_rms": spec.slope_rms, "gamma": res.options.gamma},
        notes=notes).flagged()


def plot_curves(curves: Sequence[TheoryCurve], path: str | Path, *, title: str = "",
                fe: dict[str, Any] | None = None) -> Path:
    """Plot mu(v), A/A0(v) (and the flash temperature if computed) to ``path`` (matplotlib Agg).

    ``fe`` (optional): FE results to show beside the theories, a dict with ``v`` (mm/s), ``mu``
    and optionally ``mu_err`` (standard error over samples) and ``area`` (A/A0, eq. 7.5).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hot = [c for c in curves if c.flash_dT is not None]
    fig, axes = plt.subplots(1, 3 if hot else 2, figsize=(16 if hot else 11, 4.2))
    add_to_axes(curves, axes[0], axes[1], fe=fe)
    if hot:
        for c in hot:
            axes[2].semilogx(c.v, c.flash_dT, label=c.plot_label,
                             alpha=OUTSIDE_ALPHA if c.flags else 1.0)
        axes[2].set_xlabel("sliding speed v (mm/s)")
        axes[2].set_ylabel("flash temperature T(q1) - T0 (K)")
        axes[2].grid(True, which="both", alpha=0.3)
        axes[2].legend(fontsize=7)
    lines = textwrap.wrap(title, 130 if hot else 95)  # a long surface label: two lines
    if lines:
        fig.suptitle("\n".join(lines), fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - 0.045 * max(len(lines) - 1, 0)))
    path = Path(path)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def add_to_axes(curves: Sequence[TheoryCurve], ax_mu: Any, ax_area: Any | None = None,
                fe: dict[str, Any] | None = None) -> None:
    """Draw theory curves (and optionally FE points) on existing axes: for the multiscale report.

    A curve with validity flags is drawn faded (alpha :data:`OUTSIDE_ALPHA`) and labelled
    "... (outside validity)"."""
    styles = {"persson-1d": "-", "persson-2d": "--", "kluppel-heinrich": ":"}
    for c in curves:
        ls = styles.get(c.model, "-")
        a = OUTSIDE_ALPHA if c.flags else 1.0
        line, = ax_mu.semilogx(c.v, c.mu, ls, label=c.plot_label, alpha=a)
        if c.mu_adhesion is not None:
            ax_mu.semilogx(c.v, c.mu_hysteresis, ls, color=line.get_color(), alpha=0.4 * a,
                           label=f"{c.plot_label}: hysteresis only")
        if ax_area is not None and c.area is not None:
            ax_area.loglog(c.v, c.area, ls, color=line.get_color(), label=c.plot_label, alpha=a)
    if fe is not None:
        fv = np.asarray(fe["v"], dtype=float)
        err = fe.get("mu_err")
        ax_mu.errorbar(fv, fe["mu"], yerr=err, fmt="ko", ms=5, capsize=3, label="FE multiscale")
        if ax_area is not None and fe.get("area") is not None:
            ax_area.loglog(fv, fe["area"], "ko", ms=5, label="FE multiscale (eq. 7.5)")
    ax_mu.set_xlabel("sliding speed v (mm/s)")
    ax_mu.set_ylabel("friction coefficient mu")
    ax_mu.grid(True, which="both", alpha=0.3)
    ax_mu.legend(fontsize=7)
    if ax_area is not None:
        ax_area.set_xlabel("sliding speed v (mm/s)")
        ax_area.set_ylabel("relative contact area A/A0")
        ax_area.grid(True, which="both", alpha=0.3)
        if ax_area.lines:
            ax_area.legend(fontsize=7)
