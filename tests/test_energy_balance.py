"""Energy balance of sliding runs (thesis eq. 2.8): in a periodic steady state the work of the
friction force is the energy the run dissipates, mu_energy = mu_force.

The oracle is the conservation of energy itself: over whole periods of a steady state the stored
energy returns, so the friction work F_x ds equals the viscous (+ frictional) dissipation up to
the O(dt^2) of the time integration.  At finite strain this needs the model's own dissipation
(``forms.viscoelastic``: branch stress work minus the change of the stored branch energy); the
small-strain density |H|^2 / (2 G tau) gave +3.3 % on the case below and +31 % at twice its
amplitude (partial contact, 23 % of the face).
"""

from __future__ import annotations

import math

import numpy as np

from rubberfriction.driver.multiscale.report import balance_parts, energy_balance
from rubberfriction.driver.runtime.store import Outcome
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.spec import SlidingSpec
from rubberfriction.driver.verification.viscoelastic_sinusoid import simulate
from rubberfriction.forms.material_files import load_compound


def test_steep_sinusoid_in_partial_contact_balances_its_friction_work():
    """Sinusoid of amplitude 0.05 mm on a 1 mm wavelength (slope amplitude 0.31), 0.5 MPa,
    10 mm/s, tread compound, periodic steady state (history jump): the contact is partial
    (fraction < 0.8) and no sub-step is stabilised; mu_energy within 2 % of mu_force."""
    out = simulate(load_compound("tread_default"), amplitude=0.05, pressure=0.5, velocity=10.0,
                   periods=6.0, steady_state=True)
    res = out["result"]
    assert res.status == "ok", res.reason
    assert res.contact_fraction < 0.8 and res.stabilisation_share == 0.0
    assert abs(res.mu_energy / res.mu_force - 1.0) < 0.02, (res.mu_force, res.mu_energy)


def _frictional_sinusoid(step_fraction: float, friction: float | None, elements: int = 16):
    """The steep sinusoid above with Coulomb friction mu = ``friction`` at the contact (the
    upper scales' friction runs), ``elements`` per wavelength, 6 periods with the jump."""
    x = np.linspace(0.0, 1.0, 129)[:-1]
    hc = 1.0 / elements
    spec = SlidingSpec(surface_x=x, surface_h=0.05 * np.cos(2.0 * np.pi * x), period=1.0,
                       pressure=0.5, velocity=10.0, compound=load_compound("tread_default"),
                       h_contact=hc, slide_distance=6.0, step_length=step_fraction * hc,
                       steady_state=True, friction=friction)
    res = run_sliding(spec)
    assert res.status == "ok", res.reason
    assert res.stabilisation_share == 0.0
    return res


def test_the_balance_splits_into_contact_and_rubber():
    """Where the friction work goes (docs/notes-energy.md, "Where the balance goes"): the road's
    work = viscous + frictional dissipation + what the contact takes up (``mu_interface``,
    ``StepControl._book_contact_work``) + what the rubber stores over the window.  In a periodic
    steady state the rubber stores nothing: mu_force - mu_energy - mu_interface within 0.5 % of
    mu_force with friction (0.5), 0.1 % without.  With the friction booked by the trapezoidal
    rule the friction runs balance: |mu_energy / mu_force - 1| < 0.5 % at steps of a half and
    a quarter element (the contact law's end-of-step booking gave -1.4 % and -0.8 %, first order
    in the step), while mu_force moves by less than 0.3 % between them; on a mesh half as fine
    within 1 % (-2.6 % with the law's booking, -3.3 % with the trapezoid for the slipping nodes
    alone: a node that leaves contact within a step is open at its end and books its half step
    at its last traction)."""
    coarse, fine = (_frictional_sinusoid(f, 0.5) for f in (0.5, 0.25))
    for res in (coarse, fine):
        rubber = (res.mu_force - res.mu_energy - res.mu_interface) / res.mu_force
        assert abs(rubber) < 0.005, (res.mu_force, res.mu_energy, res.mu_interface)
        assert abs(res.mu_energy / res.mu_force - 1.0) < 0.005, (res.mu_force, res.mu_energy)
    assert abs(fine.mu_force / coarse.mu_force - 1.0) < 0.003, (coarse.mu_force, fine.mu_force)
    rough = _frictional_sinusoid(0.5, 0.5, elements=8)
    assert abs(rough.mu_energy / rough.mu_force - 1.0) < 0.01, (rough.mu_force, rough.mu_energy)
    plain = _frictional_sinusoid(0.5, None)
    rubber = (plain.mu_force - plain.mu_energy - plain.mu_interface) / plain.mu_force
    assert abs(rubber) < 0.001, (plain.mu_force, plain.mu_energy, plain.mu_interface)


def test_the_report_splits_a_stored_balance():
    """``report.balance_parts`` reads the stored scalars: contact = mu_interface / mu_force,
    rubber = -(balance + contact), so that the two add up to minus the balance; a run stored
    before 0.29.0 (no mu_interface) has no split (NaN), not a wrong one."""
    o = Outcome("k", "ok", values={"mu_force": 0.8, "mu_energy": 0.76, "mu_interface": 0.024})
    contact, rubber = balance_parts(o)
    assert math.isclose(contact, 0.03) and math.isclose(rubber, 0.02)
    assert math.isclose(contact + rubber, -energy_balance(o))
    old = Outcome("k", "ok", values={"mu_force": 0.8, "mu_energy": 0.76})
    assert all(math.isnan(x) for x in balance_parts(old))
