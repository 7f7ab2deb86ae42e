"""Generators (self-affine, sinusoids, sawtooth) and the fig. 6.5 alternatives (eq. 6.9,
HDC-based sines)."""

import numpy as np
import pytest

from rubberfriction.driver.surfaces import (
    band_split,
    bandlimit,
    compare_decompositions,
    fit_psd_power_law,
    hdc_sinusoids,
    log_bin,
    psd_1d,
    psd_reconstruction,
    rms_from_psd,
    sawtooth_profile,
    self_affine_profile,
    self_affine_psd,
    two_sine_profile,
)


@pytest.mark.parametrize("H", [0.5, 0.8])
@pytest.mark.parametrize("seed", [11, 12, 13])
def test_self_affine_profile_recovers_hurst_exponent_and_rms(H, seed):
    """Gaussian amplitudes (not normalised per realisation): H within 0.05 from the PSD slope,
    rms height within 5 % of the requested value, PSD level within 10 % of the model."""
    dx, rms = 0.001, 0.05
    qr, qs = 2 * np.pi / 1.0, 2 * np.pi / 0.01
    p = self_affine_profile(2**20 * dx, dx, H=H, rms_height=rms, q_rolloff=qr, q_cutoff=qs,
                            seed=seed)
    assert p.periodic and p.meta["provenance"]["kind"] == "generated"
    q, c = psd_1d(p, window=None, detrend="mean")
    fit = fit_psd_power_law(q, c, (2 * qr, qs / 2))
    assert fit.H == pytest.approx(H, abs=0.05)
    assert rms_from_psd(q, c) == pytest.approx(rms, rel=0.05)
    assert p.rms_height() == pytest.approx(rms, rel=0.05)
    # absolute level: log-binned periodogram against the model C1D in the self-affine range
    C0 = p.meta["provenance"]["C0_mm3"]
    m = (q > 2 * qr) & (q < qs / 2)
    qb, cb, _ = log_bin(q[m], c[m])
    model = self_affine_psd(qb, H=H, C0=C0, q_rolloff=qr, q_cutoff=qs)
    assert np.exp(np.mean(np.log(cb / model))) == pytest.approx(1.0, abs=0.1)


def test_fixed_amplitudes_give_the_exact_rms_and_spectrum():
    p = self_affine_profile(100.0, 0.01, H=0.7, rms_height=0.2, q_rolloff=2 * np.pi / 5, seed=2,
                            amplitudes="fixed")
    assert p.rms_height() == pytest.approx(0.2, rel=1e-12)
    q, c = psd_1d(p, window=None, detrend=None)
    prov = p.meta["provenance"]
    model = self_affine_psd(q, H=0.7, C0=prov["C0_mm3"], q_rolloff=prov["q_rolloff"],
                            q_cutoff=prov["q_cutoff"])
    model[-1] = 0.0  # the generator leaves the Nyquist mode out
    np.testing.assert_allclose(c, model, rtol=1e-9, atol=1e-12 * model.max())


def test_generator_is_reproducible_from_its_seed():
    a = self_affine_profile(10.0, 0.01, H=0.8, rms_height=0.1, seed=7)
    b = self_affine_profile(10.0, 0.01, H=0.8, rms_height=0.1, seed=7)
    c = self_affine_profile(10.0, 0.01, H=0.8, rms_height=0.1, seed=8)
    np.testing.assert_array_equal(a.h, b.h)
    assert not np.allclose(a.h, c.h)


def test_two_sine_profile_is_eq_6_8():
    p = two_sine_profile(10.0, 0.005)
    x = p.x
    z = 0.075 * np.sin(2 * np.pi / 5 * x) + 0.01 * np.sin(2 * np.pi / 0.5 * x)
    np.testing.assert_allclose(p.h, z, atol=1e-15)
    assert p.periodic
    q, c = psd_1d(p, window=None, detrend=None)
    dq = q[0]
    big = np.argsort(c)[-2:]
    np.testing.assert_allclose(sorted(2 * np.pi / q[big]), [0.5, 5.0])
    np.testing.assert_allclose(sorted(c[big] * dq), [0.01**2 / 4, 0.075**2 / 4], rtol=1e-12)
    # eq. (6.7): the two-scale split at 1 mm gives z1 and z2 exactly
    z1, z2 = band_split(p, [10.0, 1.0, 0.1])
    np.testing.assert_allclose(z1.h, 0.075 * np.sin(2 * np.pi / 5 * x), atol=1e-13)
    np.testing.assert_allclose(z2.h, 0.01 * np.sin(2 * np.pi / 0.5 * x), atol=1e-13)


def test_sawtooth_orientations_are_mirror_images_with_one_psd():
    kw = dict(wavelength=5.0, height=1.0, steep_fraction=0.1)
    sharp = sawtooth_profile(20.0, 0.01, orientation="sharp", **kw)
    smooth = sawtooth_profile(20.0, 0.01, orientation="smooth", **kw)
    n = sharp.n
    np.testing.assert_allclose(smooth.h, sharp.h[(-np.arange(n)) % n], atol=1e-12)
    assert sharp.periodic and smooth.periodic
    assert sharp.h.max() - sharp.h.min() == pytest.approx(1.0, abs=1e-12)
    assert abs(sharp.h.mean()) < 1e-12
    # the PSD cannot tell them apart (thesis ch. 6.4.1) ...
    _, c1 = psd_1d(sharp, window=None)
    _, c2 = psd_1d(smooth, window=None)
    np.testing.assert_allclose(c1, c2, rtol=1e-9, atol=1e-15 * c1.max())
    # ... but the slopes can: sharp rises steeply (slope height / (f lambda) = 2) facing the
    # oncoming rubber (sliding in +x), smooth drops steeply
    s1 = np.diff(sharp.h) / 0.01
    s2 = np.diff(smooth.h) / 0.01
    assert s1.max() == pytest.approx(2.0, rel=1e-9) and s1.min() > -0.3
    assert s2.min() == pytest.approx(-2.0, rel=1e-9) and s2.max() < 0.3
    skew = lambda s: np.mean((s - s.mean()) ** 3) / np.std(s) ** 3  # noqa: E731
    assert skew(s1) > 1 and skew(s2) < -1


def test_psd_reconstruction_is_the_sum_of_eq_6_9():
    q = np.geomspace(0.5, 50, 30)
    c = 0.01 * q**-2.6
    X, dx = 12.566, 0.01
    p = psd_reconstruction(q, c, X, dx, seed=4)
    L = p.length
    modes, phases, amps = p.meta["q_modes"], p.meta["phases"], p.meta["amplitudes"]
    ci = np.exp(np.interp(np.log(modes), np.log(q), np.log(c)))
    np.testing.assert_allclose(amps, 2 * np.sqrt(2 * np.pi / L * ci), rtol=1e-14)
    direct = np.sin(np.outer(p.x, modes) + phases) @ amps
    np.testing.assert_allclose(p.h, direct, atol=1e-12 * np.abs(direct).max())
    # each term carries the power 2 C(q_i) dq: the rms is the PSD's rms over the used modes
    assert p.rms_height() == pytest.approx(np.sqrt(2 * np.sum(ci) * 2 * np.pi / L), rel=1e-12)
    # random phases, same amplitudes: another seed changes the shape, not the rms
    p2 = psd_reconstruction(q, c, X, dx, seed=5)
    assert p2.rms_height() == pytest.approx(p.rms_height(), rel=1e-12)
    assert not np.allclose(p.h, p2.h)


def test_hdc_sinusoids_recover_the_two_sine_amplitudes():
    """Approach 1 on eq. (6.8): the idealised single-sine HDCs reproduce z1, z2 within 2 %
    (the only error is the idealised plateau of z2 at lag 2.5 mm, ~ A2^2/A1^2)."""
    p = two_sine_profile(10.0, 0.005)
    amps, lam = hdc_sinusoids(p, [5.0, 0.5, 0.05])
    np.testing.assert_allclose(lam, [5.0, 0.5])
    np.testing.assert_allclose(amps, [0.075, 0.01], rtol=0.02)


def test_compare_decompositions_gives_three_sets_of_scales(shared_data):
    from rubberfriction.driver.surfaces import load_profile

    p = load_profile(shared_data / "captif_chipseal_station0.dat")
    edges = [20.0, 3.0, 0.3]
    res = compare_decompositions(p, edges, seed=1)
    assert set(res) == {"hdc_sinusoids", "psd_reconstruction", "filtering"}
    for bands in res.values():
        assert [b.meta["band"] for b in bands] == [(20.0, 3.0), (3.0, 0.3)]
        assert all(b.n == p.n for b in bands)
    total = sum(b.h for b in res["filtering"])
    np.testing.assert_allclose(total, bandlimit(p, 20.0, 0.3).h, atol=1e-10 * np.abs(total).max())
    # the PSD route keeps each band rms (up to Hann windowing and log binning, < 10 %)
    for f, r in zip(res["filtering"], res["psd_reconstruction"]):
        assert r.rms_height() == pytest.approx(f.rms_height(), rel=0.1)
