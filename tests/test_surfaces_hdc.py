"""Height-difference correlation eq. (2.4), its link to the PSD, and the eq. (2.5) fit.

Oracles: a hand-computed HDC; the exact identity C_HDC = 4 sum C1D (1 - cos q lambda) dq for
periodic data; the power-law closed form 2 pi K lambda^2H / (Gamma(1+2H) sin(pi H))
(background notes 3.7) and its band-limited integral; an exact eq. (2.5) curve.
"""

import numpy as np
import pytest
from scipy.integrate import quad

from rubberfriction.driver.surfaces import (
    Profile,
    fit_hdc,
    hdc,
    hdc_from_psd,
    hdc_power_law,
    psd_1d,
    self_affine_profile,
)


def test_hdc_by_hand():
    p = Profile([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 3.0, 2.0])
    lam, c = hdc(p, np.array([1, 2]), periodic=False)
    np.testing.assert_allclose(lam, [1.0, 2.0])
    np.testing.assert_allclose(c, [(1 + 4 + 1) / 3, (9 + 1) / 2])
    lam, c = hdc(p, np.array([1]), periodic=True)  # wraps: (0 - 2)^2 added
    np.testing.assert_allclose(c, [(1 + 4 + 1 + 4) / 4])


def test_hdc_equals_its_psd_form_for_periodic_data():
    p = self_affine_profile(40.96, 0.005, H=0.7, rms_height=0.2, q_rolloff=2 * np.pi / 2.0, seed=3)
    q, c = psd_1d(p, window=None, detrend="mean")
    lags = np.array([1, 3, 10, 33, 100, 333, 1000, 4000])
    lam, ch = hdc(p, lags)  # periodic profile -> circular HDC
    np.testing.assert_allclose(ch, hdc_from_psd(q, c, lam), rtol=1e-10)


@pytest.mark.parametrize("H, lo, hi", [(0.5, 0.02, 0.5), (0.8, 0.01, 0.05), (0.3, 0.1, 0.5)])
def test_hdc_of_a_power_law_profile_matches_the_closed_form(H, lo, hi):
    """Fixed amplitudes, random phases: C1D = K q^-(1+2H) exactly on 2**20 modes.

    In [lo, hi] the neglected parts of the band (q < 2 pi/L, q > pi/dx) change C_HDC by < 2 %
    (checked against the band-limited integral below), so the closed form must hold to 3 %.
    """
    dx = 0.001
    p = self_affine_profile(2**20 * dx, dx, H=H, rms_height=1.0, seed=3, amplitudes="fixed")
    prov = p.meta["provenance"]
    K = prov["C0_mm3"] * prov["q_rolloff"] ** (1 + 2 * H)
    lam_req = np.geomspace(lo, hi, 5)
    lam, c = hdc(p, np.rint(lam_req / dx).astype(int))
    np.testing.assert_allclose(c, hdc_power_law(lam, K, H), rtol=0.03)
    # band-limited continuum integral 4 Int K q^-(1+2H) (1 - cos q lambda) dq over the grid's band
    qlo, qhi = 2 * np.pi / p.length, np.pi / dx
    ref = [quad(lambda u, a=a: 4 * K * np.exp(-2 * H * u) * (1 - np.cos(np.exp(u) * a)),
                np.log(qlo), np.log(qhi), limit=2000)[0] for a in lam]
    np.testing.assert_allclose(c, ref, rtol=0.02)


def test_fit_recovers_eq_2_5_with_plateau():
    H, xi_par, xi_perp = 0.7, 3.0, 0.5
    lam = np.geomspace(0.01, 100, 80)
    rng = np.random.default_rng(0)
    noise = np.exp(0.02 * rng.standard_normal(lam.size))  # 2 % multiplicative scatter
    c = xi_perp**2 * np.minimum(lam / xi_par, 1.0) ** (2 * H) * noise
    fit = fit_hdc(lam, c, (0.02, 80))
    assert fit.plateau_found
    assert fit.H == pytest.approx(H, abs=0.01)
    assert fit.xi_par == pytest.approx(xi_par, rel=0.03)
    assert fit.xi_perp == pytest.approx(xi_perp, rel=0.02)
    assert fit.fit_range == (0.02, 80)
    assert fit.power_law_range[1] == pytest.approx(fit.xi_par)
    np.testing.assert_allclose(fit(lam), c, rtol=0.1)


def test_fit_without_plateau_reports_a_bound():
    lam = np.geomspace(0.01, 1, 30)
    fit = fit_hdc(lam, 0.3 * lam**1.2)
    assert not fit.plateau_found
    assert fit.H == pytest.approx(0.6, abs=1e-10)
    assert fit.xi_par == pytest.approx(1.0)


@pytest.mark.parametrize("H", [0.5, 0.8])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_hdc_fit_recovers_hurst_exponent_of_generated_profiles(H, seed):
    """Gaussian self-affine profile, three decades of power law: H within 0.05 from eq. (2.5)."""
    dx = 0.001
    p = self_affine_profile(2**20 * dx, dx, H=H, rms_height=1.0, seed=seed)
    lam, c = hdc(p, n_lags=40, max_lag_fraction=0.001)
    fit = fit_hdc(lam, c, (0.005, 0.5))
    assert fit.H == pytest.approx(H, abs=0.05)


def test_hdc_plateau_is_twice_the_mean_square():
    p = self_affine_profile(200.0, 0.01, H=0.8, rms_height=0.3, q_rolloff=2 * np.pi / 1.0, seed=4)
    lam, c = hdc(p, n_lags=50)
    fit = fit_hdc(lam, c, (0.03, 50))
    assert fit.plateau_found
    # beyond xi_par the HDC saturates at 2 h_rms^2 (thesis ch. 2.3.1, background notes 2.1)
    assert fit.xi_perp**2 == pytest.approx(2 * p.rms_height() ** 2, rel=0.05)
    assert 0.1 < fit.xi_par < 1.0  # below the 1 mm roll-off wavelength
