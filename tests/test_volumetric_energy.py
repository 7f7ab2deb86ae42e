"""The two volumetric energies of the split Mooney-Rivlin spring (``forms/hyperelastic.py``).

Psi_vol = K/2 g(J)^2 with K = 2/D1 and g = J - 1 (thesis eq. 3.78, "quadratic") or g = ln J
("logarithmic").  The quadratic energy's hydrostatic pressure -K (J - 1) never exceeds K: a
cell whose rubber is pressed harder than K (the cascade's lowest scales reach 30-80 MPa against
K = 96 MPa of the thesis' D1) has no volumetric resistance left and collapses.  The logarithmic
one, -K ln(J) / J, grows without bound.

* Large homogeneous compression F = diag(lam, lam, 1), J = lam^2 down to 0.25: the FE Cauchy
  stress of every element equals the closed form of its energy (``fe_helpers.mooney_rivlin_cauchy``)
  within 1e-8 (homogeneous states are exact on bilinear elements).
* At J = 0.25 the FE mean stress (the isochoric part is a deviator) is -0.75 K with the
  quadratic energy, bounded by K, and -4 ln(4) K = -5.5 K with the logarithmic one.
* Small strain: both give K within 1e-4 at J - 1 = -2e-5.
* Material files take ``volumetric``; a bad value or a feap form with it is refused naming it.
"""

from __future__ import annotations

import numpy as np
import pytest

from fe_helpers import cauchy_at_points, mooney_rivlin_cauchy, n_full, solve, unit_square
from rubberfriction.driver.fe.constraints import ConstraintSpec
from rubberfriction.driver.fe.solid import SolidProblem, SolidSettings
from rubberfriction.forms.compound import Compound, MooneyRivlin
from rubberfriction.forms.material_files import load_compound, resolve_data_path

C10, C01, D1 = 0.174, 0.300, 0.0208  # compound m1, table C.2
K = 2.0 / D1


def rubber(volumetric: str) -> Compound:
    spring = MooneyRivlin(C10, C01, D1, volumetric=volumetric)
    return Compound(name="m1-elastic", hyperelastic=spring, prony=None, wlf=None, thermal=None,
                    description="test", source="table C.2")


def compressed(element: str, volumetric: str, lams) -> np.ndarray:
    """Cauchy stress at the quadrature points after prescribing u = (lam - 1) X for each lam."""
    m, ft = unit_square(2)
    sp = SolidProblem(m, ft, rubber(volumetric), SolidSettings(element=element))
    spec = ConstraintSpec(n_full(sp))
    X, d = sp.node_X, sp.displacement_dofs()
    for lam in lams:  # load steps
        for i in range(sp.n_nodes):
            spec.fix(int(d[i, 0]), (lam - 1.0) * X[i, 0])
            spec.fix(int(d[i, 1]), (lam - 1.0) * X[i, 1])
        solve(sp, spec)
    return cauchy_at_points(sp)


@pytest.mark.parametrize("volumetric", ["quadratic", "logarithmic"])
@pytest.mark.parametrize("element", ["Q1P0", "Q1P0s", "Q1"])
def test_large_compression_matches_the_closed_form(element, volumetric):
    lams = np.linspace(0.95, 0.5, 10)
    sig = compressed(element, volumetric, lams)
    exact = mooney_rivlin_cauchy(np.diag([0.5, 0.5, 1.0]), C10, C01, D1, volumetric)
    assert np.allclose(sig, exact, rtol=1e-8, atol=1e-10 * K), (sig[0], exact)
    # the isochoric stress is a deviator: the mean stress is the volumetric one, -K (J - 1) =
    # 0.75 K (bounded by K) or -K ln(J) / J = 4 ln(4) K = 5.5 K
    mean = np.trace(sig, axis1=1, axis2=2) / 3.0
    expected = {"quadratic": -0.75 * K, "logarithmic": -4.0 * np.log(4.0) * K}[volumetric]
    assert np.allclose(mean, expected, rtol=1e-8)


@pytest.mark.parametrize("volumetric", ["quadratic", "logarithmic"])
def test_same_small_strain_bulk_modulus(volumetric):
    lam = 1.0 - 1e-5
    sig = compressed("Q1P0", volumetric, [lam])
    K_fe = np.trace(sig, axis1=1, axis2=2) / 3.0 / (lam**2 - 1.0)
    assert np.allclose(K_fe, K, rtol=1e-4)


def test_material_files_take_the_volumetric_energy(tmp_path):
    text = resolve_data_path("m1").read_text()
    good = tmp_path / "m1_log.toml"
    good.write_text(text.replace('model = "mooney_rivlin"',
                                 'model = "mooney_rivlin"\nvolumetric = "logarithmic"'))
    assert load_compound(good).hyperelastic.volumetric == "logarithmic"
    assert load_compound("m1").hyperelastic.volumetric == "quadratic"
    bad = tmp_path / "m1_bad.toml"
    bad.write_text(text.replace('model = "mooney_rivlin"',
                                'model = "mooney_rivlin"\nvolumetric = "cubic"'))
    with pytest.raises(ValueError, match=r"\[hyperelastic\].*volumetric = 'cubic'"):
        load_compound(bad)
    with pytest.raises(ValueError, match="volumetric applies to the split form"):
        MooneyRivlin(C10, C01, D1, form="feap", volumetric="logarithmic")
