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
