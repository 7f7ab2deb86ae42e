"""Periodic closure (fig. 6.6 b), sample extraction (ch. 6.5.1) and multi-measurement scales."""

import math

import numpy as np
import pytest

from rubberfriction.driver.surfaces import (
    BandError,
    Profile,
    band_split,
    close_periodic,
    extract_samples,
    load_profile,
    lowpass,
    multiscale_from_measurements,
    self_affine_profile,
)
from rubberfriction.driver.surfaces.closure import hermite_max_slope


def _cutout(m):
    """A smooth non-periodic function on [0, 10] with m steps and its exact slopes."""
    x = np.linspace(0.0, 10.0, m + 1)
    k1, k2 = 2 * np.pi / 7.3, 2 * np.pi / 1.7
    h = np.sin(k1 * x) + 0.3 * np.sin(k2 * x)
    s = k1 * np.cos(k1 * x) + 0.3 * k2 * np.cos(k2 * x)
    return x, h, s


def test_connecting_spline_matches_values_and_slopes_across_the_period():
    x, h, s = _cutout(400)
    dx = x[1] - x[0]
    hc, clo = close_periodic(h, dx, slopes=s)
    P = x[-1]
    assert hc[-1] == hc[0]  # exactly periodic
    assert clo.length > 0 and clo.n_points == round(clo.length / dx)
    # C1 across the period: the spline ends on h(0) with slope h'(0) ...
    assert clo(P) == pytest.approx(h[0], abs=1e-14)
    assert clo.slope(P) == pytest.approx(s[0], abs=1e-12)
    # ... and starts on the cutout with its slope
    assert clo(clo.x_start) == pytest.approx(h[400 - clo.n_points], abs=1e-14)
    assert clo.slope(clo.x_start) == pytest.approx(s[400 - clo.n_points], abs=1e-12)
    # the cutout is untouched before the spline, the spline is what is stored after
    k = 400 - clo.n_points
    np.testing.assert_array_equal(hc[:k + 1], h[:k + 1])
    np.testing.assert_allclose(hc[k:-1], clo(x[k:-1]), atol=1e-14)
    # the modified length is small and the spline is not steeper than the surface
    assert clo.length <= 0.25 * P
    assert clo.within_slope_cap and clo.max_slope <= np.abs(s).max() * (1 + 1e-12)
    assert clo.mismatch_height == pytest.approx(abs(h[-1] - h[0])) and clo.mismatch_height > 0.5


def test_closure_that_cannot_stay_below_the_slope_cap_says_so():
    # a ramp: ends 3 apart on a surface of slope <= 0.5; no spline within 25 % of P is that gentle
    x = np.linspace(0.0, 10.0, 401)
    h = 0.3 * x + 0.05 * np.sin(2 * np.pi * x / 1.7)
    s = 0.3 + 0.05 * 2 * np.pi / 1.7 * np.cos(2 * np.pi * x / 1.7)
    hc, clo = close_periodic(h, x[1] - x[0], slopes=s)
    assert not clo.within_slope_cap and clo.max_slope > clo.slope_cap
    assert clo.length == pytest.approx(0.25 * 10.0)  # the least steep admissible spline
    assert hc[-1] == hc[0] and clo.slope(10.0) == pytest.approx(s[0])


def test_closed_sample_is_c1_periodic_to_grid_accuracy():
    """Discrete slopes on both sides of the period join: their difference is only the
    curvature times dx (no kink) and vanishes like dx, while the raw cutout jumps in height."""
    jumps = []
    for m in (100, 200, 400, 800, 1600):
        x, h, s = _cutout(m)
        dx = x[1] - x[0]
        hc, clo = close_periodic(h, dx, slopes=s)
        P = x[-1]
        left = (hc[-1] - hc[-2]) / dx  # slope just before x = P
        right = (hc[1] - hc[0]) / dx  # slope just after x = 0 (= P)
        jumps.append(abs(left - right))
        assert hc[-1] == hc[0]
        # one-sided differences differ from the common slope h'(P) = h'(0) by curvature * dx / 2
        eps = 1e-6 * clo.length
        kappa_spline = (clo.slope(P) - clo.slope(P - eps)) / eps
        kappa_data = 0.0  # h''(0) = 0 for this sum of sines
        assert jumps[-1] <= (abs(kappa_spline) + abs(kappa_data)) * dx / 2 * 1.05 + 1e-12
    assert all(b < 0.6 * a for a, b in zip(jumps, jumps[1:]))  # first order in dx
    assert abs(h[-1] - h[0]) > 0.5


def test_closure_of_an_already_periodic_cutout_changes_nothing():
    x = np.linspace(0, 4.0, 401)
    h = np.sin(2 * np.pi * x / 2.0)
    hc, clo = close_periodic(h, x[1] - x[0], slopes=np.pi * np.cos(np.pi * x))
    assert clo.length == 0.0
    np.testing.assert_allclose(hc, h, atol=1e-15)


def test_hermite_max_slope_closed_form_against_sampling():
    rng = np.random.default_rng(0)
    p0, p1, m0, m1 = rng.standard_normal((4, 50))
    d = rng.uniform(0.1, 2.0, 50)
    t = np.linspace(0, 1, 20001)[:, None]
    a = 6 * (p0 - p1) + 3 * d * (m0 + m1)
    b = -6 * (p0 - p1) - d * (4 * m0 + 2 * m1)
    sampled = np.abs(a * t**2 + b * t + d * m0).max(axis=0) / d
    np.testing.assert_allclose(hermite_max_slope(p0, p1, m0, m1, d), sampled, rtol=1e-6)


@pytest.fixture(scope="module")
def captif_meso(shared_data):
    p = load_profile(shared_data / "captif_chipseal_station0.dat")
    band = band_split(p, [3.0, 0.3])[0]
    return p, band, lowpass(p, 3.0)


def test_samples_are_periodic_reproducible_and_from_the_top_region(captif_meso):
    p, band, carrier = captif_meso
    s1 = extract_samples(band, 3.0, 10, seed=4, carrier=carrier, top_fraction=0.2)
    s2 = extract_samples(band, 3.0, 10, seed=4, carrier=carrier, top_fraction=0.2)
    s3 = extract_samples(band, 3.0, 10, seed=5, carrier=carrier, top_fraction=0.2)
    assert [s.start for s in s1] == [s.start for s in s2]
    assert [s.start for s in s1] != [s.start for s in s3]
    thr = np.quantile(carrier.h, 0.8)
    starts = np.array([s.start for s in s1])
    assert np.all(np.diff(np.sort(starts)) > 3.0)  # no overlap
    # not within one block of the record ends, where the mirrored filter rings
    assert starts.min() >= band.x[0] + 3.0 - 1e-9 and starts.max() + 3.0 <= band.x[-1] - 3.0 + 1e-9
    dx = band.dx
    for s in s1:
        assert s.period == 3.0 and s.x[0] == 0.0 and s.x[-1] == 3.0
        assert np.allclose(np.diff(s.x), s.x[1])
        assert s.h[-1] == s.h[0]
        i0 = int(round((s.start - band.x[0]) / dx))
        m = s.x.size - 1
        # centre of the cutout on a top asperity of the surface the meso block rides on
        assert carrier.h[i0 + m // 2] >= thr
        # measured data are kept as they are outside the closure
        keep = s.x < s.period - s.closure_length - 1e-9
        np.testing.assert_array_equal(s.h[keep], band.h[i0:i0 + m + 1][keep])
        # windows avoid interpolated dropouts
        assert p.repaired[i0:i0 + m + 1].mean() <= 0.02
        # statistics and their report against the band
        assert s.rms_height == pytest.approx(np.std(s.h[:-1]))
        assert s.rms_slope == pytest.approx(np.sqrt(np.mean((np.diff(s.h) / s.x[1]) ** 2)))
        assert s.band_rms_height == pytest.approx(band.rms_height())
        assert s.height_ratio == pytest.approx(s.rms_height / band.rms_height())
        assert 0 < s.closure_length <= 0.25 * 3.0 + 1e-9
        assert s.source == "measured" and s.band == (3.0, 0.3)
        assert abs(s.meta["stretch"]) < dx / 3.0


def test_top_fraction_selects_high_regions(captif_meso):
    _, band, carrier = captif_meso
    top = extract_samples(band, 3.0, 10, seed=1, carrier=carrier, top_fraction=0.1)
    low = extract_samples(band, 3.0, 10, seed=1, carrier=-carrier.h, top_fraction=0.1)
    m = top[0].x.size - 1

    def c_at(ss):
        return np.array([carrier.h[int(round((s.start - band.x[0]) / band.dx)) + m // 2]
                         for s in ss])

    assert c_at(top).min() > c_at(low).max()


def test_sample_errors():
    p = self_affine_profile(10.0, 0.01, H=0.8, rms_height=0.1, seed=1)
    (b,) = band_split(p, [5.0, 0.05])
    with pytest.raises(BandError, match="too short"):
        extract_samples(b, 20.0, 3, 0)
    with pytest.raises(BandError, match="grid steps"):
        extract_samples(b, 0.05, 3, 0)
    # a short record: overlapping samples are taken and flagged
    s = extract_samples(b, 5.0, 4, 0, top_fraction=1.0)
    assert len(s) == 4 and s[0].meta["overlap"]


def test_each_scale_comes_from_the_measurement_that_resolves_it():
    coarse = self_affine_profile(200.0, 0.02, H=0.8, rms_height=1.0, seed=1)
    fine = self_affine_profile(2.0, 0.001, H=0.8, rms_height=0.01, seed=2)
    coarse = Profile(coarse.x, coarse.h, source="coarse", meta=coarse.meta)
    fine = Profile(fine.x, fine.h, source="fine", meta=fine.meta)
    road = multiscale_from_measurements([fine, coarse], [20.0, 3.0, 0.3, 0.04, 0.003])
    assert [sc.measurement for sc in road.scales] == ["coarse", "coarse", "fine", "fine"]
    assert road.names == ["macro", "meso", "micro1", "micro2"]
    assert [sc.block_length for sc in road.scales] == [20.0, 3.0, 0.3, 0.04]
    # bands of one measurement partition its spectrum; carriers are the longer wavelengths
    sc = road.scales[2]
    np.testing.assert_allclose(sc.carrier.h, lowpass(fine, 0.3).h, atol=1e-12)
    np.testing.assert_allclose(road.scales[2].profile.h + road.scales[3].profile.h,
                               sum(band_split(fine, [0.3, 0.04, 0.003])[i].h for i in range(2)),
                               atol=1e-12)
    samples = road.extract_samples(3, seed=9)
    assert [len(g) for g in samples] == [3, 3, 3, 3]
    assert [g[0].period for g in samples] == [20.0, 3.0, 0.3, 0.04]
    again = road.extract_samples(3, seed=9)
    assert all(a.start == b.start for ga, gb in zip(samples, again) for a, b in zip(ga, gb))
    with pytest.raises(BandError, match="no measurement resolves the band 0.04-0.003"):
        multiscale_from_measurements([coarse], [20.0, 3.0, 0.3, 0.04, 0.003])


@pytest.mark.parametrize("n", [12, 13])
def test_refine_periodic_is_the_band_limited_interpolant(n):
    """A periodic sum of waves the grid resolves (including the Nyquist cosine for even n) is
    recovered exactly between the points (1e-12) and every original point is kept."""
    from rubberfriction.driver.surfaces.samples import refine_periodic

    def f(x):
        out = 0.3 * np.sin(2 * np.pi * x) + 0.1 * np.cos(2 * np.pi * 5 * x + 0.3)
        return out + (0.05 * np.cos(2 * np.pi * (n // 2) * x) if n % 2 == 0 else 0.0)

    x = np.arange(n) / n
    fine = refine_periodic(f(x), 8)
    assert fine.size == 8 * n
    assert np.allclose(fine[::8], f(x), rtol=0, atol=1e-12)
    assert np.allclose(fine, f(np.arange(8 * n) / (8 * n)), rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="whole number"):
        refine_periodic(f(x), 1.5)


def test_master_polyline_reaches_the_vertex_density_and_keeps_the_points():
    from rubberfriction.driver.multiscale.specs import master_polyline

    L, n = 0.04, 80  # micro2 of the default road: 6 points per 0.003 mm wavelength
    x = np.arange(n) * L / n
    h = 0.001 * np.sin(2 * np.pi * x / 0.004) + 0.0005 * np.cos(2 * np.pi * x / 0.0032)
    xr, hr = master_polyline(x, h, L, 0.003, 32)
    assert xr.size == 6 * n  # ceil(32 * 0.0005 / 0.003) = 6
    assert np.allclose(xr[::6], x, rtol=0, atol=1e-15) and np.allclose(hr[::6], h, atol=1e-15)
    assert np.allclose(np.diff(xr), L / xr.size)
    for args in ((L, 0.003, 0), (L, 0.02, 32)):  # switched off; fine enough, not 2x finer
        xs, hs = master_polyline(x, h, *args)
        assert xs is x and hs is h
    xn = x.copy()
    xn[3] += 1e-4  # not uniform: as given
    assert master_polyline(xn, h, L, 0.003, 32)[0] is xn


def test_master_polyline_keeps_every_kth_point_of_a_finer_sample():
    """A sample finer than the vertex density by a factor >= 2 keeps every k-th point, k the
    largest divisor of its point count that leaves at least points_per_wavelength per shortest
    wavelength: the four-scale macro sample, 20 mm at 4 um (5000 points), band edge 3 mm, 32
    points a wavelength: k <= 3 / (32 * 0.004) = 23.4, the largest divisor of 5000 is 20."""
    from rubberfriction.driver.multiscale.specs import master_points, master_polyline

    L, n, lam = 20.0, 5000, 3.0
    x = np.arange(n) * L / n
    h = 0.1 * np.sin(2 * np.pi * x / 4.0) + 0.05 * np.cos(2 * np.pi * x / (L / 6))  # periodic
    xd, hd = master_polyline(x, h, L, lam, 32)
    assert xd.size == 250
    assert np.array_equal(xd, x[::20]) and np.array_equal(hd, h[::20])
    assert lam / (xd[1] - xd[0]) >= 32
    assert np.allclose(np.diff(xd), L / xd.size)
    # 4999 is prime: no whole factor, so the points nearest to equal steps of k_max = 23
    xs, hs, Ls = x[:4999], h[:4999], L * 4999 / 5000
    xp, hp = master_polyline(xs, hs, Ls, lam, 32)
    assert xp.size == math.ceil(4999 / 23)
    steps = np.round(np.diff(np.append(xp, xp[0] + Ls)) / (Ls / 4999)).astype(int)
    assert set(steps) <= {22, 23} and steps.sum() == 4999
    assert np.array_equal(hp, np.interp(xp, xs, hs))  # every vertex a point of the sample
    assert master_polyline(xs, hs, Ls, lam, 32, uniform=True)[0] is xs  # node-to-surface
    # a point is left out only where the subset's polyline passes within max_deviation of it:
    # the smooth waves above are 4e-4 mm off at k = 20; a tip truncated flat (polish) is not
    assert master_polyline(x, h, L, lam, 32, max_deviation=1e-3)[0].size == 250
    flat = np.minimum(h, 0.9 * h.max())
    assert master_polyline(x, flat, L, lam, 32, max_deviation=1e-6)[0] is x
    # at least MASTER_POINTS_PER_ELEMENT (4) per contact element of a finer mesh

    class Num:
        master_points_per_wavelength = 32
        elements_per_wavelength = 12

    assert master_points(Num) == 48
    Num.master_points_per_wavelength = 0
    assert master_points(Num) == 0
