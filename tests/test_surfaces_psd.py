"""PSD normalisation (Persson convention), windowing, log binning and the 1D -> 2D conversion.

Oracles: the sine-bin identity and Parseval (background notes 3.4, exact in floating point),
the Hann main-lobe sum rule, and the isotropic conversion (background notes 2.1: the factor
Gamma(H+1)/(sqrt(pi) Gamma(H+1/2)) and the Abel inverse of C1D(qx) = Int C(|q|) dqy).
"""

import numpy as np
import pytest
from scipy.integrate import quad

from rubberfriction.driver.surfaces import (
    Profile,
    SurfaceError,
    fit_psd_power_law,
    log_bin,
    psd_1d,
    psd_iso_from_1d,
    rms_from_psd,
    self_affine_iso_factor,
)
from rubberfriction.driver.surfaces.psd import from_surface_topography, to_surface_topography


def _periodic(h, dx):
    return Profile(dx * np.arange(len(h)), h, meta={"periodic": True})


@pytest.mark.parametrize("n", [1024, 1023])
def test_sine_puts_a2_over_4_in_its_bin(n):
    dx, k0, A = 0.01, 37, 0.3
    L = n * dx
    x = dx * np.arange(n)
    p = _periodic(A * np.sin(2 * np.pi * k0 * x / L + 0.7), dx)
    q, c = psd_1d(p, window=None, detrend=None)
    dq = 2 * np.pi / L
    assert q[k0 - 1] == pytest.approx(2 * np.pi * k0 / L, rel=1e-14)
    # Persson convention: the bin holds C dq = A^2/4 (the -q mirror holds the other A^2/4)
    assert c[k0 - 1] * dq == pytest.approx(A**2 / 4, rel=1e-12)
    # SurfaceTopography convention C_ST = 2 pi C1D: C_ST / L = A^2 / 4
    assert to_surface_topography(c)[k0 - 1] / L == pytest.approx(A**2 / 4, rel=1e-12)
    assert from_surface_topography(to_surface_topography(c))[k0 - 1] == pytest.approx(c[k0 - 1])
    others = np.delete(c, k0 - 1)
    assert others.max() < 1e-20 * c[k0 - 1]  # no leakage for an on-bin sine


@pytest.mark.parametrize("n", [4096, 4095])
@pytest.mark.parametrize("kind", ["mean", "linear"])
def test_parseval_exact_without_window(n, kind):
    rng = np.random.default_rng(5)
    dx = 0.02
    x = dx * np.arange(n)
    h = np.cumsum(rng.standard_normal(n)) * 0.01 + 0.3 * x + 2.0  # non-periodic, trend, offset
    p = Profile(x, h)
    q, c = psd_1d(p, window=None, detrend=kind)
    if kind == "mean":
        ms = np.mean((h - h.mean()) ** 2)
    else:
        res = h - np.polyval(np.polyfit(x, h, 1), x)
        ms = np.mean(res**2)
    # h_rms^2 = 2 Int_0^inf C1D dq, exactly for the discrete estimator
    assert 2 * np.sum(c) * (2 * np.pi / (n * dx)) == pytest.approx(ms, rel=1e-12)
    assert rms_from_psd(q, c) == pytest.approx(np.sqrt(ms), rel=1e-12)


def test_hann_window_main_lobe_sum_rule_and_broadband_parseval():
    n, dx, k0, A = 2048, 0.01, 100, 0.5
    L = n * dx
    x = dx * np.arange(n)
    q, c = psd_1d(_periodic(A * np.sin(2 * np.pi * k0 * x / L), dx), window="hann", detrend=None)
    dq = 2 * np.pi / L
    # periodic Hann normalised by <w^2> = 3/8: bins k0-1, k0, k0+1 hold A^2/4 together
    assert np.sum(c[k0 - 2:k0 + 1]) * dq == pytest.approx(A**2 / 4, rel=1e-12)
    assert c[k0 - 1] * dq == pytest.approx(A**2 / 4 * (0.25 / 0.375), rel=1e-12)
    # white noise: Parseval holds in expectation (2**16 points: statistical error ~0.6 %)
    rng = np.random.default_rng(1)
    h = rng.standard_normal(2**16)
    q, c = psd_1d(Profile(dx * np.arange(h.size), h), window="hann", detrend="mean")
    assert 2 * np.sum(c) * q[0] == pytest.approx(np.var(h), rel=0.02)
    # and its level is flat at sigma^2 dx / (2 pi)
    assert np.mean(c) == pytest.approx(np.var(h) * dx / (2 * np.pi), rel=0.02)


def test_psd_refuses_raw_profiles():
    x = np.arange(10.0)
    with pytest.raises(SurfaceError, match="NaN"):
        psd_1d(Profile(x, np.where(x == 3, np.nan, x)))
    with pytest.raises(SurfaceError, match="uniform"):
        psd_1d(Profile(x**1.5, x))
    with pytest.raises(SurfaceError, match="window"):
        psd_1d(Profile(x, np.sin(x)), window="kaiser")


def test_log_bin_averages_and_counts():
    q = np.arange(1, 10001) * 0.01
    c = 3.0 * q**-2.6
    qb, cb, n = log_bin(q, c, bins_per_decade=10)
    assert n.sum() == q.size
    assert np.all(np.diff(np.log10(qb)) > 0)
    # the mean of a power law over a narrow bin is close to the power law at the geometric centre
    assert np.allclose(cb, 3.0 * qb**-2.6, rtol=0.06)
    qb, cb, _ = log_bin(q, np.full_like(q, 7.0))
    assert np.allclose(cb, 7.0, rtol=1e-14)


def test_fit_psd_power_law_exact():
    q = np.geomspace(0.1, 1000, 500)
    for H in (0.3, 0.8):
        fit = fit_psd_power_law(q, 0.02 * q ** -(1 + 2 * H))
        assert fit.H == pytest.approx(H, abs=1e-10)
        # K from arithmetic bin means (right for noisy periodograms): the mean of q^-a over a bin
        # of log-width w exceeds the value at its centre by about (a w)^2 / 24, 1.5 % for
        # a = 2.6 and w = ln(10) / 10
        assert fit.K == pytest.approx(0.02, rel=0.02)


@pytest.mark.parametrize("H, factor", [(0.5, 0.5), (0.6, 0.5299), (0.8, 0.5855), (0.9, 0.6116),
                                       (1.0, 2 / np.pi)])
def test_self_affine_iso_factor_table(H, factor):
    assert self_affine_iso_factor(H) == pytest.approx(factor, abs=1e-4)


@pytest.mark.parametrize("H", [0.3, 0.8])
def test_abel_route_matches_self_affine_factor_for_a_power_law(H):
    q = np.geomspace(1e-2, 1e3, 120)
    c1 = 0.7 * q ** -(1 + 2 * H)
    exact = psd_iso_from_1d(q, c1, H=H)
    abel = psd_iso_from_1d(q, c1)
    np.testing.assert_allclose(abel, exact, rtol=2e-3)
    # without the tail the top end must be underestimated (the transform needs q' > q)
    cut = psd_iso_from_1d(q, c1, tail="zero")
    assert cut[-5] < 0.9 * exact[-5]


def test_abel_route_inverts_the_projection_with_rolloff():
    """C(q) with roll-off -> C1D by direct integration -> Abel inverse recovers C(q)."""
    H, qr, C0 = 0.7, 1.0, 2.0

    def c2(q):
        return C0 if q < qr else C0 * (q / qr) ** (-2 - 2 * H)

    qx = np.geomspace(0.05, 200, 70)
    # C1D(qx) = Int_-inf^inf dqy C(sqrt(qx^2 + qy^2)), split at the roll-off circle
    c1 = []
    for a in qx:
        ky = np.sqrt(max(qr**2 - a**2, 0.0))
        inner = quad(lambda y: c2(np.hypot(a, y)), 0, ky)[0] if ky > 0 else 0.0
        outer = quad(lambda y: c2(np.hypot(a, y)), ky, np.inf, limit=200)[0]
        c1.append(2 * (inner + outer))
    c1 = np.array(c1)
    back = psd_iso_from_1d(qx, c1)
    ref = np.array([c2(v) for v in qx])
    away = np.abs(np.log(qx / qr)) > 0.3  # the kink is smoothed by the interpolation
    np.testing.assert_allclose(back[away], ref[away], rtol=0.03)
    # and a single global H would be wrong on the plateau by a large factor
    assert abs(psd_iso_from_1d(qx, c1, H=H)[0] / ref[0] - 1) > 0.5
