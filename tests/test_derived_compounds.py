"""Compounds c1..c6 derived from one DMA curve (forms/derive.py, scripts/make_derived_compounds.py).

Each transformation is pinned by its exact identity (closed forms written here); the shipped files
must be what the script writes; cross-file identities follow exactly from the construction.  No
trend outcome (e.g. which compound has more friction) is tested: issue 44, item 6.
"""

from __future__ import annotations

import importlib.util
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.forms import derive as D
from rubberfriction.forms.compound import WLF, ZERO_CELSIUS, MooneyRivlin
from rubberfriction.forms.material_files import load_compound

ROOT = Path(__file__).resolve().parents[1]
T20 = 20.0 + ZERO_CELSIUS
W = np.logspace(-3, 12, 61)  # rad/s

_spec = importlib.util.spec_from_file_location("make_derived_compounds",
                                               ROOT / "scripts" / "make_derived_compounds.py")
MK = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = MK  # dataclasses look their module up
_spec.loader.exec_module(MK)

# thesis table 6.1 (C10, C01, D1), written here independently of the script
TABLE = {"c1": (0.136, 0.518, 0.031), "c2": (0.246, 0.489, 0.027), "c3": (0.174, 0.309, 0.042),
         "c4": (0.150, 0.623, 0.026), "c5": (0.327, 0.613, 0.021), "c6": (0.219, 0.318, 0.038)}


@pytest.fixture(scope="module")
def build() -> MK.Build:
    return MK.build()


def _toy() -> D.Spectrum:
    return D.Spectrum(2.0, [5.0, 40.0, 100.0, 30.0, 3.0], [1e-7, 1e-5, 1e-4, 1e-3, 1e-1],
                      WLF(7.95, 109.32, T20))


def test_rereference_wlf_is_the_same_law() -> None:
    w = WLF(7.95, 109.32, T20)
    r = D.rereference_wlf(w, T20 - 25.0)
    T = np.array([260.0, 280.0, 300.0, 350.0])
    np.testing.assert_allclose(r.log10_aT(T), w.log10_aT(T) - w.log10_aT(T20 - 25.0),
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("dT", [-20.0, 15.0])
def test_tg_shift_moves_the_loss_peak_by_the_wlf_factor(dT: float) -> None:
    sp = _toy()
    new = D.shift_glass_transition(sp, dT)
    F = 10.0 ** (7.95 * dT / (109.32 - dT))  # tau_new(T_ref) = a_base(T_ref - dT) tau_base
    assert D.tg_shift_factor(sp.wlf, dT) == pytest.approx(F, rel=1e-13)
    peak0, peak1 = D.loss_peak_omega(sp.E_k, sp.tau), D.loss_peak_omega(new.E_k, new.tau)
    assert peak1 / peak0 == pytest.approx(1.0 / F, rel=1e-9)
    assert (peak1 < peak0) == (dT > 0)  # higher Tg: the peak at T_ref at lower frequency
    # the whole temperature picture translated: E*_new(w, T) = E*_base(w, T - dT)
    for T in (T20 - 10.0, T20, T20 + 30.0):
        np.testing.assert_allclose(new.complex_modulus(W, T), sp.complex_modulus(W, T - dT),
                                   rtol=1e-11)
    back = D.shift_glass_transition(new, -dT)
    np.testing.assert_allclose(back.tau, sp.tau, rtol=1e-12)
    assert (back.wlf.c1, back.wlf.c2) == pytest.approx((7.95, 109.32), rel=1e-12)


def test_gent_relation_and_hardness_scaling() -> None:
    # Gent (1958) at S = 50: 0.0981 (56 + 381.168) / (0.137505 * 127)
    assert D.gent_modulus(50.0) == pytest.approx(0.0981 * 437.168 / (0.137505 * 127.0), rel=1e-13)
    assert D.gent_shore(D.gent_modulus(63.0)) == pytest.approx(63.0, rel=1e-12)
    s = D.hardness_factor(57.0, 10.0)
    assert s == pytest.approx(D.gent_modulus(67.0) / D.gent_modulus(57.0), rel=1e-14)
    sp = _toy()
    hard = D.scale_moduli(sp, s)
    for T in (T20, T20 + 40.0):
        np.testing.assert_allclose(hard.complex_modulus(W, T), s * sp.complex_modulus(W, T),
                                   rtol=1e-13)


def test_filler_stretch_and_modulus_ratio() -> None:
    sp = _toy()
    tau_p = 1.0 / D.loss_peak_omega(sp.E_k, sp.tau)
    m = D.guth_gold(D.filler_volume_fraction(35.0))
    phi = (35 / 1.8) / (35 / 1.8 + 100 / 0.93)
    assert m == pytest.approx(1 + 2.5 * phi + 14.1 * phi**2, rel=1e-14)
    f = D.apply_filler(sp, 1.25, m)
    assert D.log_tau_spread(f, tau_p) == pytest.approx(1.25 * D.log_tau_spread(sp, tau_p),
                                                       rel=1e-12)
    np.testing.assert_allclose(np.log(f.tau / tau_p), 1.25 * np.log(sp.tau / tau_p), rtol=1e-12)
    assert f.E_k.sum() == pytest.approx(m * sp.E_k.sum(), rel=1e-13)  # E0 - E_inf
    assert f.E_inf == sp.E_inf
    # E_k scaling leaves the FWHM unchanged.  The FWHM itself need not grow with the stretch
    # for a few discrete terms (here it falls: one term dominates the peak), so it is not pinned.
    stretched = D.stretch_spectrum(sp, 1.25)
    assert D.loss_fwhm_decades(f.E_k, f.tau) == pytest.approx(
        D.loss_fwhm_decades(stretched.E_k, stretched.tau), rel=1e-9)
    back = D.stretch_spectrum(stretched, 0.8, tau_p)
    np.testing.assert_allclose(back.tau, sp.tau, rtol=1e-12)


def test_loss_half_width_is_half_the_maximum() -> None:
    sp = _toy()
    lo, hi = D.loss_half_width(sp.E_k, sp.tau)
    peak = sp.complex_modulus([D.loss_peak_omega(sp.E_k, sp.tau)]).imag[0]
    np.testing.assert_allclose(sp.complex_modulus([lo, hi]).imag, 0.5 * peak, rtol=1e-10)
    # one Maxwell element: FWHM of x/(1+x^2) is 2 log10(2 + sqrt 3) decades
    assert D.loss_fwhm_decades([1.0], [1e-3]) == pytest.approx(
        2 * math.log10(2 + math.sqrt(3)), rel=1e-10)


def test_shipped_files_are_what_the_script_writes(tmp_path: Path) -> None:
    assert MK.main(["--out", str(tmp_path), "--no-plot"]) == 0
    for name in TABLE:
        shipped = tomllib.loads((ROOT / "forms" / "data" / f"{name}.toml").read_text())
        fresh = tomllib.loads((tmp_path / f"{name}.toml").read_text())
        for key in ("gamma", "tau"):
            np.testing.assert_allclose(shipped["prony"][key], fresh["prony"].pop(key), rtol=1e-9)
            shipped["prony"].pop(key)
        for key in ("c1", "c2", "T_ref"):
            assert shipped["wlf"].pop(key) == pytest.approx(fresh["wlf"].pop(key), rel=1e-9)
        assert shipped == fresh, name


def test_shipped_files_hold_the_table_and_the_derived_moduli(build: MK.Build) -> None:
    """Long-term modulus = table 6.1's Mooney-Rivlin E_inf; Maxwell moduli E_k = the derived
    ones (gamma_k written against that E_inf): an edited C10/C01/D1 or gamma breaks this."""
    for c in build.compounds:
        comp = load_compound(c.row.name)
        C10, C01, D1 = TABLE[c.row.name]
        mr = comp.hyperelastic
        assert (mr.C10, mr.C01, mr.D1) == (C10, C01, D1)
        mu, K = 2 * (C10 + C01), 2 / D1
        assert comp.E_inf == pytest.approx(9 * K * mu / (3 * K + mu), rel=1e-12)
        np.testing.assert_allclose(comp.prony.moduli(comp.E_inf), c.derived.E_k, rtol=1e-10)
        np.testing.assert_allclose(comp.prony.tau, c.derived.tau, rtol=1e-12)
        np.testing.assert_allclose(comp.complex_modulus(W, T20 + 5.0).imag,
                                   c.derived.complex_modulus(W, T20 + 5.0).imag, rtol=1e-10)


def test_base_is_the_anchored_dma_fit(build: MK.Build) -> None:
    c6 = load_compound("c6")
    assert build.base.E_inf == pytest.approx(MooneyRivlin(*TABLE["c6"]).E, rel=1e-12)
    np.testing.assert_allclose(c6.complex_modulus(W, T20), build.base.complex_modulus(W),
                               rtol=1e-10)
    assert c6.wlf.T_ref == pytest.approx(T20, abs=1e-9)


@pytest.mark.parametrize("low, high", [("c4", "c1"), ("c5", "c2")])
def test_tg_pairs_are_exact_translations(low: str, high: str) -> None:
    """c4 = c1 and c5 = c2 with Tg - 20 K: E''(w, T) of the low-Tg compound equals E'' of the
    other at T + 20 K (E'' does not depend on the files' different long-term moduli)."""
    a, b = load_compound(low), load_compound(high)
    for T in (T20 - 10.0, T20, T20 + 25.0):
        np.testing.assert_allclose(a.complex_modulus(W, T).imag,
                                   b.complex_modulus(W, T + 20.0).imag, rtol=1e-9)


@pytest.mark.parametrize("hard, soft", [("c1", "c3"), ("c2", "c6")])
def test_hardness_pairs_scale_the_loss_modulus(hard: str, soft: str, build: MK.Build) -> None:
    s = D.hardness_factor(D.gent_shore(MooneyRivlin(*TABLE["c6"]).E), 10.0)
    a, b = load_compound(hard), load_compound(soft)
    for T in (T20, T20 + 30.0):
        np.testing.assert_allclose(a.complex_modulus(W, T).imag,
                                   s * b.complex_modulus(W, T).imag, rtol=1e-9)
