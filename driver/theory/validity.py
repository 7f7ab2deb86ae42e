"""Plausibility of an analytical baseline: where a theory's result is outside its validity.

The baselines are evaluated wherever a user asks, also on surfaces and speeds their
assumptions do not cover.  This module states those assumptions as checks on a computed
:class:`~rubberfriction.driver.theory.curves.TheoryCurve`, so that the command line, the JSON and
the plots flag a curve instead of printing a mu of 5 without comment:

* every model: mu above :data:`MU_PLAUSIBLE` (measured rubber friction on roads and in the
  thesis stays below about 3); a contact fraction A/A0 outside [0, 1];
* Persson (eq. 2.10 and its line-roughness form): the contact mechanics is linear (small
  slopes); the cumulative rms slope of the spectrum above :data:`SLOPE_PERSSON` is beyond the
  slope where Persson's group cuts a spectrum (Lorenz, Oh, Nam, Jeon, Persson, J. Chem. Phys.
  142, 194701, 2015; the same 1.3 as the scene's slope cut-off);
* Klüppel-Heinrich (eq. 2.9): a self-affine surface needs a Hurst exponent in (0, 1)
  (fractal dimension D = 3 - H in (2, 3)); the Greenwood-Williamson penetration depth <z_p>
  must stay below the roughness height xi_perp (deeper, the summits are flattened and the
  summit statistics no longer describe the contact).

A flag never changes a number: it is a sentence attached to the curve.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: Highest coefficient of friction taken as plausible (rubber on roads, thesis ch. 6-8: < 3).
MU_PLAUSIBLE = 3.0
#: Largest cumulative rms slope of a spectrum for Persson's theory (Lorenz et al. 2015).
SLOPE_PERSSON = 1.3


@dataclass(frozen=True)
class ValidityFlag:
    """One assumption a curve violates: the model, what is off, and a sentence for users."""

    model: str
    quantity: str
    message: str

    def to_dict(self) -> dict[str, str]:
        return {"model": self.model, "quantity": self.quantity, "message": self.message}


def _speeds(v: np.ndarray, mask: np.ndarray) -> str:
    """``v = a..b mm/s`` over the speeds where ``mask`` holds."""
    sel = v[mask]
    if sel.size == 1:
        return f"v = {sel[0]:.3g} mm/s"
    return f"v = {sel.min():.3g}..{sel.max():.3g} mm/s"


def validity_flags(curve: Any) -> list[ValidityFlag]:
    """The assumptions of ``curve.model`` that ``curve`` (a ``TheoryCurve``) violates."""
    flags: list[ValidityFlag] = []
    model = curve.model
    v = np.asarray(curve.v, dtype=float)
    mu = np.asarray(curve.mu, dtype=float)
    high = np.isfinite(mu) & (mu > MU_PLAUSIBLE)
    if np.any(high):
        flags.append(ValidityFlag(
            model, "mu",
            f"mu up to {float(mu[high].max()):.3g} > {MU_PLAUSIBLE:g} at {_speeds(v, high)}: "
            "beyond measured rubber friction; the theory is outside its validity there"))
    if curve.area is not None:
        area = np.asarray(curve.area, dtype=float)
        bad = np.isfinite(area) & ((area < 0.0) | (area > 1.0 + 1e-9))
        if np.any(bad):
            flags.append(ValidityFlag(
                model, "area",
                f"contact fraction A/A0 outside [0, 1] at {_speeds(v, bad)}"))
    extra = curve.extra or {}
    if model.startswith("persson"):
        slope = extra.get("slope_rms")
        if slope is not None and float(slope) > SLOPE_PERSSON:
            flags.append(ValidityFlag(
                model, "slope",
                f"cumulative rms slope {float(slope):.3g} > {SLOPE_PERSSON:g}: Persson's "
                "contact mechanics assumes small slopes (Lorenz et al. 2015 cut spectra at "
                "1.3); cut the spectrum (--lambda-min, scene [surface] cutoff)"))
    if model == "kluppel-heinrich":
        H = extra.get("H")
        if H is not None and not 0.0 < float(H) < 1.0:
            flags.append(ValidityFlag(
                model, "hurst",
                f"Hurst exponent {float(H):.3g} outside (0, 1): the surface is not self-affine "
                "over the fitted range (fractal dimension outside 2..3)"))
        z_p, xi_perp = extra.get("z_p_mm"), extra.get("xi_perp_mm")
        if z_p is not None and xi_perp is not None:
            zp = np.broadcast_to(np.asarray(z_p, dtype=float), v.shape)
            deep = np.isfinite(zp) & (zp > float(xi_perp))
            if np.any(deep):
                flags.append(ValidityFlag(
                    model, "penetration",
                    f"penetration depth <z_p> up to {float(zp[deep].max()):.3g} mm > xi_perp "
                    f"{float(xi_perp):.3g} mm at {_speeds(v, deep)}: the summits are flattened, "
                    "Greenwood-Williamson statistics no longer apply"))
    return flags
