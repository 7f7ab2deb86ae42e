"""The embedded default road: CAPTIF chipseal (measured) plus a self-affine fine extension.

The thesis builds its four-scale setup (ch. 6.5.1) from two measurements of one road: a coarse
profilometer scan (0.019 mm) for the macro (20-3 mm) and meso (3-0.3 mm) scales and a fine one
(0.003 mm) for micro 1 (0.3-0.04 mm) and micro 2 (0.04-0.003 mm).  The project has one real
road profile, the CAPTIF stationary laser scan ``captif_chipseal_station0.dat`` (chipseal,
0.0375 mm spacing, MIT licence, see ``data/LICENSE.captif-slp``), which resolves wavelengths
down to 0.075 mm only.  So:

* macro and meso come from the **measured** CAPTIF profile (cleaned: reference-plate outliers
  and dropouts handled by :func:`~rubberfriction.driver.surfaces.defects.clean_profile`);
* micro 1 and micro 2 come from a **generated** fine "measurement" (:func:`fine_extension`): a
  Gaussian random profile, 32.768 mm long at 0.0005 mm spacing, whose PSD is the measured PSD
  for wavelengths above 3 mm and, below, the power law C1D = K q^-(1+2H) fitted to the measured
  PSD over 3-0.3 mm (the meso band, sampled with >= 8 points per wavelength; below ~0.2 mm the
  laser's own smoothing and noise flatten the measured spectrum), continued down to the cut-off
  0.003 mm.  This is an assumption (self-affinity continuing over two more decades), not a
  measurement; the output says so.

The data file is looked for in ``shared_data_dir``, then ``$RF_SHARED_DATA``, then
``../shared/data`` beside the repository, and finally the complete gzip-compressed copy shipped
in ``driver/surfaces/data/``, so the default road builds in a fresh clone and in an installed
package alike.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.generators import profile_from_psd
from rubberfriction.driver.surfaces.multiscale import (
    MultiScaleSurface,
    multiscale_from_measurements,
)
from rubberfriction.driver.surfaces.profile import Profile
from rubberfriction.driver.surfaces.psd import PowerLawFit, fit_psd_power_law, log_bin, psd_1d
from rubberfriction.driver.surfaces.readers import load_profile

__all__ = ["DEFAULT_EDGES", "DEFAULT_SEED", "default_road", "find_station0", "fine_extension"]

#: Scale edges of thesis ch. 6.5.1 (mm): macro 20-3, meso 3-0.3, micro 1 0.3-0.04,
#: micro 2 0.04-0.003.
DEFAULT_EDGES: tuple[float, ...] = (20.0, 3.0, 0.3, 0.04, 0.003)
#: Seed of the generated fine extension (the CAPTIF measurement date, 11/10/2021).
DEFAULT_SEED = 20211011
STATION0 = "captif_chipseal_station0.dat"
DATA_DIR = Path(__file__).resolve().parent / "data"
EMBEDDED_STATION0 = DATA_DIR / (STATION0 + ".gz")
#: Generated fine measurement: spacing (6 points per 0.003 mm wavelength) and length (2^16 points).
FINE_DX = 0.0005
FINE_LENGTH = 32.768
#: Wavelength range (mm) of the measured PSD that the fine extension's power law is fitted to.
EXTENSION_FIT_RANGE = (3.0, 0.3)


def _repo_shared_data() -> Path:
    return Path(__file__).resolve().parents[2].parent / "shared" / "data"


def find_station0(shared_data_dir: str | Path | None = None) -> tuple[Path, str]:
    """Path of the CAPTIF station-0 scan and where it was found.

    An explicit ``shared_data_dir`` must contain the file (else :class:`SurfaceError`); without
    it, ``$RF_SHARED_DATA``, ``../shared/data`` beside the repository and the embedded copy are
    tried in this order.
    """
    if shared_data_dir is not None:
        p = Path(shared_data_dir) / STATION0
        if not p.is_file():
            raise SurfaceError(f"{STATION0} not found in {shared_data_dir}")
        return p, "given shared data folder"
    env = os.environ.get("RF_SHARED_DATA")
    if env and (Path(env) / STATION0).is_file():
        return Path(env) / STATION0, "$RF_SHARED_DATA"
    p = _repo_shared_data() / STATION0
    if p.is_file():
        return p, "../shared/data beside the repository"
    if EMBEDDED_STATION0.is_file():
        return EMBEDDED_STATION0, "copy embedded in the package (driver/surfaces/data)"
    raise SurfaceError(f"{STATION0} not found (no shared data folder and no embedded copy)")


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def fine_extension(
    measured: Profile,
    *,
    fit_range: tuple[float, float] = EXTENSION_FIT_RANGE,
    lam_min: float = 0.003,
    length: float = FINE_LENGTH,
    dx: float = FINE_DX,
    seed: int | None = DEFAULT_SEED,
) -> tuple[Profile, PowerLawFit]:
    """A generated fine "measurement" continuing the measured PSD below its resolution.

    C1D(q) = measured (log-binned, Hann window, linear detrend) for lambda > fit_range[0];
    K q^-(1+2H) fitted on fit_range for fit_range[0] >= lambda >= lam_min; zero beyond.
    Returns the periodic profile (``meta["provenance"]["kind"] == "generated"``) and the fit.
    """
    q, c = psd_1d(measured, window="hann", detrend="linear")
    lam_long, lam_short = fit_range
    fit = fit_psd_power_law(q, c, (2 * np.pi / lam_long, 2 * np.pi / lam_short))
    if not 0.0 < fit.H < 1.5:
        raise SurfaceError(f"fitted Hurst exponent {fit.H:.3g} over {fit_range} mm is implausible")
    qb, cb, _ = log_bin(q, c, bins_per_decade=20)
    ok = cb > 0
    lqb, lcb = np.log(qb[ok]), np.log(cb[ok])
    q_join = 2 * np.pi / lam_long
    q_cut = 2 * np.pi / lam_min

    def c1d(qq: np.ndarray) -> np.ndarray:
        meas = np.exp(np.interp(np.log(qq), lqb, lcb))
        out = np.where(qq < q_join, meas, fit(qq))
        return np.where(qq <= q_cut * (1 + 1e-12), out, 0.0)

    prov: dict[str, Any] = {
        "kind": "generated",
        "model": "self-affine extension of the measured PSD",
        "H": fit.H,
        "K_mm": fit.K,
        "K_units": "mm^(2-2H)",
        "fit_range_mm": list(fit_range),
        "fit_rms_log_residual": fit.rms_log_residual,
        "measured_psd_above_mm": lam_long,
        "cutoff_mm": lam_min,
        "based_on": measured.source,
    }
    p = profile_from_psd(c1d, length, dx, seed=seed, amplitudes="gaussian",
                         source=f"generated: self-affine extension (H={fit.H:.3f}) of "
                                f"{Path(measured.source).name}",
                         provenance=prov)
    return p, fit


def default_road(
    shared_data_dir: str | Path | None = None,
    *,
    seed: int | None = DEFAULT_SEED,
    edges: Sequence[float] = DEFAULT_EDGES,
    fine_dx: float = FINE_DX,
    fine_length: float = FINE_LENGTH,
) -> MultiScaleSurface:
    """The default four-scale road (thesis ch. 6.5.1 edges 20-3-0.3-0.04-0.003 mm).

    Measured CAPTIF chipseal for the scales its 0.0375 mm spacing resolves, the generated
    self-affine extension (:func:`fine_extension`) for the finer ones; ``describe()`` and
    ``provenance`` of the result say which is which and give the fitted parameters.
    """
    path, where = find_station0(shared_data_dir)
    measured = load_profile(path)
    report = measured.meta["defects"]
    measured.meta["provenance"] = {
        "kind": "measured",
        "file": str(path),
        "found_in": where,
        "sha256": _sha256(path),
        "instrument": "CAPTIF stationary laser profiler (chipseal, station 0, 11/10/2021)",
        "licence": "MIT, (c) 2021 CAPTIF Road Research Centre, captif-nz/captif-slp",
        "dx_mm": measured.dx,
        "kept_range_mm": list(report.kept_range),
        "dropouts": report.n_dropouts,
        "outliers": report.n_outliers,
        "interpolated_fraction": report.interpolated_fraction,
    }
    fine, fit = fine_extension(measured, lam_min=min(edges), length=fine_length, dx=fine_dx,
                               seed=seed)
    prov = {
        "measured": dict(measured.meta["provenance"]),
        "generated": dict(fine.meta["provenance"]),
        "defects": str(report),
    }
    road = multiscale_from_measurements(
        [measured, fine], edges, provenance=prov,
        name="default road (CAPTIF chipseal + self-affine fine extension)",
    )
    road.provenance["fine_extension_fit"] = {
        "H": fit.H,
        "K_mm": fit.K,
        "fit_range_mm": list(EXTENSION_FIT_RANGE),
        "n_bins": fit.n_points,
    }
    return road
