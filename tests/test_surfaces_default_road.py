"""The embedded default road (measured CAPTIF + generated fine extension) and the surface CLI."""

import importlib
import json

import numpy as np
import pytest

from rubberfriction.driver.cli import main as cli
from rubberfriction.driver.surfaces import (
    DEFAULT_EDGES,
    default_road,
    find_station0,
    fit_psd_power_law,
    load_profile,
    log_bin,
    psd_1d,
)

# the package exports the function default_road; the module is reached by its full name
dr_module = importlib.import_module("rubberfriction.driver.surfaces.default_road")


@pytest.fixture(scope="module")
def road(shared_data):
    return default_road(shared_data)


def test_default_road_scales_and_provenance(road, shared_data):
    assert road.edges == (20.0, 3.0, 0.3, 0.04, 0.003) == DEFAULT_EDGES
    assert road.names == ["macro", "meso", "micro1", "micro2"]
    assert [sc.kind for sc in road.scales] == ["measured", "measured", "generated", "generated"]
    assert [sc.block_length for sc in road.scales] == [20.0, 3.0, 0.3, 0.04]
    assert road.scales[0].measurement == str(shared_data / "captif_chipseal_station0.dat")
    gen = road.provenance["generated"]
    assert gen["kind"] == "generated" and gen["fit_range_mm"] == [3.0, 0.3]
    assert gen["cutoff_mm"] == 0.003 and gen["seed"] == dr_module.DEFAULT_SEED
    assert road.provenance["measured"]["sha256"].startswith("ea097ad4")
    assert "near_resolution_limit" not in road.provenance
    text = road.describe()
    assert text.count("MEASURED") == 2 and text.count("GENERATED") == 2
    # every scale is resolved by its source with >= 4 samples per shortest wavelength
    for sc in road.scales:
        assert sc.band[1] >= 4 * sc.profile.dx * (1 - 1e-9)
        assert sc.profile.length >= sc.band[0]


def test_fine_extension_continues_the_measured_power_law(road, shared_data):
    measured = load_profile(shared_data / "captif_chipseal_station0.dat")
    q, c = psd_1d(measured, window="hann", detrend="linear")
    fit = fit_psd_power_law(q, c, (2 * np.pi / 3.0, 2 * np.pi / 0.3))
    assert road.provenance["generated"]["H"] == pytest.approx(fit.H, abs=1e-12)
    assert 0.5 < fit.H < 1.0
    # the generated micro bands follow K q^-(1+2H) on average (Gaussian scatter of the bins)
    for sc in road.scales[2:]:
        qg, cg = psd_1d(sc.profile, window=None, detrend="mean")
        lo, hi = 2 * np.pi / sc.band[0], 2 * np.pi / sc.band[1]
        m = (qg > lo) & (qg < hi)
        qb, cb, _ = log_bin(qg[m], cg[m])
        assert np.exp(np.mean(np.log(cb / fit(qb)))) == pytest.approx(1.0, abs=0.1)
    # and the measured meso band has the rms its PSD says
    meso = road.scales[1].profile
    rms = [sc.profile.rms_height() for sc in road.scales]
    assert meso.rms_height() == rms[1] and rms[0] > rms[1] > rms[2] > rms[3] > 0


def test_default_road_is_reproducible_and_has_ten_samples_per_scale(road, shared_data):
    again = default_road(shared_data)
    for a, b in zip(road.scales, again.scales):
        np.testing.assert_array_equal(a.profile.h, b.profile.h)
    samples = road.extract_samples(10, seed=1)
    assert [len(g) for g in samples] == [10, 10, 10, 10]
    assert [g[0].source for g in samples] == ["measured", "measured", "generated", "generated"]
    for g, sc in zip(samples, road.scales):
        for s in g:
            assert s.period == sc.block_length and s.h[-1] == s.h[0]
            assert s.closure_length <= 0.25 * s.period + 1e-12


def test_default_road_falls_back_to_the_embedded_copy(monkeypatch, tmp_path, road):
    monkeypatch.delenv("RF_SHARED_DATA", raising=False)
    monkeypatch.setattr(dr_module, "_repo_shared_data", lambda: tmp_path / "missing")
    path, where = find_station0()
    assert path == dr_module.EMBEDDED_STATION0 and "embedded" in where
    emb = default_road()
    assert emb.provenance["measured"]["found_in"].startswith("copy embedded")
    np.testing.assert_array_equal(emb.scales[0].profile.h, road.scales[0].profile.h)
    np.testing.assert_array_equal(emb.scales[3].profile.h, road.scales[3].profile.h)


def test_cli_analyse_writes_json_and_plot(shared_data, tmp_path, capsys):
    out_json, out_png = tmp_path / "a.json", tmp_path / "a.png"
    rc = cli.main(["surface", "analyse", str(shared_data / "captif_chipseal_station0.dat"),
                   "--edges", "20", "3", "0.3", "--psd-fit", "3", "0.3",
                   "--json", str(out_json), "--plot", str(out_png)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "dropouts: 4373" in text and "xi_par" in text
    data = json.loads(out_json.read_text())
    assert data["defects"]["n_nan"] == 4373
    assert data["hdc_fit"]["fit_range"][0] == pytest.approx(4 * data["dx_mm"])
    assert "Persson" in data["psd"]["convention"]
    assert [b["band_mm"] for b in data["bands"]] == [[20.0, 3.0], [3.0, 0.3]]
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_split_takes_each_band_from_the_resolving_file(shared_data, tmp_path, capsys):
    fine = tmp_path / "fine.csv"
    assert cli.main(["surface", "generate", "self-affine", "--length", "4", "--dx", "0.002",
                     "--rms", "0.01", "--out", str(fine)]) == 0
    out = tmp_path / "split"
    rc = cli.main(["surface", "split", str(shared_data / "captif_chipseal_station0.dat"), str(fine),
                   "--edges", "20", "3", "0.3", "0.04", "--samples", "3", "--seed", "2",
                   "--out", str(out)])
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    kinds = [s["measurement"] for s in summary["surface"]["scales"]]
    assert kinds[0].endswith("station0.dat") and kinds[1].endswith("station0.dat")
    assert kinds[2].endswith("fine.csv")
    poly = np.loadtxt(out / "micro_sample00.csv", delimiter=",")
    assert poly[-1, 0] == pytest.approx(0.3) and poly[-1, 1] == poly[0, 1]
    assert len(list(out.glob("*_sample*.csv"))) == 9 and (out / "samples.png").is_file()


def test_cli_default_and_bench(tmp_path, capsys, monkeypatch):
    out = tmp_path / "default"
    assert cli.main(["surface", "default", "--out", str(out), "--samples", "2"]) == 0
    assert "dropped" in capsys.readouterr().out  # the slope cut-off drops the generated bands
    assert len(list(out.glob("*_sample*.csv"))) == 4
    out = tmp_path / "default_to_3um"
    assert cli.main(["surface", "default", "--out", str(out), "--samples", "2",
                     "--cutoff", "0.003"]) == 0
    assert len(list(out.glob("*_sample*.csv"))) == 8
    s = json.loads((out / "summary.json").read_text())
    kinds = [sc["kind"] for sc in s["surface"]["scales"]]
    assert kinds == ["measured", "measured", "generated", "generated"]
    from rubberfriction.driver.bench import surfaces as bench_surfaces

    assert bench_surfaces.main(["--points", "40000", "--samples", "2"]) == 0
    assert "decompose into 4 scales" in capsys.readouterr().out
