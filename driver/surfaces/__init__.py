"""Rough surfaces: measured profiles -> band-pass scales -> periodic samples (thesis ch. 6.3).

Pipeline (units mm; PSD in Persson's convention, see :mod:`.psd`):

    profile = load_profile("captif_chipseal_station0.dat")     # readers + defects
    q, C = psd_1d(profile)                                      # eq. (2.6), 1D
    lam, C_hdc = hdc(profile); fit = fit_hdc(lam, C_hdc)        # eqs. (2.4), (2.5)
    bands = band_split(profile, [20, 3, 0.3])                   # eq. (6.10)
    samples = extract_samples(bands[0], 20.0, n=10, seed=1)     # ch. 6.5.1, fig. 6.6 b
    road = default_road()                                       # four scales, measured + generated

Modules: :mod:`.profile` (container, units, detrending), :mod:`.readers` (text/CSV/HDF5),
:mod:`.defects` (dropouts, outliers, resampling), :mod:`.psd`, :mod:`.hdc`, :mod:`.bands`,
:mod:`.closure` (periodic spline closure), :mod:`.samples`, :mod:`.multiscale`,
:mod:`.generators`, :mod:`.reconstruction` (fig. 6.5 alternatives), :mod:`.default_road`,
:mod:`.polish` (truncated asperity tips, thesis 6.5.3), :mod:`.plots`.
"""

from rubberfriction.driver.surfaces.bands import (
    band_split,
    band_weights,
    bandlimit,
    lowpass,
    resolves,
)
from rubberfriction.driver.surfaces.closure import Closure, close_periodic
from rubberfriction.driver.surfaces.default_road import (
    DEFAULT_EDGES,
    default_road,
    find_station0,
    fine_extension,
)
from rubberfriction.driver.surfaces.defects import (
    DefectReport,
    Gap,
    clean_profile,
    find_dropouts,
    find_outliers,
    resample_uniform,
)
from rubberfriction.driver.surfaces.errors import (
    BandError,
    DefectError,
    ProfileFormatError,
    SurfaceError,
)
from rubberfriction.driver.surfaces.generators import (
    profile_from_psd,
    sawtooth_profile,
    self_affine_profile,
    self_affine_psd,
    sinusoid_sum_profile,
    two_sine_profile,
)
from rubberfriction.driver.surfaces.hdc import HDCFit, fit_hdc, hdc, hdc_from_psd, hdc_power_law
from rubberfriction.driver.surfaces.multiscale import (
    MultiScaleSurface,
    Scale,
    multiscale_from_measurements,
)
from rubberfriction.driver.surfaces.polish import polish_sample, truncate_tips
from rubberfriction.driver.surfaces.profile import Profile, detrend, unit_factor
from rubberfriction.driver.surfaces.psd import (
    PowerLawFit,
    fit_psd_power_law,
    log_bin,
    psd_1d,
    psd_iso_from_1d,
    rms_from_psd,
    rms_slope_from_psd,
    self_affine_iso_factor,
)
from rubberfriction.driver.surfaces.readers import load_profile
from rubberfriction.driver.surfaces.reconstruction import (
    compare_decompositions,
    hdc_sinusoids,
    psd_reconstruction,
    psd_reconstruction_bands,
)
from rubberfriction.driver.surfaces.samples import SurfaceSample, extract_samples, samples_table

__all__ = [
    "BandError",
    "Closure",
    "DEFAULT_EDGES",
    "DefectError",
    "DefectReport",
    "Gap",
    "HDCFit",
    "MultiScaleSurface",
    "PowerLawFit",
    "Profile",
    "ProfileFormatError",
    "Scale",
    "SurfaceError",
    "SurfaceSample",
    "band_split",
    "band_weights",
    "bandlimit",
    "clean_profile",
    "close_periodic",
    "compare_decompositions",
    "default_road",
    "detrend",
    "extract_samples",
    "find_dropouts",
    "find_outliers",
    "find_station0",
    "fine_extension",
    "fit_hdc",
    "fit_psd_power_law",
    "hdc",
    "hdc_from_psd",
    "hdc_power_law",
    "hdc_sinusoids",
    "load_profile",
    "log_bin",
    "lowpass",
    "multiscale_from_measurements",
    "polish_sample",
    "profile_from_psd",
    "psd_1d",
    "psd_iso_from_1d",
    "psd_reconstruction",
    "psd_reconstruction_bands",
    "resample_uniform",
    "resolves",
    "rms_from_psd",
    "rms_slope_from_psd",
    "samples_table",
    "sawtooth_profile",
    "self_affine_iso_factor",
    "self_affine_profile",
    "self_affine_psd",
    "sinusoid_sum_profile",
    "truncate_tips",
    "two_sine_profile",
    "unit_factor",
]
