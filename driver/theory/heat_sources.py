"""Closed forms of surface heating (Carslaw & Jaeger), the oracles of the thermal macro scale.

Units: q in mW/mm^2, k in mW/(mm K), rho in t/mm^3, c in mJ/(t K), t in s, lengths in mm.

* Uniform flux q into a half-space from t = 0: surface temperature rise
  dT(t) = 2 q sqrt(t / (pi k rho c)) = 2 q sqrt(t / pi) / e, with the effusivity e = sqrt(k rho c).
* Two half-spaces in perfect contact, q released at the interface: the interface rises by
  2 q sqrt(t / pi) / (e1 + e2), body i takes the share e_i / (e1 + e2) of the heat.
* Band source q on [0, l] moving at v over the surface of a half-space (2D, steady, in the frame of
  the source): dT(x) = int_0^l q / (pi k) exp(-v xi / (2 chi)) K0(v |xi| / (2 chi)) dx',
  xi = x - x' (positive ahead of the source), chi = k / (rho c) (Jaeger's moving line source, per
  unit depth; the surface source heats one half-space, twice the full-space source).
  The 2D solution exists for every v > 0 but grows like log(chi / (v l)) as the Peclet number
  Pe = v l / (2 chi) goes to 0: the heated region reaches ~ 2 chi / v deep and behind the source,
  which a finite FE road must contain (``moving_band_domain``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate, special


def effusivity(k: float, rho: float, c: float) -> float:
    """e = sqrt(k rho c) in mW s^0.5/(mm^2 K)."""
    return math.sqrt(k * rho * c)


def flash_flux_rise(q: float, t, k: float, rho: float, c: float):
    """Surface temperature rise of a half-space under a uniform flux q switched on at t = 0."""
    return 2.0 * q * np.sqrt(np.asarray(t, float) / math.pi) / effusivity(k, rho, c)


def two_body_rise(q: float, t, e1: float, e2: float):
    """Interface temperature rise of two half-spaces in perfect contact heated at the interface."""
    return 2.0 * q * np.sqrt(np.asarray(t, float) / math.pi) / (e1 + e2)


def moving_band_rise(x, *, q: float, length: float, velocity: float, k: float,
                     chi: float) -> np.ndarray:
    """Steady surface temperature rise at x (in the source frame, band on [0, length], moving
    towards +x) of a band source q moving at `velocity` over a half-space (see module doc)."""
    if velocity <= 0.0:
        raise ValueError(f"moving band source: velocity = {velocity!r}, expected > 0 "
                         "(the 2D static line source has no steady state)")
    s = velocity / (2.0 * chi)

    def side(u: float, x0: float, sign: float) -> float:
        # x' = x0 - sign u^2: dx' = 2 u du removes the log singularity of K0 at x' = x0
        if u == 0.0:
            return 0.0
        xi = sign * u * u
        r = u * u
        # exp(-s xi) K0(s r), written with the scaled K0e = exp(s r) K0 to stay finite behind the
        # source
        return 2.0 * u * math.exp(-s * (xi + r)) * special.k0e(s * r)

    out = []
    for x0 in np.atleast_1d(np.asarray(x, float)):
        val = 0.0
        # band parts behind (x' > x0) and ahead of x0 (x' < x0)
        lo, hi = min(x0, length), max(x0, 0.0)
        if x0 > 0.0:  # sources at x' in [0, min(x0, l)]: xi = x0 - x' > 0
            a, b = math.sqrt(max(x0 - lo, 0.0)), math.sqrt(x0)
            val += integrate.quad(side, a, b, args=(x0, 1.0), limit=200, epsabs=0.0,
                                  epsrel=1e-11)[0]
        if x0 < length:  # sources at x' in [max(x0, 0), l]: xi = x0 - x' < 0
            a, b = math.sqrt(max(hi - x0, 0.0)), math.sqrt(length - x0)
            val += integrate.quad(side, a, b, args=(x0, -1.0), limit=200, epsabs=0.0,
                                  epsrel=1e-11)[0]
        out.append(q / (math.pi * k) * val)
    return np.asarray(out)


def moving_band_domain(length: float, velocity: float, chi: float, *, decay: float = 12.0) -> dict:
    """Road extents (mm) that hold the moving band's temperature field to ~exp(-decay/2): ahead of
    the band the field decays like exp(-v r / chi), below it like exp(-v r / (2 chi)), behind it
    slowly (the wake leaves through an outflow face).  Lengths in units of 2 chi / v."""
    ell = 2.0 * chi / velocity
    return {"decay_length": ell, "ahead": 0.5 * decay * ell, "depth": decay * ell + length,
            "behind": decay * ell + length, "peclet": velocity * length / (2.0 * chi)}
