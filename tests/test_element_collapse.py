"""Collapsed elements are refused like inverted ones (SlidingSpec.min_jacobian, issue 14).

A Q1P0 element constrains only its mean dilatation, so contact forces on a peak sharper than the
element can squeeze it to zero area at every quadrature point while the solve still converges
(measured on the default scene's micro2 run at 29 MPa: det F 1e-14).  Its second Piola-Kirchhoff
history then grows like 1 / det F^2 (6e13 MPa there) and the next sub-step of another length
starts at residuals of 1e12.  A state with det F <= min_jacobian at a quadrature point is
therefore not accepted.  The default limit 1e-3 lies below what runs that converge with a
consistent mu reach (0.0036 and 0.0095 on the default scene's micro1 and micro2 runs) and above
what the collapsed one did (1e-5 .. 1e-14).

* det F of a homogeneous vertical squeeze F = diag(1, s) is s at every quadrature point: the check
  reads s exactly and names the cause (collapse against the limit, inversion at s <= 0).
* min_jacobian = 0 keeps the former rule (inversion only).
* An accepted run reports the smallest det F of its accepted states (``min_det_F``, a stored
  result scalar and a samples.csv column), above the limit.
* Bad limits are refused naming the field.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rubberfriction.driver.runtime.store import Store
from rubberfriction.driver.sliding.model import SlidingModel
from rubberfriction.driver.sliding.run import SlidingRun, block_mesh, sliding_contact
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.forms.material_files import load_compound


def sinusoid_spec(**kw) -> SlidingSpec:
    """The full-contact viscoelastic sinusoid of ``verify viscoelastic-sinusoid`` (1 mm, 2 um,
    0.1 MPa, 10 mm/s, 16 elements per wavelength)."""
    x = np.linspace(0.0, 1.0, 129)[:-1]
    return SlidingSpec(surface_x=x, surface_h=0.002 * np.cos(2.0 * np.pi * x), period=1.0,
                       pressure=0.1, velocity=10.0, compound=load_compound("tread_default"),
                       h_contact=1.0 / 16, slide_distance=0.25, step_length=0.5 / 16, **kw)


def squeezed(model: SlidingModel, s: float) -> None:
    """u = (0, (s - 1) (Z - Z_0)): F = diag(1, s), det F = s everywhere."""
    X = model.sp.node_X
    d = model.sp.displacement_dofs()
    x = model.sp.w.x.array
    x[:] = 0.0
    x[d[:, 1]] = (s - 1.0) * (X[:, 1] - X[:, 1].min())


@pytest.fixture(scope="module")
def built():
    run = SlidingRun(sinusoid_spec(), block_mesh, sliding_contact)
    run.build("mortar")
    return run.model  # the element check is the model's (driver.sliding.model)


@pytest.mark.parametrize("s", [1.0, 0.5, 0.005])
def test_a_squeezed_but_whole_block_is_accepted(built, s):
    squeezed(built, s)
    assert not built.inverted()
    assert built.iterate_det_F == pytest.approx(s, rel=1e-10)


def test_a_collapsed_block_is_refused_naming_the_cause(built):
    squeezed(built, 5e-4)
    assert built.inverted()
    assert built.iterate_det_F == pytest.approx(5e-4, rel=1e-10)
    assert built.bad_element_reason() == "element collapse (det F = 0.0005 <= min_jacobian 0.001)"
    squeezed(built, -0.2)
    assert built.inverted()
    assert built.bad_element_reason() == "element inversion (det F <= 0)"


def test_limit_zero_is_the_inversion_rule():
    run = SlidingRun(sinusoid_spec(min_jacobian=0.0), block_mesh, sliding_contact)
    run.build("mortar")
    model = run.model
    squeezed(model, 1e-12)
    assert not model.inverted()
    squeezed(model, 0.0)
    assert model.inverted() and "inversion" in model.bad_element_reason()


def test_a_run_reports_its_smallest_det_F(tmp_path):
    """The sinusoid (2 um on 1 mm at 0.1 MPa) hardly deforms: det F stays within 1 % of 1; the
    value is a stored result scalar (samples.csv reads it from the store)."""
    spec = sinusoid_spec()
    res = SlidingRun(spec, block_mesh, sliding_contact).run()
    assert res.ok, res.reason
    assert 0.99 < res.min_det_F <= 1.0 + 1e-9
    outcome = Store(tmp_path).put("0" * 64, spec, res, wall_time=0.0)
    assert outcome.value("min_det_F") == res.min_det_F


@pytest.mark.parametrize("limit", [-0.1, 1.0, float("nan")])
def test_bad_limit_is_refused_naming_the_field(limit):
    with pytest.raises(ValueError, match=r"min_jacobian = .*expected 0 <= det F limit < 1"):
        SlidingRun(dataclasses.replace(sinusoid_spec(), min_jacobian=limit), block_mesh,
                   sliding_contact)
