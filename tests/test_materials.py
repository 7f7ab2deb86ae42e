"""Material objects and data files vs closed forms and the thesis tables (ch. 3.3, app. A, C)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.forms import material_files, spectrum
from rubberfriction.forms.compound import Compound, MooneyRivlin, PronySeries, Road, Thermal, WLF
from rubberfriction.forms.material_files import load_compound, load_road
from rubberfriction.forms.prony import loss_peak_omega

C = 273.15  # K at 0 degC

# ------------------------------------------------------------------------------------------
# WLF (eq. 3.33, 3.37)
# ------------------------------------------------------------------------------------------

# log10 aT = -c1 (T - Tref) / (c2 + T - Tref), c1 = 7.95, c2 = 109.32, Tref = 20 degC, by hand:
#   -10 degC: dT = -30 ->  238.5 / 79.32  =  3.0068078669...
#     0 degC: dT = -20 ->  159.0 / 89.32  =  1.7801164353...
#    40 degC: dT =  20 -> -159.0 / 129.32 = -1.2295081967...
#    80 degC: dT =  60 -> -477.0 / 169.32 = -2.8171509568...
WLF_TABLE = [(-10.0, 3.0068078669), (0.0, 1.7801164353), (40.0, -1.2295081967),
             (80.0, -2.8171509568)]


@pytest.fixture()
def wlf_m1() -> WLF:
    return WLF(c1=7.95, c2=109.32, T_ref=20.0 + C)


@pytest.mark.parametrize("T_C, expected", WLF_TABLE)
def test_wlf_table(wlf_m1: WLF, T_C: float, expected: float) -> None:
    assert wlf_m1.log10_aT(T_C + C) == pytest.approx(expected, abs=1e-9)
    assert wlf_m1.aT(T_C + C) == pytest.approx(10.0**expected, rel=1e-8)


def test_wlf_vectorised_and_shift(wlf_m1: WLF) -> None:
    T = np.array([[-10.0, 0.0], [40.0, 80.0]]) + C
    got = wlf_m1.log10_aT(T)
    assert got.shape == (2, 2)
    np.testing.assert_allclose(got.ravel(), [v for _, v in WLF_TABLE], atol=1e-9)
    assert wlf_m1.log10_aT(20.0 + C) == 0.0
    # eq. 3.37: tau(T) = a(T) tau_ref; colder -> slower
    assert wlf_m1.shift_tau(1e-3, 0.0 + C) == pytest.approx(1e-3 * 10**1.7801164353, rel=1e-8)
    np.testing.assert_allclose(wlf_m1.shift_tau(np.array([1.0, 2.0]), 40.0 + C),
                               10**-1.2295081967 * np.array([1, 2]), rtol=1e-8)
    assert WLF.from_celsius(7.95, 109.32, 20.0) == wlf_m1


def test_wlf_singularity(wlf_m1: WLF) -> None:
    T_sing = 20.0 + C - 109.32
    for T in (T_sing, T_sing - 5.0, np.array([300.0, T_sing - 1.0])):
        with pytest.raises(ValueError, match="singularity"):
            wlf_m1.log10_aT(T)
    assert np.isfinite(wlf_m1.log10_aT(T_sing + 1e-6))


@pytest.mark.parametrize("kwargs, field", [
    (dict(c1=-7.95, c2=109.32, T_ref=293.15), "c1"),
    (dict(c1=7.95, c2=0.0, T_ref=293.15), "c2"),
    (dict(c1=7.95, c2=109.32, T_ref=-1.0), "T_ref"),
    (dict(c1=math.nan, c2=109.32, T_ref=293.15), "c1"),
    (dict(c1=7.95, c2=math.inf, T_ref=293.15), "c2"),
])
def test_wlf_bad_input(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=f"WLF.{field}"):
        WLF(**kwargs)


# ------------------------------------------------------------------------------------------
# Mooney-Rivlin (eq. 3.53, 3.58, A.7-A.9, 3.60)
# ------------------------------------------------------------------------------------------

# table C.2 / 6.1 / 7.1 (C10, C01, D1); the checks below recompute mu, K by hand
TABLES = {"m1": (0.174, 0.300, 0.0208), "m2": (0.174, 0.309, 0.0417), "m3": (0.347, 0.810, 0.0174),
          "c1": (0.136, 0.518, 0.031), "c2": (0.246, 0.489, 0.027), "c3": (0.174, 0.309, 0.042),
          "c4": (0.150, 0.623, 0.026), "c5": (0.327, 0.613, 0.021), "c6": (0.219, 0.318, 0.038),
          "A": (0.382, 0.300, 0.029), "B": (0.113, 0.581, 0.029), "C": (0.374, 0.266, 0.031),
          "tread_default": (0.174, 0.300, 0.001)}  # m1's C10, C01; K = 2 GPa (the file's comments)


def test_mr_moduli_m1() -> None:
    mr = MooneyRivlin(0.174, 0.300, 0.0208)
    assert mr.mu == pytest.approx(0.948, rel=1e-12)          # 2 (0.174 + 0.300)
    assert mr.K == pytest.approx(96.153846153846, rel=1e-12)  # 2 / 0.0208
    # A.7: E = 2 mu (1 + nu) = 3 K (1 - 2 nu)
    assert mr.E == pytest.approx(2 * mr.mu * (1 + mr.nu), rel=1e-12)
    assert mr.E == pytest.approx(3 * mr.K * (1 - 2 * mr.nu), rel=1e-12)
    K = 96.153846153846
    assert mr.E == pytest.approx(9 * K * 0.948 / (3 * K + 0.948), rel=1e-10)


def _psi_split(mr: MooneyRivlin, F: np.ndarray) -> float:
    """Eq. (3.58) with + C01, J_th = 1, written out independently of the module."""
    J = np.linalg.det(F)
    Cb = J ** (-2 / 3) * F.T @ F
    I1, I2 = np.trace(Cb), 0.5 * (np.trace(Cb) ** 2 - np.trace(Cb @ Cb))
    return mr.C10 * (I1 - 3) + mr.C01 * (I2 - 3) + (J - 1) ** 2 / mr.D1


def _psi_feap(mu1: float, mu2: float, lam: float, F: np.ndarray) -> float:
    """Eq. (3.53) as printed ("- mu2/2"); the module's "+ mu2" convention: mu2 -> -mu2."""
    J = np.linalg.det(F)
    b = F @ F.T
    I, II = np.trace(b), 0.5 * (np.trace(b) ** 2 - np.trace(b @ b))
    return (mu1 / 2 * (I - 3 - 2 * np.log(J)) - mu2 / 2 * (II - 3 - 4 * np.log(J))
            + lam / 4 * (J**2 - 1 - 2 * np.log(J)))


def _small_strain_moduli(psi) -> tuple[float, float]:
    """mu from simple shear (Psi = mu g^2 / 2), K from pure dilatation (Psi = K e^2 / 2)."""
    g, e = 1e-4, 1e-4
    shear = np.eye(3)
    shear[0, 1] = g
    dil = (1 + e) ** (1 / 3) * np.eye(3)
    return 2 * psi(shear) / g**2, 2 * psi(dil) / e**2


@pytest.mark.parametrize("name", ["m1", "c1", "m3"])
def test_mr_split_form_small_strain(name: str) -> None:
    """The '+ C01' reading of eq. 3.58 gives mu = 2 (C10 + C01) and K = 2/D1 (eq. A.8)."""
    C10, C01, D1 = TABLES[name]
    mr = MooneyRivlin(C10, C01, D1)
    mu, K = _small_strain_moduli(lambda F: _psi_split(mr, F))
    assert mu == pytest.approx(2 * (C10 + C01), rel=1e-3)
    assert K == pytest.approx(2 / D1, rel=1e-3)
    assert mu == pytest.approx(mr.mu, rel=1e-3) and K == pytest.approx(mr.K, rel=1e-3)


@pytest.mark.parametrize("name", ["m1", "c1", "m3"])
def test_mr_feap_mapping(name: str) -> None:
    """Eq. 3.53 with mu1, mu2, lambda from the mapping has the same small-strain mu and K."""
    mr = MooneyRivlin(*TABLES[name], form="feap")
    assert mr.mu1 + mr.mu2 == pytest.approx(mr.mu, rel=1e-12)
    assert mr.mu2 == pytest.approx(2 * TABLES[name][1], rel=1e-12)
    mu, K = _small_strain_moduli(lambda F: _psi_feap(mr.mu1, -mr.mu2, mr.lam, F))
    assert mu == pytest.approx(mr.mu, rel=1e-3)
    assert K == pytest.approx(mr.K, rel=1e-3)
    back = MooneyRivlin.from_feap(mr.mu1, mr.mu2, mr.lam)
    assert (back.C10, back.C01, back.D1) == pytest.approx(TABLES[name], rel=1e-12)


def test_mr_constructors() -> None:
    nh = MooneyRivlin.neo_hooke(mu=1.2, K=600.0)
    assert (nh.C10, nh.C01, nh.D1) == pytest.approx((0.6, 0.0, 2 / 600.0))
    assert nh.mu == pytest.approx(1.2) and nh.K == pytest.approx(600.0)
    # eq. 3.60 against A.7-A.9: E = 6 MPa, nu = 0.49, f = 0.3
    bk = MooneyRivlin.from_blatz_ko(E=6.0, nu=0.49, f=0.3)
    mu, K = 6.0 / (2 * 1.49), 6.0 / (3 * (1 - 0.98))
    assert (bk.C10, bk.C01) == pytest.approx((mu / 2 * 0.3, mu / 2 * 0.7), rel=1e-12)
    assert bk.K == pytest.approx(K, rel=1e-12) and bk.E == pytest.approx(6.0, rel=1e-12)
    assert bk.nu == pytest.approx(0.49, rel=1e-12)


@pytest.mark.parametrize("args, field", [
    ((0.0, 0.3, 0.02), "C10"), ((-0.1, 0.3, 0.02), "C10"), ((0.17, -0.3, 0.02), "C01"),
    ((0.17, 0.3, 0.0), "D1"), ((0.17, 0.3, -0.02), "D1"), ((math.nan, 0.3, 0.02), "C10"),
    ((0.17, math.inf, 0.02), "C01"), ((0.17, 0.3, "0.02"), "D1"),
])
def test_mr_bad_input(args: tuple, field: str) -> None:
    with pytest.raises(ValueError, match=f"MooneyRivlin.{field}"):
        MooneyRivlin(*args)


def test_mr_bad_form() -> None:
    with pytest.raises(ValueError, match="MooneyRivlin.form"):
        MooneyRivlin(0.17, 0.3, 0.02, form="abaqus")


# ------------------------------------------------------------------------------------------
# Prony series (eq. 3.34-3.36)
# ------------------------------------------------------------------------------------------


def test_single_maxwell_closed_forms() -> None:
    E_inf, E1, tau = 2.0, 98.0, 1e-3
    s = PronySeries.from_moduli(E_inf, [E1], [tau])
    assert s.gamma[0] == pytest.approx(0.98) and s.gamma_inf == pytest.approx(0.02)
    assert s.E0(E_inf) == pytest.approx(100.0)
    w = np.logspace(-3, 9, 120001)
    loss = s.loss(w, E_inf)
    assert w[np.argmax(loss)] == pytest.approx(1 / tau, rel=2e-4)       # peak at omega = 1/tau
    assert s.loss(1 / tau, E_inf) == pytest.approx(E1 / 2, rel=1e-14)  # of height E1/2
    assert s.storage(1 / tau, E_inf) == pytest.approx(E_inf + E1 / 2, rel=1e-14)
    assert s.storage(0.0, E_inf) == pytest.approx(E_inf, rel=1e-14)       # E'(0) = E_inf
    assert s.storage(1e12 / tau, E_inf) == pytest.approx(100.0, rel=1e-12)  # E'(inf) = E0
    assert s.loss(0.0, E_inf) == 0.0
    wt = 3.7
    expected = E_inf + E1 * (1j * wt) / (1 + 1j * wt)
    assert s.complex_modulus(wt / tau, E_inf) == pytest.approx(expected, rel=1e-14)
    # relaxation E(t) = E0 (gamma_inf + gamma exp(-t/tau))
    assert s.relaxation(0.0, E_inf) == pytest.approx(100.0)
    assert s.relaxation(tau, E_inf) == pytest.approx(E_inf + E1 / math.e, rel=1e-14)
    assert s.relaxation(1e3, E_inf) == pytest.approx(E_inf, rel=1e-12)


def test_prony_sum_rule_and_shapes() -> None:
    """Kramers-Kronig-type sum rule (2/pi) Int E'' d ln(omega) = E0 - E_inf (pi/2 E_k per term)."""
    s = PronySeries([0.3, 0.2, 0.25, 0.1], [1e-5, 1e-3, 1e-1, 1e1])
    E_inf = 5.0
    lnw = np.linspace(np.log(1e-9), np.log(1e13), 200001)
    integral = 2 / np.pi * np.trapz(s.loss(np.exp(lnw), E_inf), lnw)
    assert integral == pytest.approx(s.E0(E_inf) - E_inf, rel=1e-6)
    W = np.ones((3, 4))
    assert s.storage(W, E_inf).shape == (3, 4) and s.relaxation(W, E_inf).shape == (3, 4)
    assert isinstance(s.loss(1.0, E_inf), float)
    assert isinstance(s.complex_modulus(1.0, E_inf), complex)


def test_prony_sorted_and_helpers() -> None:
    s = PronySeries(np.array([0.1, 0.0, 0.3]), np.array([1.0, 1e-2, 1e-4]))
    np.testing.assert_array_equal(s.tau, [1e-4, 1e-2, 1.0])
    np.testing.assert_array_equal(s.gamma, [0.3, 0.0, 0.1])
    assert len(s.pruned()) == 2 and s.pruned().gamma_inf == pytest.approx(s.gamma_inf)
    np.testing.assert_allclose(s.shifted(10.0).tau, [1e-3, 1e-1, 10.0])
    assert s == PronySeries([0.1, 0.0, 0.3], [1.0, 1e-2, 1e-4])
    with pytest.raises(ValueError):
        s.gamma[0] = 0.5  # read-only


@pytest.mark.parametrize("gamma, tau, match", [
    ([0.5, 0.5], [1.0, 2.0], "sum"),
    ([0.6, 0.6], [1.0, 2.0], "sum"),
    ([-0.1, 0.5], [1.0, 2.0], r"gamma\[0\]"),
    ([0.1, 0.5], [0.0, 2.0], r"tau\[0\]"),
    ([0.1, 0.5], [1.0, -2.0], r"tau\[1\]"),
    ([0.1, math.nan], [1.0, 2.0], r"gamma\[1\]"),
    ([0.1, 0.2], [1.0, math.inf], r"tau\[1\]"),
    ([0.1, 0.2], [1.0], "PronySeries.gamma"),
    ([0.1, 0.2], [1.0, 1.0], "PronySeries.tau"),
    ([[0.1], [0.2]], [[1.0], [2.0]], "PronySeries.gamma"),
])
def test_prony_bad_input(gamma, tau, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        PronySeries(gamma, tau)


def test_prony_bad_arguments() -> None:
    s = PronySeries([0.5], [1.0])
    calls = ((lambda: s.storage(1.0, 0.0), "E_inf"), (lambda: s.storage(-1.0, 1.0), "omega"),
             (lambda: s.relaxation(-1.0, 1.0), r"\.t"), (lambda: s.E0(math.nan), "E_inf"),
             (lambda: PronySeries.from_moduli(1.0, [-1.0], [1.0]), "E_k"))
    for call, field in calls:
        with pytest.raises(ValueError, match=field):
            call()


def test_published_pyvisco_relaxation(shared_data: Path) -> None:
    """The published pyvisco Prony series (E0 = 1739.03 MPa) reproduces its relaxation master curve.

    Tolerance 5 % max / 1 % rms: the accuracy of that published fit; a wrong E(t) formula (e.g.
    missing gamma_inf, tau used as a rate) is off by orders of magnitude.
    """
    terms = shared_data / "pyvisco_prony_terms_KPf_MD.csv"
    gamma, tau = np.loadtxt(terms, delimiter=",", comments="#").T
    s = PronySeries(gamma, tau)
    E_inf = 1739.03 * s.gamma_inf
    assert s.E0(E_inf) == pytest.approx(1739.03, rel=1e-12)
    t, E = np.loadtxt(shared_data / "pyvisco_time_user_master.csv", delimiter=",", skiprows=2).T
    rel = s.relaxation(t, E_inf) / E - 1
    assert np.abs(rel).max() < 0.05 and np.sqrt(np.mean(rel**2)) < 0.01


# ------------------------------------------------------------------------------------------
# thermal, road, compound objects
# ------------------------------------------------------------------------------------------


def test_thermal() -> None:
    th = Thermal(rho=1.208e-9, c=1.67e9, k=0.2553)
    assert th.diffusivity == pytest.approx(0.2553 / (1.208e-9 * 1.67e9), rel=1e-14)
    # 1.67e9 mJ/(t K) = 1670 J/(kg K); 0.2553 mW/(mm K) = 0.2553 W/(m K): alpha = 1.2655e-7 m^2/s
    assert th.diffusivity * 1e-6 == pytest.approx(0.2553 / (1208.0 * 1670.0), rel=1e-12)
    for kwargs, field in ((dict(rho=0.0, c=1.0, k=1.0), "rho"), (dict(rho=1.0, c=-1.0, k=1.0), "c"),
                          (dict(rho=1.0, c=1.0, k=math.nan), "k")):
        with pytest.raises(ValueError, match=f"Thermal.{field}"):
            Thermal(**kwargs)


def test_road_r1() -> None:
    r1 = load_road("r1")
    assert (r1.E, r1.nu) == (40000.0, 0.15)
    assert (r1.thermal.rho, r1.thermal.c, r1.thermal.k) == (2.19e-9, 0.92e9, 0.7)
    assert r1.mu == pytest.approx(40000 / 2.3) and r1.K == pytest.approx(40000 / (3 * 0.7))
    for kwargs, field in ((dict(E=-1.0, nu=0.2), "Road.E"), (dict(E=1.0, nu=0.5), "Road.nu"),
                          (dict(E=1.0, nu=math.nan), "Road.nu")):
        with pytest.raises(ValueError, match=field):
            Road(name="x", thermal=None, **kwargs)


def _compound(**kw) -> Compound:
    base = dict(name="x", hyperelastic=MooneyRivlin(0.174, 0.3, 0.0208),
                prony=PronySeries([0.5, 0.3], [1e-6, 1e-3]),
                wlf=WLF.from_celsius(7.95, 109.32, 20.0),
                thermal=None, description="", source="test")
    base.update(kw)
    return Compound(**base)


def test_compound_wlf_shift() -> None:
    c = _compound()
    w = np.logspace(-2, 8, 11)
    # at 0 degC omega is equivalent to omega * a(0 degC) at 20 degC, a = 10^1.7801164353
    np.testing.assert_allclose(c.complex_modulus(w, T=0.0 + C),
                               c.prony.complex_modulus(w * 10**1.7801164353, c.E_inf), rtol=1e-8)
    np.testing.assert_allclose(c.complex_modulus(w), c.complex_modulus(w, T=20.0 + C), rtol=1e-14)
    # colder is stiffer at a given frequency
    assert c.complex_modulus(10.0, T=0.0 + C).real > c.complex_modulus(10.0, T=40.0 + C).real
    with pytest.raises(ValueError, match="WLF"):
        _compound(wlf=None).complex_modulus(1.0, T=300.0)
    elastic = _compound(prony=None)
    assert elastic.complex_modulus(np.array([1.0, 2.0])) == pytest.approx(np.full(2, elastic.E_inf))
    assert elastic.E0 == elastic.E_inf


def test_compound_instantaneous_poisson() -> None:
    c = _compound()
    K, E0 = 2 / 0.0208, c.E_inf / 0.2
    assert c.E0 == pytest.approx(E0)
    assert c.nu0 == pytest.approx((3 * K - E0) / (6 * K))
    G0 = 0.948 / 0.2
    assert c.nu0_fe == pytest.approx((3 * K - 2 * G0) / (2 * (3 * K + G0)))
    assert c.E0_fe == pytest.approx(2 * G0 * (1 + c.nu0_fe))
    assert "WARNING" not in c.summary()  # E0 = 14 MPa < 3K: positive nu0
    d = load_compound("A")  # the thesis' D1 (K = 69 MPa) under the default glassy spectrum
    assert d.nu0 < -1 and "WARNING" in d.summary() and f"{d.nu0:.4f}" in d.summary()
    # the default compound's K = 2 GPa: a physical instantaneous response (0 < nu0 < 0.5)
    t = load_compound("tread_default")
    assert 0.4 < t.nu0 < 0.5 and 0.4 < t.nu0_fe < 0.5 and "WARNING" not in t.summary()


@pytest.mark.parametrize("field, value", [("name", ""), ("hyperelastic", None), ("prony", "x"),
                                          ("wlf", 1.0), ("thermal", 2.0), ("source", None)])
def test_compound_bad_input(field: str, value) -> None:
    with pytest.raises(ValueError, match=f"Compound.{field}"):
        _compound(**{field: value})


# ------------------------------------------------------------------------------------------
# data files
# ------------------------------------------------------------------------------------------


def test_all_files_load_and_match_tables() -> None:
    names = material_files.available()
    assert set(TABLES) | {"r1"} <= set(names)
    for name in names:
        path = material_files.DATA_DIR / f"{name}.toml"
        kind = tomllib.loads(path.read_text())["kind"]
        obj = load_compound(name) if kind == "compound" else load_road(name)
        assert obj.name == name and obj.source
    for name, (C10, C01, D1) in TABLES.items():
        c = load_compound(name)
        mr = c.hyperelastic
        assert (mr.C10, mr.C01, mr.D1, mr.form) == (C10, C01, D1, "split")
        assert mr.mu == pytest.approx(2 * (C10 + C01), rel=1e-14)
        assert mr.K == pytest.approx(2 / D1, rel=1e-14)
        assert c.prony is not None
        if name not in DERIVED | PLACED:  # c1..c6: test_derived_compounds.py
            assert c.prony == load_compound("tread_default").prony
        else:  # m1, m2: test_tau_factor_moves_the_referenced_spectrum
            assert c.prony != load_compound("tread_default").prony


DERIVED = {"c1", "c2", "c3", "c4", "c5", "c6"}
PLACED = {"m1", "m2"}  # tread_default's spectrum moved along the frequency axis (tau_factor)


def test_thermal_and_wlf_tables() -> None:
    for name, cap, has_wlf in (("m1", 1.67e9, True), ("m2", 1.4e9, True), ("m3", 1.4e9, False)):
        c = load_compound(name)
        assert (c.thermal.rho, c.thermal.c, c.thermal.k) == (1.208e-9, cap, 0.2553)
        if has_wlf:
            assert (c.wlf.c1, c.wlf.c2) == (7.95, 109.32)
            assert c.wlf.T_ref == pytest.approx(293.15, abs=1e-12)
        else:
            assert c.wlf is None
    assert load_compound("A").wlf == load_compound("m1").wlf  # c1..c6: derived (test_derived_*)
    assert "WLF: same as" in load_compound("A").source


def test_default_compound_regenerates() -> None:
    """The stored default spectrum is exactly what its [prony.generator] table produces."""
    regenerated = tomllib.loads(spectrum.regenerate_prony_toml())
    stored = load_compound("tread_default").prony
    np.testing.assert_allclose(regenerated["gamma"], stored.gamma, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(regenerated["tau"], stored.tau, rtol=1e-12)


def test_default_compound_physics() -> None:
    d = load_compound("tread_default")
    gen, _ = spectrum.spectrum_generator()
    # Tg = -25 degC at 10 Hz: log10 a = 7.95*45/(109.32-45) = 357.75/64.32 = 5.5620335821
    f_peak = 10.0 * 10**5.5620335821
    assert gen.peak_frequency_Hz(d.wlf) == pytest.approx(f_peak, rel=1e-9)
    f = np.logspace(3, 9, 60001)
    target = gen.target(2 * np.pi * f, d.E_inf, d.wlf)
    assert f[np.argmax(target.imag)] == pytest.approx(f_peak, rel=1e-3)
    # one term per decade: the Prony E'' maximum lies within half a decade of the target peak
    assert abs(math.log10(loss_peak_omega(d.prony, d.E_inf) / (2 * np.pi) / f_peak)) < 0.5
    assert 500.0 < d.E0 < 2000.0              # glassy plateau of order 1 GPa
    assert d.E_inf == pytest.approx(MooneyRivlin(0.174, 0.300, 0.001).E)
    assert len(d.prony) == 13
    assert (d.prony.tau[0], d.prony.tau[-1]) == pytest.approx((1e-10, 1e2))
    # rubbery at low frequency, glassy at high frequency
    assert d.complex_modulus(1e-6).real == pytest.approx(d.E_inf, rel=1e-3)
    assert d.complex_modulus(1e14).real == pytest.approx(d.E0, rel=1e-3)


# ------------------------------------------------------------------------------------------
# file format errors and options
# ------------------------------------------------------------------------------------------

UNITS = """[units]
length = "mm"
time = "s"
mass = "t"
force = "N"
stress = "MPa"
energy = "mJ"
temperature = "{T}"
"""
HYPER = """[hyperelastic]
model = "mooney_rivlin"
C10 = 0.174
C01 = 0.300
D1 = 0.0208
"""


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _head(name: str = "t") -> str:
    return f'kind = "compound"\nname = "{name}"\nsource = "test"\n'


def test_units_required(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"missing \[units\]"):
        load_compound(_write(tmp_path, "a", _head() + HYPER))
    with pytest.raises(ValueError, match="missing key.*energy"):
        units = UNITS.format(T="K").replace('energy = "mJ"\n', "")
        load_compound(_write(tmp_path, "b", _head() + units + HYPER))
    with pytest.raises(ValueError, match="stress"):
        units = UNITS.format(T="K").replace('"MPa"', '"Pa"')
        load_compound(_write(tmp_path, "c", _head() + units + HYPER))
    with pytest.raises(ValueError, match="temperature"):
        load_compound(_write(tmp_path, "d", _head() + UNITS.format(T="F") + HYPER))
    thermal = "[thermal]\nrho = 1e-9\nc = 1e9\nk = 0.2\n"
    with pytest.raises(ValueError, match="density"):
        load_compound(_write(tmp_path, "e", _head() + UNITS.format(T="K") + HYPER + thermal))


def test_celsius_and_kelvin_files_agree(tmp_path: Path) -> None:
    wlf_C = "[wlf]\nc1 = 7.95\nc2 = 109.32\nT_ref = 20.0\n"
    wlf_K = "[wlf]\nc1 = 7.95\nc2 = 109.32\nT_ref = 293.15\n"
    a = load_compound(_write(tmp_path, "a", _head() + UNITS.format(T="degC") + HYPER + wlf_C))
    b = load_compound(_write(tmp_path, "b", _head() + UNITS.format(T="K") + HYPER + wlf_K))
    assert a.wlf.T_ref == pytest.approx(b.wlf.T_ref, abs=1e-12)


@pytest.mark.parametrize("extra, match", [
    ("[prony]\ngamma = [0.5]\ntau = [1.0]\nsame_as = \"tread_default\"\n", "exactly one"),
    ("[prony]\ngamma = [0.5]\n", "missing key"),
    ("[prony]\ngamma = [0.7, 0.4]\ntau = [1.0, 2.0]\n", "sum"),
    ("[prony]\ngama = [0.5]\ntau = [1.0]\n", "unknown key"),
    ("[wlf]\nc1 = 7.95\nc2 = 109.32\n", "T_ref"),
    ("[wlf]\nsame_as = \"m3\"\n", "no WLF"),
])
def test_file_errors(tmp_path: Path, extra: str, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        load_compound(_write(tmp_path, "x", _head() + UNITS.format(T="degC") + HYPER + extra))


def test_file_errors_misc(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="not found"):
        load_compound("no_such_compound")
    with pytest.raises(ValueError, match="kind"):
        load_compound("r1")
    with pytest.raises(ValueError, match="kind"):
        load_road("m1")
    ref = '[prony]\nsame_as = "{}"\n'
    _write(tmp_path, "p", _head("p") + UNITS.format(T="K") + HYPER + ref.format("q"))
    _write(tmp_path, "q", _head("q") + UNITS.format(T="K") + HYPER + ref.format("p"))
    with pytest.raises(ValueError, match="circular"):
        load_compound(tmp_path / "p.toml")


def test_tau_factor_moves_the_referenced_spectrum(tmp_path: Path) -> None:
    """``same_as`` with ``tau_factor = f``: the referenced gamma_k and f tau_k, so E*(omega) is
    the reference's at omega f (exact, 1e-12); m1 is tread_default's spectrum with its loss peak
    moved from 5.75e4 to 2.95e6 rad/s (tau_factor = a_T(T_ref + 30 K), 1e-9), m2 is m1's."""
    ref = load_compound("tread_default").prony
    text = '[prony]\nsame_as = "tread_default"\ntau_factor = 0.01\n'
    c = load_compound(_write(tmp_path, "f", _head() + UNITS.format(T="degC") + HYPER + text))
    np.testing.assert_array_equal(c.prony.gamma, ref.gamma)
    np.testing.assert_allclose(c.prony.tau, 0.01 * ref.tau, rtol=1e-12)
    w, E_inf = np.logspace(0, 8, 9), 2.0
    np.testing.assert_allclose(c.prony.complex_modulus(w, E_inf),
                               ref.complex_modulus(0.01 * w, E_inf), rtol=1e-12)
    m1, base = load_compound("m1"), load_compound("tread_default")
    np.testing.assert_allclose(m1.prony.tau, base.prony.tau * base.wlf.aT(base.wlf.T_ref + 30.0),
                               rtol=1e-9)
    np.testing.assert_array_equal(load_compound("m2").prony.tau, m1.prony.tau)
    bad = '[prony]\nsame_as = "tread_default"\ntau_factor = -1.0\n'
    with pytest.raises(ValueError, match="tau_factor"):
        load_compound(_write(tmp_path, "g", _head() + UNITS.format(T="degC") + HYPER + bad))


def _write_dma(path: Path, w: np.ndarray, E: np.ndarray, unit: str = "rad/s") -> None:
    rows = "".join(f"{a!r},{b.real!r},{b.imag!r}\n" for a, b in zip(w, E))
    path.write_text(f"omega,E_stor,E_loss\n{unit},MPa,MPa\n" + rows)


def test_fit_from_dma_file(tmp_path: Path) -> None:
    """``fit_from`` recovers a known series and shifts it from the data temperature to T_ref."""
    mr = MooneyRivlin(0.174, 0.300, 0.0208)
    true = PronySeries([0.3, 0.25, 0.2, 0.15], [1e-4, 1e-2, 1e-1, 1e1])
    w = np.logspace(-2, 5, 71)
    _write_dma(tmp_path / "dma.csv", w, true.complex_modulus(w, mr.E))
    prony = ('[prony]\nfit_from = "dma.csv"\nfreq_unit = "rad/s"\n'
             'columns = ["omega", "E_stor", "E_loss"]\nT = {T}\nE_inf = "hyperelastic"\n')
    head = _head() + UNITS.format(T="degC") + HYPER
    wlf = "[wlf]\nc1 = 7.95\nc2 = 109.32\nT_ref = 20.0\n"
    c = load_compound(_write(tmp_path, "a", head + prony.format(T=20.0) + wlf))
    np.testing.assert_allclose(c.complex_modulus(w), true.complex_modulus(w, mr.E), rtol=1e-6)
    assert "fitted from dma.csv" in c.source
    # the same curve measured at 40 degC: at 20 degC the times are longer by 1/a(40 degC)
    c40 = load_compound(_write(tmp_path, "b", head + prony.format(T=40.0) + wlf))
    np.testing.assert_allclose(c40.prony.tau, c.prony.tau * 10**1.2295081967, rtol=1e-8)
    np.testing.assert_allclose(c40.complex_modulus(w, T=40.0 + C), true.complex_modulus(w, mr.E),
                               rtol=1e-6)


# ------------------------------------------------------------------------------------------
# command line (driver/cli/material.py), on its own parser
# ------------------------------------------------------------------------------------------


def _cli(argv: list[str]) -> int:
    import argparse

    from rubberfriction.driver.cli import material as cli_material

    parser = argparse.ArgumentParser(prog="rubberfriction")
    cli_material.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(argv)
    return int(args.func(args) or 0)


def test_cli_show(capsys) -> None:
    assert _cli(["material", "show", "tread_default"]) == 0
    out = capsys.readouterr().out
    assert "E0 = E_inf/gamma_inf" in out and "tan delta" in out and "log10 aT" in out
    d = load_compound("tread_default")
    E10 = d.complex_modulus(2 * np.pi * 10.0)
    assert f"{E10.real:.5g}" in out and f"{E10.imag / E10.real:.4f}" in out
    assert _cli(["material", "show", "r1"]) == 0 and "40000 MPa" in capsys.readouterr().out
    assert _cli(["material", "show", "no_such_material"]) == 2  # bad input: exit status 2


def test_cli_fit_writes_loadable_compound(tmp_path: Path) -> None:
    """``material fit`` with the base E_inf fixed reproduces a known series; --T-ref-C (alias
    --T-C) at base's T_ref leaves tau, at 40 degC shifts it by 1/a(T) (eq. 3.37)."""
    base = load_compound("tread_default")
    true = PronySeries([0.4, 0.3, 0.2], [1e-5, 1e-3, 1e-1])
    f = np.logspace(-1, 4, 51)
    E = true.complex_modulus(2 * np.pi * f, base.E_inf)
    csv = tmp_path / "dma.csv"
    csv.write_text("f,E_stor,E_loss\nHz,MPa,MPa\n" + "".join(f"{a!r},{b.real!r},{b.imag!r}\n"
                                                             for a, b in zip(f, E)))
    out, png = tmp_path / "fit.toml", tmp_path / "fit.png"
    assert _cli(["material", "fit", str(csv), "--fix-E-inf", "--T-ref-C", "20", "--toml",
                 str(out), "--plot", str(png)]) == 0
    assert "# master curve reference temperature 20 degC (--T-ref-C)" in out.read_text()
    c = load_compound(out)
    assert c.hyperelastic == base.hyperelastic and c.wlf == base.wlf and c.thermal == base.thermal
    np.testing.assert_allclose(c.complex_modulus(2 * np.pi * f), E, rtol=1e-6)
    assert png.stat().st_size > 0
    out40 = tmp_path / "fit40.toml"
    assert _cli(["material", "fit", str(csv), "--fix-E-inf", "--T-C", "40",
                 "--toml", str(out40)]) == 0
    np.testing.assert_allclose(load_compound(out40).prony.tau, c.prony.tau * 10**1.2295081967,
                               rtol=1e-8)


def test_cli_fit_needs_the_reference_temperature(tmp_path: Path, capsys,
                                                 shared_data: Path) -> None:
    """No --T-ref-C and no --shift-factors: refused (no silent 20 degC), nothing written."""
    csv = shared_data / "pyvisco_freq_master.csv"
    out = tmp_path / "x.toml"
    assert _cli(["material", "fit", str(csv), "--toml", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--T-ref-C" in err and "--shift-factors" in err and not out.exists()


def test_cli_fit_with_shift_factors(tmp_path: Path, capsys, shared_data: Path) -> None:
    """pyvisco's curve with its shift-factor table: reference -5 degC, the compound's WLF is the
    least-squares fit to the table at T_ref = -5 degC (tau not shifted), all stated."""
    from rubberfriction.forms import prony as P

    out = tmp_path / "pv.toml"
    assert _cli(["material", "fit", str(shared_data / "pyvisco_freq_master.csv"),
                 "--shift-factors", str(shared_data / "pyvisco_freq_master_shift_factors.csv"),
                 "--toml", str(out)]) == 0
    text = capsys.readouterr().out
    assert "reference temperature of the master curve: -5 degC (--shift-factors" in text
    wfit = P.fit_wlf(*P.read_shift_factors(shared_data / "pyvisco_freq_master_shift_factors.csv"))
    assert wfit.report() in text
    c = load_compound(out)
    assert c.wlf == wfit.wlf and c.wlf.T_ref == pytest.approx(268.15, abs=1e-12)
    omega, E1, E2 = P.read_dma_csv(shared_data / "pyvisco_freq_master.csv")
    fit = P.fit_prony(omega, E1, E2)
    np.testing.assert_array_equal(c.prony.tau, fit.series.pruned().tau)  # not shifted
    toml = out.read_text()
    assert "# master curve reference temperature -5 degC" in toml and "tau not shifted" in toml
    for line in P.plausibility_warnings(fit.series, c.E_inf, (omega.min(), omega.max()),
                                        K=c.hyperelastic.K):
        assert f"warning: {line}" in text and f"# warning: {line}" in toml


@pytest.mark.parametrize("kind, name", [("time", "pyvisco_time_user_master.csv"),
                                        ("prony", "pyvisco_prony_terms_KPf_MD.csv")])
def test_cli_fit_time_and_prony(tmp_path: Path, capsys, shared_data: Path, kind: str,
                                name: str) -> None:
    """E(t) curves and published terms make compounds too; at base's T_ref nothing shifts, so
    the compound's gamma, tau are the fit's (time) or the file's (prony)."""
    from rubberfriction.forms import prony as P

    out = tmp_path / "c.toml"
    assert _cli(["material", "fit", str(shared_data / name), "--kind", kind, "--T-ref-C", "20",
                 "--toml", str(out)]) == 0
    assert "reference temperature of the master curve: 20 degC (--T-ref-C)" in \
        capsys.readouterr().out
    got = (P.fit_prony_time(*P.read_relaxation_csv(shared_data / name)) if kind == "time"
           else P.read_prony_csv(shared_data / name)).series.pruned()
    c = load_compound(out)
    np.testing.assert_allclose(c.prony.tau, got.tau, rtol=1e-15)
    np.testing.assert_allclose(c.prony.gamma, got.gamma, rtol=1e-15)
    assert c.wlf == load_compound("tread_default").wlf
