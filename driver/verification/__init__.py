"""Registry of the analytical verification cases (``rubberfriction verify CASE``).

name -> (module, one-line description).  A module provides ``add_arguments(parser)`` and
``run(args) -> dict`` (see ``driver/cli/verify.py`` for the result layout) and plain functions
with keyword parameters that the tests call directly.
"""

CASES: dict[str, tuple[str, str]] = {
    "hertz": ("rubberfriction.driver.verification.contact_cases", "plane-strain cylinder on a rigid flat (Hertz)"),
    "westergaard": ("rubberfriction.driver.verification.contact_cases",
                    "elastic block on a rigid periodic sinusoid (Westergaard)"),
    "patch": ("rubberfriction.driver.verification.contact_cases", "contact patch test on non-matching meshes"),
    "sliding-block": ("rubberfriction.driver.verification.contact_cases",
                      "Coulomb sliding block, Fx/Fz = mu (constant mu and a mu(p, v) law)"),
    "thermal-bars": ("rubberfriction.driver.verification.contact_cases",
                     "thermal contact: two bars through a conductance, frictional heat split kappa"),
    "periodic-sliding": ("rubberfriction.driver.verification.contact_cases",
                         "elastic layer sliding over 3 periods of a wrapped periodic sinusoid"),
    "viscoelastic-sinusoid": ("rubberfriction.driver.verification.viscoelastic_sinusoid",
                              "viscoelastic block sliding over a sinusoid in full contact"),
    "sawtooth": ("rubberfriction.driver.verification.sawtooth", "sawtooth anisotropy, sharp vs smooth"),
    "relaxation": ("rubberfriction.driver.verification.relaxation",
                   "bulk stress relaxation and harmonic shear vs the Prony closed form"),
}


def check(quantity: str, computed: float, analytical: float, tolerance: float | None = None) -> dict:
    """One computed-vs-analytical line of a verification result."""
    rel = abs(computed - analytical) / abs(analytical) if analytical != 0 else abs(computed)
    out = {"quantity": quantity, "computed": float(computed), "analytical": float(analytical),
           "rel_error": float(rel), "tolerance": tolerance}
    if tolerance is not None:
        out["passed"] = bool(rel <= tolerance)
    return out
