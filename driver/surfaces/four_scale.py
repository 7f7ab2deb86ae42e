"""A synthetic four-scale road whose every scale a mesh can resolve (issue: resolved scales).

The default road's generated micro bands continue the CAPTIF spectrum self-affinely and become
too steep for any mesh (rms slopes 2 and 3.8).  This road is the opposite design: one
self-affine spectrum (Hurst exponent H = 0.8, thesis ch. 2.3.1) over the thesis edges
20 / 3 / 0.3 / 0.04 / 0.003 mm, its amplitude chosen so that the cumulative 2D rms slope of the
four bands reaches ``FOUR_SCALE_SLOPE`` = 1.3 exactly at 3 um, the slope cut-off of Lorenz et
al. (2015) (:mod:`.cutoff`).  As in the thesis (6.5.1) it comes as two "measurements" of one
road: a coarse profile (300 mm at 4 um, for macro, meso and micro 1) and a fine one (3 mm at
0.3 um, for micro 2), and for edges below 3 um (cut-off studies) an ultra-fine one, all
periodic Gaussian random profiles of the same PSD C1D(q) = C0 q^-(1+2H) for q >= 2 pi / 20 mm
(flat below), made from a stated seed.  The
amplitude is set on the realised bands (finite-difference slopes, as the cut-off rule measures
them), so the rule keeps all four scales whatever the seed.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from rubberfriction.driver.surfaces.generators import profile_from_psd, self_affine_psd
from rubberfriction.driver.surfaces.multiscale import (
    MultiScaleSurface,
    multiscale_from_measurements,
)
from rubberfriction.driver.surfaces.profile import Profile

__all__ = ["FOUR_SCALE_EDGES", "FOUR_SCALE_H", "FOUR_SCALE_SEED", "FOUR_SCALE_SLOPE",
           "four_scale_road"]

FOUR_SCALE_EDGES: tuple[float, ...] = (20.0, 3.0, 0.3, 0.04, 0.003)
FOUR_SCALE_H = 0.8
FOUR_SCALE_SLOPE = 1.3
FOUR_SCALE_SEED = 42
#: the two generated "measurements": (length, spacing) in mm
COARSE = (300.0, 0.004)
FINE = (3.0, 0.0003)
#: the ultra-fine profile for edges below 3 um (resolves bands down to 0.08 um); a fixed grid,
#: so any cut of the road is one realisation
ULTRA = (0.3, 0.00002)


def _profiles(seed: int, lam_min: float, scale: float) -> list[Profile]:
    """The generated "measurements" of the road down to ``lam_min``: coarse and fine, and below
    3 um an ultra-fine one.  Each keeps its grid whatever ``lam_min``, so every cut of the road
    is the same realisation."""
    q_r, q_s = 2.0 * math.pi / FOUR_SCALE_EDGES[0], 2.0 * math.pi / lam_min

    def c1d(q: np.ndarray) -> np.ndarray:
        return scale**2 * self_affine_psd(q, H=FOUR_SCALE_H, C0=1.0, q_rolloff=q_r, q_cutoff=q_s)

    grids = [COARSE, FINE]
    if lam_min < FOUR_SCALE_EDGES[-1] * (1 - 1e-9):
        grids.append(ULTRA)
    seeds = np.random.SeedSequence(seed).generate_state(3)
    out = []
    for (length, dx), s, what in zip(grids, seeds, ("coarse", "fine", "ultra-fine")):
        prov = {"kind": "generated", "model": "four-scale self-affine road", "H": FOUR_SCALE_H,
                "q_rolloff": q_r, "q_cutoff": q_s, "amplitude_factor": scale, "seed": seed,
                "profile": what}
        out.append(profile_from_psd(c1d, length, dx, seed=int(s), source=(
            f"generated: four-scale road ({what}, H={FOUR_SCALE_H:g}, seed={seed})"),
            provenance=prov))
    return out


def four_scale_road(edges: Sequence[float] = FOUR_SCALE_EDGES, *,
                    seed: int = FOUR_SCALE_SEED) -> MultiScaleSurface:
    """The four-scale road cut into the bands between ``edges`` (mm, descending).

    The spectrum ends at the finest edge; its amplitude is fixed by the thesis edges (cumulative
    2D rms slope 1.3 at 3 um, for this seed), so other edges cut the same road differently.
    """
    unit = multiscale_from_measurements(_profiles(seed, FOUR_SCALE_EDGES[-1], 1.0),
                                        FOUR_SCALE_EDGES)
    cum = math.sqrt(2.0 * sum(sc.rms_slope**2 for sc in unit.scales))
    factor = FOUR_SCALE_SLOPE / cum
    road = multiscale_from_measurements(
        _profiles(seed, min(edges), factor), edges,
        name=f"four-scale self-affine road (H={FOUR_SCALE_H:g}, seed {seed})",
        provenance={"generated": {"model": "four-scale self-affine road", "H": FOUR_SCALE_H,
                                  "seed": seed, "amplitude_factor": factor,
                                  "cumulative_slope_2d_at_3um": FOUR_SCALE_SLOPE,
                                  "coarse_mm": list(COARSE), "fine_mm": list(FINE)}})
    return road
