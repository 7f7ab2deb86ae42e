"""Analytical baselines beside the FE: Persson, Klüppel-Heinrich, adhesion (thesis ch. 2.3.2, 7).

The same surface PSD and the same Prony/WLF compound the FE uses give, in well under a second
for a 50-speed curve:

* :mod:`.persson`: Persson's hysteretic friction, eq. (2.10), with the contact area P(q), the
  correction S(q) and (opt-in) the flash temperature (:mod:`.flash`), for isotropic roughness
  and for line roughness (plane strain, the fair comparison with the 2D FE);
* :mod:`.kluppel`: Klüppel-Heinrich, eq. (2.9);
* :mod:`.adhesion`: the bell law, eq. (7.6), and mu_A, eqs. (2.11)/(7.7);
* :mod:`.spectrum`: PSD -> quadrature nodes (Persson conventions); :mod:`.rubber`: the material
  as a complex-modulus callable; :mod:`.curves`: all models from one profile PSD, plots.

Units: mm, s, MPa, K; speeds in mm/s, wavenumbers q = 2 pi/lambda in 1/mm.
"""

from rubberfriction.driver.theory.adhesion import BellLaw, mu_adhesion, mu_combined
from rubberfriction.driver.theory.curves import MODELS, TheoryCurve, plot_curves, theory_curves
from rubberfriction.driver.theory.errors import TheoryInputError
from rubberfriction.driver.theory.flash import FlashOptions
from rubberfriction.driver.theory.kluppel import (
    HDCDescriptors,
    KHResult,
    descriptors_from_psd,
    kluppel_heinrich_friction,
)
from rubberfriction.driver.theory.persson import (
    AREA_CONSTANT,
    GAMMA_DEFAULT,
    PerssonOptions,
    PerssonResult,
    contact_area_elastic,
    full_contact_pressure_sinusoid,
    mu_full_contact_sinusoid,
    persson_friction,
)
from rubberfriction.driver.theory.rubber import Rubber, prony_modulus, rubber_from_compound
from rubberfriction.driver.theory.spectrum import (
    Spectrum,
    line_spectrum,
    sinusoid_spectrum,
    spectrum_from_psd,
)

__all__ = [
    "AREA_CONSTANT",
    "BellLaw",
    "FlashOptions",
    "GAMMA_DEFAULT",
    "HDCDescriptors",
    "KHResult",
    "MODELS",
    "PerssonOptions",
    "PerssonResult",
    "Rubber",
    "Spectrum",
    "TheoryCurve",
    "TheoryInputError",
    "contact_area_elastic",
    "descriptors_from_psd",
    "full_contact_pressure_sinusoid",
    "kluppel_heinrich_friction",
    "line_spectrum",
    "mu_adhesion",
    "mu_combined",
    "mu_full_contact_sinusoid",
    "persson_friction",
    "plot_curves",
    "prony_modulus",
    "rubber_from_compound",
    "sinusoid_spectrum",
    "spectrum_from_psd",
    "theory_curves",
]
