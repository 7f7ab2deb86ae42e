"""FE contact patch test (non-matching meshes) and thermal two-bar test -- the exact cases.

The closed forms are evaluated here, from the parameters the test passes:

* patch test: both blocks are in the same homogeneous plane-strain state of the neo-Hooke solid
  under the dead load q on top (stretches from sigma_xx = 0, -sigma_zz lambda_x = q, solved with
  the closed-form stress of ``fe_helpers``); the contact pressure at every slave node and
  -sigma_zz everywhere equal q/lambda_x, the total contact force is q L (force balance) and every
  slave node is in contact.  Segment-to-segment (mortar) must reproduce this exactly (1e-10
  relative; achieved ~1e-14) across non-matching meshes; node-to-segment is run too and its
  (expected) failure is recorded, not hidden.
* thermal bars: q = (T_top - T_bottom)/(L1/k1 + 1/h_c + L2/k2), h_c = h0 + h1 p^beta,
  p = c_N x penetration; heat q w in at the top and out at the bottom, interface jump q/h_c;
  frictional heat W = mu p v A, v = (slide - mu p/c_T)/dt, A = w - slide, split kappa W (slave,
  upper bar) and (1 - kappa) W (master).
"""

from __future__ import annotations

import math

import pytest

from fe_helpers import checks_of, plane_strain_compression, rel
from rubberfriction.driver.fe.contact import DEFAULT_TANGENTIAL_FRACTION
from rubberfriction.driver.verification.patch import patch
from rubberfriction.driver.verification.thermal_bars import thermal_bars

PATCH = dict(E=10.0, nu=0.3, pressure=0.1, length=1.0)
PATCH_CHECKS = {"slave nodes in contact", "contact pressure min", "contact pressure max",
                "total contact force F_z", "sigma_zz upper (max dev.)", "sigma_zz lower (max dev.)"}
PATCH_TOL = 1e-10  # product: 1e-8


def patch_exact(E, nu, pressure, length):
    """(contact pressure = -sigma_zz, total force) of the homogeneous solution."""
    lam_x, _ = plane_strain_compression(E, nu, pressure)
    return pressure / lam_x, pressure * length


@pytest.mark.parametrize("n_upper,n_lower,element",
                         [(7, 5, "Q1P0"), (4, 9, "Q1P0"), (7, 5, "Q1P0s")])
def test_patch_mortar_exact(n_upper, n_lower, element):
    """Exact with the stabilised element too: a uniform pressure has no jumps."""
    r = patch(n_upper=n_upper, n_lower=n_lower, method="mortar", element=element, **PATCH)
    by = checks_of(r, PATCH_CHECKS)
    p_exact, force = patch_exact(**PATCH)
    assert by["slave nodes in contact"]["computed"] == n_upper + 1  # every slave node
    for q in ("contact pressure min", "contact pressure max"):
        assert rel(by[q]["computed"], p_exact) <= PATCH_TOL, by[q]
    assert rel(by["total contact force F_z"]["computed"], force) <= PATCH_TOL
    # the worst quadrature point
    for q in ("sigma_zz upper (max dev.)", "sigma_zz lower (max dev.)"):
        assert rel(by[q]["computed"], -p_exact) <= PATCH_TOL, by[q]
    assert (r["pressure_spread"] < 1e-10 and r["stress_spread_lower"] < 1e-10
            and r["stress_spread_upper"] < 1e-10)


def test_patch_node_to_segment_fails_as_known():
    """One-pass node-to-segment on non-matching meshes: total force right, distribution wrong."""
    r = patch(method="nts", **PATCH)
    by = checks_of(r, PATCH_CHECKS)
    p_exact, force = patch_exact(**PATCH)
    assert rel(by["total contact force F_z"]["computed"], force) <= PATCH_TOL
    spread = ((by["contact pressure max"]["computed"] - by["contact pressure min"]["computed"])
              / p_exact)
    assert spread > 0.1 and r["pressure_spread"] > 0.1 and r["stress_spread_lower"] > 0.1
    assert rel(by["sigma_zz lower (max dev.)"]["computed"], -p_exact) > 0.1


BARS = dict(L1=0.5, L2=1.0, k1=0.25, k2=50.0, width=1.0, h0=2.0, h1=0.5, beta=1.0, T_top=400.0,
            T_bottom=300.0, penetration=1e-4, c_N=1e3, mu=0.5, kappa=0.3, slide=0.01, dt=1e-3)
BARS_CHECKS = {"conduction: heat in at top", "conduction: heat out at bottom",
               "conduction: interface jump", "friction: total heat W", "friction: slave share",
               "friction: master share", "friction: W from contact state"}


def bars_exact(L1, L2, k1, k2, width, h0, h1, beta, T_top, T_bottom, penetration, c_N, mu, kappa,
               slide, dt):
    p = c_N * penetration
    hc = h0 + h1 * p ** beta
    q = (T_top - T_bottom) / (L1 / k1 + 1.0 / hc + L2 / k2)
    c_T = DEFAULT_TANGENTIAL_FRACTION * c_N  # the case's penalty: PenaltySettings(c_N=c_N)
    v = (slide - mu * p / c_T) / dt
    W = mu * p * v * (width - slide)
    return {"conduction: heat in at top": q * width, "conduction: heat out at bottom": q * width,
            "conduction: interface jump": q / hc, "friction: total heat W": W,
            "friction: slave share": kappa * W, "friction: master share": (1.0 - kappa) * W,
            "friction: W from contact state": W}


def test_thermal_bars_mortar_exact():
    r = thermal_bars(method="mortar", **BARS)
    by = checks_of(r, BARS_CHECKS)
    exact = bars_exact(**BARS)
    assert (exact["friction: total heat W"] > 0.0
            and math.isfinite(exact["conduction: heat in at top"]))
    for q, value in exact.items():
        # product: 1e-8 (conduction), 1e-6 (friction); achieved <= 5e-12
        assert rel(by[q]["computed"], value) <= 1e-9, (q, by[q], value)


def test_thermal_bars_node_to_segment_reported():
    r = thermal_bars(method="nts", **BARS)
    by = checks_of(r, BARS_CHECKS)
    exact = bars_exact(**BARS)
    # nodal collocation: conductance error ~1e-4 on non-matching meshes, and the slave node that
    # overhangs the master after sliding loses its share of the frictional heat
    jump = rel(by["conduction: interface jump"]["computed"], exact["conduction: interface jump"])
    assert 1e-6 < jump < 1e-3
    assert rel(by["friction: total heat W"]["computed"], exact["friction: total heat W"]) > 1e-2
