"""Reading profiles (CAPTIF text, CSV, HDF5), defects (dropouts, outliers, spacing), bad inputs."""

import gzip

import h5py
import numpy as np
import pytest

from conftest import sha256
from rubberfriction.driver.surfaces import (
    DefectError,
    Profile,
    ProfileFormatError,
    clean_profile,
    detrend,
    load_profile,
    resample_uniform,
    self_affine_profile,
)
from rubberfriction.driver.surfaces.default_road import EMBEDDED_STATION0

CAPTIF = "captif_chipseal_station0.dat"


def _captif_raw_counts(path):
    """Independent count of the file's rows, NaN rows and reference-plate rows (> 30 mm)."""
    rows = path.read_text().splitlines()[11:]
    depth = [r.split("\t")[2] for r in rows]
    n_nan = sum(d.strip().lower() == "nan" for d in depth)
    n_plate = sum(d.strip().lower() != "nan" and float(d) > 30 for d in depth)
    return len(rows), n_nan, n_plate


def test_captif_loads_and_reports_its_dropouts(shared_data):
    path = shared_data / CAPTIF
    n_rows, n_nan, n_plate = _captif_raw_counts(path)
    p = load_profile(path)
    info = p.meta["reader"]
    assert info["header_lines"] == 11 and info["delimiter"] == "\t"
    assert (info["x_col"], info["h_col"]) == (1, 2)
    assert info["columns"][1:] == ["Distance (mm)", "Depth (mm)"]
    rep = p.meta["defects"]
    assert rep.n_points_raw == n_rows == 51067
    assert rep.n_nan == n_nan == 4373
    # positions are printed to 1 um: snapped to the 0.0375 mm grid, not interpolated
    assert rep.spacing["method"] == "snapped"
    assert rep.spacing["dx"] == pytest.approx(0.0375, rel=0.002)
    assert p.is_uniform() and p.dx == pytest.approx(rep.spacing["dx"])
    # the reference plate (~47 mm) is caught as global outliers and cut away with its gaps
    assert rep.n_outlier_global >= n_plate
    assert np.all(np.isfinite(p.h)) and p.h.max() < 10 and p.h.min() > -6
    discarded = [g for g in rep.gaps if g.action == "discarded (long gap)"]
    assert any(g.start_x < 25 and g.end_x > 55 for g in discarded)
    assert any(g.start_x > 1850 and g.end_x > 1900 for g in discarded)
    assert 60 < p.x[0] < 62 and 1870 < p.x[-1] < 1873
    interp = [g for g in rep.gaps if g.action == "interpolated"]
    assert len(interp) > 100 and max(g.span for g in interp) <= rep.max_gap
    assert rep.n_interpolated == int(p.repaired.sum())
    assert 0.02 < rep.interpolated_fraction < 0.10
    assert "dropouts: 4373" in str(rep)
    assert p.meta["provenance"]["kind"] == "measured"


def test_captif_raw_read_and_embedded_copy(shared_data):
    """The package's gzip copy reads exactly as the original, uncompressed file.  The fixture's
    uncompressed file is the original byte for byte: its sha256 is the original's (recorded from
    ``../shared/data/captif_chipseal_station0.dat``)."""
    assert sha256(shared_data / CAPTIF) == \
        "ea097ad417d64eeb9dd7db2ad5eb7ed5f1f4410d57a00ea336ae76a7fd88f52a"
    raw = load_profile(shared_data / CAPTIF, clean=False)
    assert raw.n == 51067 and int(np.isnan(raw.h).sum()) == 4373
    emb = load_profile(EMBEDDED_STATION0)
    ref = load_profile(shared_data / CAPTIF)
    np.testing.assert_array_equal(emb.h, ref.h)
    np.testing.assert_array_equal(emb.x, ref.x)
    assert EMBEDDED_STATION0.stat().st_size < 1_000_000
    assert (EMBEDDED_STATION0.parent / "LICENSE.captif-slp").is_file()


def test_captif_long_gaps_can_be_refused(shared_data):
    with pytest.raises(DefectError, match="longer than max_gap"):
        load_profile(shared_data / CAPTIF, long_gaps="error")


def test_csv_with_units_in_header(tmp_path):
    x = np.arange(200) * 5.0  # um
    h = 30.0 * np.sin(x / 100.0)  # um
    f = tmp_path / "scan.csv"
    f.write_text("# instrument: test\nposition [um],height [um]\n" + "\n".join(
        f"{a:.6f},{b:.6f}" for a, b in zip(x, h)))
    p = load_profile(f, units="auto")
    np.testing.assert_allclose(p.x, x * 1e-3, atol=1e-12)
    np.testing.assert_allclose(p.h, h * 1e-3, atol=1e-9)
    assert p.meta["reader"]["delimiter"] == ","
    with pytest.raises(ProfileFormatError, match="header gives x in 'um'"):
        load_profile(f, units="mm")
    p2 = load_profile(f, units="um")
    np.testing.assert_array_equal(p2.h, p.h)


def test_single_column_whitespace_file_needs_dx(tmp_path):
    f = tmp_path / "heights.txt"
    f.write_text("\n".join(f"  {v:.5f}" for v in np.cos(np.arange(50) * 0.3)))
    with pytest.raises(ProfileFormatError, match="dx"):
        load_profile(f)
    p = load_profile(f, dx=0.02)
    assert p.n == 50 and p.dx == pytest.approx(0.02)


def test_gzip_text_and_reversed_positions(tmp_path):
    f = tmp_path / "rev.txt.gz"
    x = np.arange(100)[::-1] * 0.1
    with gzip.open(f, "wt") as g:
        g.write("\n".join(f"{a:.3f} {np.sin(a):.6f}" for a in x))
    p = load_profile(f)
    assert p.meta["reader"].get("reversed") is True
    assert np.all(np.diff(p.x) > 0)
    np.testing.assert_allclose(p.h, np.sin(p.x), atol=1e-6)


def test_hdf5_datasets_and_table(tmp_path):
    x = np.linspace(0, 10, 501)
    h = 0.1 * np.sin(x)
    f = tmp_path / "scan.h5"
    with h5py.File(f, "w") as g:
        g["profile/x"] = x * 1e3
        g["profile/x"].attrs["units"] = "um"
        g["profile/height"] = h * 1e3
        g["profile/height"].attrs["units"] = "um"
    p = load_profile(f, units="auto")
    np.testing.assert_allclose(p.x, x, atol=1e-12)
    np.testing.assert_allclose(p.h, h, atol=1e-12)
    f2 = tmp_path / "table.hdf5"
    with h5py.File(f2, "w") as g:
        g["data"] = np.column_stack([x, h])
    p2 = load_profile(f2)
    np.testing.assert_allclose(p2.h, h, atol=1e-12)
    f3 = tmp_path / "spacing.h5"
    with h5py.File(f3, "w") as g:
        g["z"] = h
        g["z"].attrs["dx"] = 0.02
    p3 = load_profile(f3)
    assert p3.dx == pytest.approx(0.02)


@pytest.mark.parametrize("content, error, match", [
    ("", ProfileFormatError, "empty"),
    ("# just a comment\n\n", ProfileFormatError, "empty|no rows"),
    ("x,h\n0,nan\n1,NaN\n2,nan\n3,nan\n", DefectError, "all 4 heights are dropouts"),
    ("0 1\n1 2\n3 3\n2 4\n4 5\n", ProfileFormatError, "not monotonic"),
    ("0 1\n1 1\n1 2\n2 2\n", ProfileFormatError, "not monotonic"),
    ("0,1\n1,2\n2,3\n3\n4,5\n", ProfileFormatError, "regular table"),
])
def test_bad_files_give_clear_errors(tmp_path, content, error, match):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    with pytest.raises(error, match=match):
        load_profile(f)


def test_missing_file_and_too_few_points(tmp_path):
    with pytest.raises(ProfileFormatError, match="not found"):
        load_profile(tmp_path / "nope.dat")
    f = tmp_path / "short.csv"
    f.write_text("0,1\n1,2\n2,nan\n3,4\n")
    with pytest.raises(DefectError, match="valid heights"):
        load_profile(f)


def test_sentinels_and_short_gaps_are_interpolated():
    x = np.arange(400) * 0.01
    h = np.sin(2 * np.pi * x / 1.3)
    raw = h.copy()
    raw[[50, 51, 52]] = -9999.0
    raw[200] = np.nan
    p = clean_profile(Profile(x, raw))
    rep = p.meta["defects"]
    assert (rep.n_sentinel, rep.n_nan) == (3, 1)
    assert rep.n_interpolated == 4 and p.repaired.sum() == 4
    # linear interpolation over a span of 4 steps: error <= max|h''| span^2 / 8
    np.testing.assert_allclose(p.h, h, atol=(2 * np.pi / 1.3) ** 2 * 0.04**2 / 8)
    np.testing.assert_array_equal(p.h[~p.repaired], h[~p.repaired])


def test_spikes_are_found_and_smooth_or_rough_data_are_left_alone():
    x = np.arange(5000) * 0.01
    h = 0.5 * np.sin(2 * np.pi * x / 3.0)
    raw = h.copy()
    raw[[700, 2300, 4100]] += [1.2, -0.9, 0.8]
    p = clean_profile(Profile(x, raw))
    rep = p.meta["defects"]
    assert rep.n_outlier_spike == 3 and rep.n_outlier_global == 0
    np.testing.assert_allclose(p.h, h, atol=1e-4)
    # a rough Gaussian profile has no outliers: none may be flagged
    g = self_affine_profile(100.0, 0.005, H=0.3, rms_height=1.0, seed=9)
    q = clean_profile(Profile(g.x, g.h))
    assert q.meta["defects"].n_outliers == 0
    np.testing.assert_array_equal(q.h, g.h)


def test_non_uniform_positions_are_resampled_and_rounded_ones_snapped():
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.uniform(0.007, 0.013, 3000))
    f = lambda t: np.sin(2 * np.pi * t / 2.0)  # noqa: E731
    xu, hu, info = resample_uniform(x, f(x))
    assert info["method"].startswith("interpolated")
    assert np.allclose(np.diff(xu), info["dx"])
    np.testing.assert_allclose(hu, f(xu), atol=(2 * np.pi / 2.0) ** 2 * 0.013**2 / 8 * 1.01)
    # positions rounded to 1e-3 of a 0.0375 grid: heights kept, grid recovered
    xr = np.round(np.arange(2000) * 0.0375, 3)
    xs, hs, info = resample_uniform(xr, f(xr))
    assert info["method"] == "snapped" and info["dx"] == pytest.approx(0.0375, rel=1e-5)
    np.testing.assert_array_equal(hs, f(xr))
    # missing rows become dropouts on the grid
    keep = np.ones(2000, bool)
    keep[[100, 101, 900]] = False
    xs, hs, info = resample_uniform(xr[keep], f(xr[keep]))
    assert info["missing_rows"] == 3 and xs.size == 2000
    assert np.isnan(hs[[100, 101, 900]]).all()


def test_detrend_is_explicit():
    x = np.linspace(0, 10, 101)
    p = Profile(x, 2.0 + 0.3 * x + np.sin(x))
    lin = detrend(p, "linear")
    assert np.polyfit(x, lin.h, 1) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert detrend(p, "mean").h.mean() == pytest.approx(0.0, abs=1e-12)
    assert detrend(p, None) is p
