"""Prony-series identification (eq. 3.34) against known series and the pyvisco DMA master curve."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.forms.compound import PronySeries
from rubberfriction.forms.prony import (default_tau, fit_prony, havriliak_negami,
                                        hn_loss_peak_omega, minimax_rel_error_bound, plot_fit,
                                        read_dma_csv, validate_dma)

# a known 8-term series on decade relaxation times, E_inf = 3 MPa
TRUE_TAU = np.logspace(-6, 1, 8)
TRUE_GAMMA = np.array([0.20, 0.25, 0.18, 0.12, 0.08, 0.06, 0.04, 0.03])
E_INF = 3.0


def _known() -> PronySeries:
    return PronySeries(TRUE_GAMMA, TRUE_TAU)


def _data(series: PronySeries, omega: np.ndarray,
          E_inf: float = E_INF) -> tuple[np.ndarray, np.ndarray]:
    """E', E'' of eq. (3.34) written out here, independently of PronySeries."""
    E0 = E_inf / (1 - series.gamma.sum())
    wt = np.outer(omega, series.tau)
    Ek = series.gamma * E0
    return E_inf + (wt**2 / (1 + wt**2)) @ Ek, (wt / (1 + wt**2)) @ Ek


OMEGA = np.logspace(-3, 7, 81)


def test_recovers_known_series_given_tau() -> None:
    E1, E2 = _data(_known(), OMEGA)
    fit = fit_prony(OMEGA, E1, E2, tau=TRUE_TAU)
    np.testing.assert_allclose(fit.series.gamma, TRUE_GAMMA, rtol=1e-6)
    assert fit.E_inf == pytest.approx(E_INF, rel=1e-6)
    assert fit.E_inf_fitted
    assert fit.rel_error_storage.max < 1e-6 and fit.rel_error_loss.max < 1e-6


def test_recovers_known_series_fixed_E_inf() -> None:
    E1, E2 = _data(_known(), OMEGA)
    fit = fit_prony(OMEGA, E1, E2, tau=TRUE_TAU[::-1], E_inf=E_INF)  # order of tau is irrelevant
    np.testing.assert_allclose(fit.series.gamma, TRUE_GAMMA, rtol=1e-6)
    assert fit.E_inf == E_INF and not fit.E_inf_fitted


def test_default_grid_reproduces_moduli() -> None:
    """Default grid: decades 10^floor(log10(1/w_max)) .. 10^ceil(log10(1/w_min)), 1e-7 .. 1e3 s."""
    E1, E2 = _data(_known(), OMEGA)
    tau = default_tau(OMEGA)
    np.testing.assert_allclose(tau, np.logspace(-7, 3, 11))
    fit = fit_prony(OMEGA, E1, E2)
    assert len(fit.series) == 11
    dense = np.logspace(-3, 7, 1001)
    D1, D2 = _data(_known(), dense)
    np.testing.assert_allclose(fit.series.storage(dense, fit.E_inf), D1, rtol=1e-6)
    np.testing.assert_allclose(fit.series.loss(dense, fit.E_inf), D2, rtol=1e-6)
    assert fit.rel_error_storage.max < 1e-6 and fit.rel_error_loss.max < 1e-6


def test_n_terms_grid() -> None:
    tau = default_tau(OMEGA, n_terms=6)
    np.testing.assert_allclose(tau, np.geomspace(1e-7, 1e3, 6))
    E1, E2 = _data(_known(), OMEGA)
    assert len(fit_prony(OMEGA, E1, E2, n_terms=6).series) == 6


def test_reported_errors_are_the_errors() -> None:
    """An off-grid series: the reported max/rms errors equal those recomputed from the series."""
    off = PronySeries(TRUE_GAMMA, TRUE_TAU * 3.1)
    E1, E2 = _data(off, OMEGA)
    fit = fit_prony(OMEGA, E1, E2, n_terms=5)
    r1 = fit.series.storage(OMEGA, fit.E_inf) / E1 - 1
    r2 = fit.series.loss(OMEGA, fit.E_inf) / E2 - 1
    assert fit.rel_error_storage.max == pytest.approx(np.abs(r1).max(), rel=1e-12)
    assert fit.rel_error_storage.rms == pytest.approx(np.sqrt(np.mean(r1**2)), rel=1e-12)
    assert fit.rel_error_loss.max == pytest.approx(np.abs(r2).max(), rel=1e-12)
    assert fit.rel_error_loss.rms == pytest.approx(np.sqrt(np.mean(r2**2)), rel=1e-12)
    assert f"{100 * fit.rel_error_loss.max:.3f}%" in fit.report()


def _kkt_violation(omega, E1, E2, fit) -> float:
    """KKT optimality of the relative least squares: gradient >= 0 on zero unknowns, 0 elsewhere.

    Returned relative to the gradient scale; written independently of the module.
    """
    wt = np.outer(omega, fit.series.tau)
    A = np.vstack([np.hstack([np.ones((omega.size, 1)), wt**2 / (1 + wt**2)]) / E1[:, None],
                   np.hstack([np.zeros((omega.size, 1)), wt / (1 + wt**2)]) / E2[:, None]])
    x = np.r_[fit.E_inf, fit.series.moduli(fit.E_inf)]
    r = A @ x - 1.0
    scale = np.linalg.norm(A, axis=0)
    g = (A.T @ r) / scale  # gradient per unit column norm
    active = x * scale > 1e-9 * (x * scale).max()
    return max(np.abs(g[active]).max(), max(0.0, -g[~active].min(initial=0.0))) / np.linalg.norm(r)


def test_pyvisco_master_curve(shared_data: Path) -> None:
    """Fit of the real DMA master curve pyvisco_freq_master.csv (206 points, 1e-12 .. 1e14 Hz).

    The brief asked for a max relative error below 5 % on E' and E''.  These data do not allow it:
    the linear programme below shows that NO Prony series on a dense grid (4 per decade, 1e-18 ..
    1e16 s, far beyond the data) can do better than about 28 % max error on both curves together,
    because the measured E'' (a flat ~11 MPa over 1e-12 .. 1e-6 Hz, and (2/pi) Int E'' dln(w)
    = 11 800 MPa against an E' rise of 9 500 MPa) violates the Kramers-Kronig relations that any
    linear viscoelastic solid obeys.  E' alone can be matched within 5 % (bound ~4.4 %); E'' alone
    only within ~8.6 % (scatter narrower than a relaxation peak).  What the test asserts:
    * the bound for both curves is above 5 % and E' alone is below (why 5 % is unreachable here);
    * our least-squares fit is optimal (KKT conditions hold to 1e-6) and no better than the bound;
    * its reported errors match those recomputed here (the numbers quoted in the report: E' max
      54 %, rms 20 %; E'' max 29 %, rms 14 %).
    """
    omega, E1, E2 = read_dma_csv(shared_data / "pyvisco_freq_master.csv")
    assert omega.size == 206
    fit = fit_prony(omega, E1, E2)
    dense = np.logspace(-18, 16, 137)
    bound = minimax_rel_error_bound(omega, E1, E2, dense)
    assert bound > 0.05
    assert minimax_rel_error_bound(omega, E1, E2, dense, curves="storage") < 0.05
    assert minimax_rel_error_bound(omega, E1, E2, dense, curves="loss") > 0.05
    worst = max(fit.rel_error_storage.max, fit.rel_error_loss.max)
    assert worst >= bound * (1 - 1e-6)
    assert _kkt_violation(omega, E1, E2, fit) < 1e-6
    r1 = fit.series.storage(omega, fit.E_inf) / E1 - 1
    r2 = fit.series.loss(omega, fit.E_inf) / E2 - 1
    assert fit.rel_error_storage.max == pytest.approx(np.abs(r1).max(), rel=1e-12)
    assert fit.rel_error_loss.rms == pytest.approx(np.sqrt(np.mean(r2**2)), rel=1e-12)
    assert fit.E_inf > 0 and fit.series.gamma_inf > 0


def test_minimax_bound_zero_for_exact_data() -> None:
    E1, E2 = _data(_known(), OMEGA)
    assert minimax_rel_error_bound(OMEGA, E1, E2, TRUE_TAU) < 1e-7


def test_havriliak_negami_peak_closed_form() -> None:
    for alpha, beta in ((0.5, 0.5), (0.3, 0.8), (1.0, 1.0)):
        w = np.logspace(-4, 4, 400001)
        E = havriliak_negami(w, 1.0, 1000.0, 1.0, alpha, beta)
        assert w[np.argmax(E.imag)] == pytest.approx(hn_loss_peak_omega(1.0, alpha, beta), rel=1e-4)
    # Debye case alpha = beta = 1: a single Maxwell element with tau0
    w = np.array([0.1, 1.0, 10.0])
    single = PronySeries.from_moduli(1.0, [999.0], [1.0])
    np.testing.assert_allclose(havriliak_negami(w, 1.0, 1000.0, 1.0, 1.0, 1.0),
                               single.complex_modulus(w, 1.0), rtol=1e-12)


# ------------------------------------------------------------------------------------------
# bad input
# ------------------------------------------------------------------------------------------

W3 = np.array([1.0, 10.0, 100.0])
P3 = np.array([1.0, 2.0, 3.0])


@pytest.mark.parametrize("omega, E1, E2, match", [
    (np.array([1.0, 100.0, 10.0]), P3, P3, "not sorted"),
    (np.array([1.0, 10.0, 10.0]), P3, P3, "repeats"),
    (np.array([0.0, 10.0, 100.0]), P3, P3, r"omega\[0\]"),
    (np.array([-1.0, 10.0, 100.0]), P3, P3, r"omega\[0\]"),
    (np.array([1.0, math.nan, 100.0]), P3, P3, r"omega\[1\]"),
    (W3, np.array([1.0, math.inf, 3.0]), P3, r"E_storage\[1\]"),
    (W3, np.array([1.0, -2.0, 3.0]), P3, r"E_storage\[1\]"),
    (W3, P3, np.array([1.0, 2.0, -3.0]), r"E_loss\[2\]"),
    (W3, P3, np.array([1.0, 0.0, 3.0]), r"E_loss\[1\]"),
    (W3, P3[:2], P3, "equal lengths"),
    (W3[:1], P3[:1], P3[:1], "at least 2"),
])
def test_bad_dma_data(omega, E1, E2, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        fit_prony(omega, E1, E2)


def test_explicit_sort_only() -> None:
    w, E1, E2 = validate_dma([100.0, 1.0, 10.0], [3.0, 1.0, 2.0], [0.3, 0.1, 0.2], sort=True)
    np.testing.assert_array_equal(w, [1.0, 10.0, 100.0])
    np.testing.assert_array_equal(E1, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(E2, [0.1, 0.2, 0.3])


@pytest.mark.parametrize("kwargs, match", [
    (dict(n_terms=3, tau=[1.0, 2.0]), "not both"),
    (dict(n_terms=0), "n_terms"),
    (dict(tau=[1.0, -1.0]), "tau"),
    (dict(tau=[1.0, 1.0]), "tau"),
    (dict(E_inf=-1.0), "E_inf"),
    (dict(E_inf=math.nan), "E_inf"),
    (dict(weights="log"), "weights"),
])
def test_bad_fit_options(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        fit_prony(W3, P3, P3, **kwargs)


def test_fluid_fit_is_refused() -> None:
    """E'' ~ omega^1 and E' ~ omega^2 at all frequencies: a Maxwell fluid, no equilibrium spring."""
    w = np.logspace(-2, 0, 21)
    wt = w * 1e4  # a single Maxwell element, tau = 1e4 s, E_1 = 1 MPa, no spring
    with pytest.raises(ValueError, match="E_inf is 0"):
        fit_prony(w, wt**2 / (1 + wt**2), wt / (1 + wt**2), tau=[1e4])


# ------------------------------------------------------------------------------------------
# reading and plotting
# ------------------------------------------------------------------------------------------


def test_read_pyvisco_csv(shared_data: Path) -> None:
    omega, E1, E2 = read_dma_csv(shared_data / "pyvisco_freq_master.csv")
    # first data row: 1e-12 Hz, 88.79651575665739 MPa, 10.502460140936773 MPa
    assert omega[0] == pytest.approx(2 * np.pi * 1e-12, rel=1e-15)
    assert (E1[0], E2[0]) == (88.79651575665739, 10.502460140936773)
    with pytest.raises(ValueError, match="rad/s"):
        read_dma_csv(shared_data / "pyvisco_freq_master.csv", freq_unit="rad/s")
    with pytest.raises(ValueError, match="column 'E1' not found"):
        read_dma_csv(shared_data / "pyvisco_freq_master.csv", columns=("f", "E1", "E_loss"))


def test_read_csv_units_and_order(tmp_path: Path) -> None:
    path = tmp_path / "dma.csv"
    path.write_text("# comment line\nE_loss,freq,E_stor\nkPa,rad/s,kPa\n100,10,2000\n50,1,1000\n")
    with pytest.raises(ValueError, match="not sorted"):
        read_dma_csv(path, freq_unit="rad/s", columns=("freq", "E_stor", "E_loss"))
    w, E1, E2 = read_dma_csv(path, freq_unit="rad/s", columns=(1, 2, 0), sort=True)
    np.testing.assert_array_equal(w, [1.0, 10.0])
    np.testing.assert_allclose(E1, [1.0, 2.0])    # kPa -> MPa
    np.testing.assert_allclose(E2, [0.05, 0.1])
    bad = tmp_path / "bad.csv"
    bad.write_text("f,E_stor,E_loss\n1,2,x\n2,3,4\n")
    with pytest.raises(ValueError, match="non-numeric"):
        read_dma_csv(bad)


def test_plot_fit(tmp_path: Path) -> None:
    E1, E2 = _data(_known(), OMEGA)
    fit = fit_prony(OMEGA, E1, E2)
    out = plot_fit(fit, OMEGA, E1, E2, tmp_path / "fit.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 10_000
