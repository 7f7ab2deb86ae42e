"""Band-pass decomposition, eq. (6.10): partition of the spectrum, band content, errors."""

import numpy as np
import pytest

from rubberfriction.driver.surfaces import (
    BandError,
    Profile,
    band_split,
    bandlimit,
    load_profile,
    lowpass,
    psd_1d,
    self_affine_profile,
)

THESIS_EDGES = [20.0, 3.0, 0.3, 0.04, 0.003]


def _rel(a, b):
    return np.linalg.norm(a - b) / np.linalg.norm(b)


@pytest.mark.parametrize("filt", ["ideal", "cosine"])
def test_bands_partition_the_captif_spectrum(shared_data, filt):
    p = load_profile(shared_data / "captif_chipseal_station0.dat")
    edges = [20.0, 3.0, 0.3, 0.08]  # what a 0.0375 mm scan resolves
    bands = band_split(p, edges, filter=filt)
    assert [b.meta["band"] for b in bands] == [(20.0, 3.0), (3.0, 0.3), (0.3, 0.08)]
    total = np.sum([b.h for b in bands], axis=0)
    ref = bandlimit(p, 20.0, 0.08, filter=filt)
    assert _rel(total, ref.h) < 1e-10
    # each band is a real part of the surface, not zero, and they differ in scale
    rms = [b.rms_height() for b in bands]
    assert rms[0] > rms[1] > rms[2] > 0


def test_bands_partition_a_generated_four_scale_profile():
    p = self_affine_profile(60.0, 0.001, H=0.8, rms_height=0.5, seed=3)
    p = Profile(p.x, p.h + 0.01 * p.x, meta={"provenance": p.meta["provenance"]})  # non-periodic
    bands = band_split(p, THESIS_EDGES)
    assert _rel(np.sum([b.h for b in bands], axis=0), bandlimit(p, 20.0, 0.003).h) < 1e-10
    # with everything below and above: lowpass + bands + (nothing beyond Nyquist) = detrended h
    full = band_split(p, [20.0, 3.0, 0.3, 0.04, 2 * p.dx])
    h_det = p.h - np.polyval(np.polyfit(p.x - p.x.mean(), p.h, 1), p.x - p.x.mean())
    recon = lowpass(p, 20.0).h + np.sum([b.h for b in full], axis=0)
    assert _rel(recon, h_det) < 1e-10


def test_periodic_bands_hold_exactly_their_part_of_the_spectrum():
    # 40.97 mm: no band edge falls exactly on a Fourier mode
    p = self_affine_profile(40.97, 0.001, H=0.7, rms_height=0.2, seed=5)
    q, c = psd_1d(p, window=None, detrend="mean")
    dq = q[0]
    for b in band_split(p, THESIS_EDGES[1:]):
        lo, hi = 2 * np.pi / b.meta["band"][0], 2 * np.pi / b.meta["band"][1]
        inside = (q >= lo) & (q < hi)
        assert inside.sum() > 50
        qb, cb = psd_1d(b, window=None, detrend="mean")
        assert cb[~inside].max() < 1e-20 * c.max()
        np.testing.assert_allclose(cb[inside], c[inside], rtol=1e-8)
        # band variance = 2 * PSD integral over the band
        assert b.rms_height() ** 2 == pytest.approx(2 * np.sum(c[inside]) * dq, rel=1e-10)


def test_mirror_extension_stops_leakage_of_non_periodic_records():
    """A long sine with a non-integer number of periods plus a trend has no short wavelengths:
    the mirrored filter keeps the short band nearly empty, a periodic FFT does not."""
    x = np.arange(20000) * 0.005
    p = Profile(x, np.sin(2 * np.pi * x / 13.7) + 0.05 * x)
    mirror = band_split(p, [2.0, 0.05])[0]
    periodic = band_split(p, [2.0, 0.05], extension="periodic")[0]
    # the periodic FFT sees a jump of ~5 at the ends and rings through the record
    assert periodic.rms_height() > 5 * mirror.rms_height()
    assert np.abs(periodic.h).max() > 5 * np.abs(mirror.h).max()
    # the mirrored record only has a slope kink: away from the ends < 0.5 % of the unit sine
    inner = slice(2000, 18000)
    assert np.abs(mirror.h[inner]).max() < 5e-3
    assert np.abs(periodic.h[inner]).max() > 2 * np.abs(mirror.h[inner]).max()


def test_band_errors():
    p = self_affine_profile(10.0, 0.01, H=0.8, rms_height=0.1, seed=1)
    with pytest.raises(BandError, match="too short"):
        band_split(p, [20.0, 3.0, 0.3])
    with pytest.raises(BandError, match="finer measurement"):
        band_split(p, [3.0, 0.3, 0.01])
    with pytest.raises(BandError, match="descending"):
        band_split(p, [0.3, 3.0])
    with pytest.raises(BandError, match="at least two"):
        band_split(p, [3.0])
    with pytest.raises(BandError, match="positive"):
        band_split(p, [3.0, -1.0])
    bands = band_split(p, [3.0, 0.3, 0.01], allow_unresolved=True)
    assert [b.meta["resolved"] for b in bands] == [True, False]
    raw = Profile(np.arange(10.0), np.where(np.arange(10) == 4, np.nan, 1.0))
    with pytest.raises(BandError, match="NaN"):
        band_split(raw, [5.0, 2.0])
