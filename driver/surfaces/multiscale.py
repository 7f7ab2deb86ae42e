"""A surface decomposed into scales, possibly from several measurements (thesis ch. 6.5.1).

The thesis measures one road with two profilometers, a coarse one (0.019 mm lateral
resolution) for the macro and meso scales and a fine one (0.003 mm) for the two micro scales,
and decomposes each measurement into two scales.  :func:`multiscale_from_measurements` does the
same for any set of profiles: every band takes its profile from the *coarsest* measurement that
resolves it, i.e. that is at least ``min_periods`` x lambda_long long and samples lambda_short
at least at Nyquist (lambda_short >= 2 dx).  Each band also gets its *carrier*, the wavelengths
of the same measurement longer than the band, on which its samples' top-asperity selection is
based (ch. 6.5.1).  All bands of one measurement come from one spectrum, so the bands of a
measurement partition its spectrum (eq. (6.10)).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from rubberfriction.driver.surfaces.bands import (
    _filtered,
    _smooth_step,
    band_weights,
    check_edges,
    resolves,
)
from rubberfriction.driver.surfaces.errors import BandError
from rubberfriction.driver.surfaces.profile import Profile
from rubberfriction.driver.surfaces.samples import SurfaceSample, extract_samples, provenance_kind

__all__ = ["Scale", "MultiScaleSurface", "multiscale_from_measurements", "scale_names"]


def scale_names(n: int) -> list[str]:
    """Thesis names: macro, meso, micro 1, micro 2 for four scales; macro/micro for two."""
    if n == 4:
        return ["macro", "meso", "micro1", "micro2"]
    if n == 3:
        return ["macro", "meso", "micro"]
    if n == 2:
        return ["macro", "micro"]
    return [f"scale{i}" for i in range(n)]


@dataclass
class Scale:
    """One scale: its band profile, the carrier it rides on and where both come from."""

    name: str
    band: tuple[float, float]  #: (lambda_long, lambda_short) in mm
    profile: Profile  #: band profile
    carrier: Profile | None  #: wavelengths > lambda_long of the same measurement
    kind: str  #: "measured" or "generated"
    measurement: str  #: source of the profile the band was cut from
    block_length: float  #: rubber block length of this scale (default lambda_long), mm

    @property
    def rms_height(self) -> float:
        return self.profile.rms_height()

    @property
    def rms_slope(self) -> float:
        return self.profile.rms_slope()


@dataclass
class MultiScaleSurface:
    """Band profiles of all scales between ``edges`` (mm, descending) with their provenance."""

    edges: tuple[float, ...]
    scales: list[Scale]
    provenance: dict[str, Any] = field(default_factory=dict)
    name: str = ""

    @property
    def bands(self) -> list[Profile]:
        """The band profile of every scale, coarsest first."""
        return [s.profile for s in self.scales]

    @property
    def names(self) -> list[str]:
        return [s.name for s in self.scales]

    def extract_samples(
        self, n: int = 10, seed: int | None = 0, **kwargs: Any
    ) -> list[list[SurfaceSample]]:
        """``n`` periodic samples per scale (thesis: ten), from the top-asperity regions.

        The seed of scale i is derived from ``seed`` and i, so every scale is reproducible on
        its own.  Extra keyword arguments go to :func:`extract_samples`.
        """
        out = []
        for i, sc in enumerate(self.scales):
            sub = None
            if seed is not None:
                sub = int(np.random.SeedSequence([seed, i]).generate_state(1)[0])
            samples = extract_samples(sc.profile, sc.block_length, n, sub, carrier=sc.carrier,
                                      scale=i, **kwargs)
            for s in samples:
                s.meta["scale_name"] = sc.name
                s.seed = seed
            out.append(samples)
        return out

    def describe(self) -> str:
        """Human-readable provenance: which scale is measured and which is generated."""
        edges = ", ".join(f"{e:g}" for e in self.edges)
        lines = [f"multiscale surface {self.name!r}: edges {edges} mm"]
        for sc in self.scales:
            lines.append(
                f"  {sc.name:<7} {sc.band[0]:>7g} - {sc.band[1]:<7g} mm  "
                f"block {sc.block_length:g} mm  "
                f"rms h {sc.rms_height:.4g} mm  rms slope {sc.rms_slope:.3g}  "
                f"{sc.kind.upper()}: {sc.measurement}"
            )
        for key, val in self.provenance.items():
            if isinstance(val, dict):
                lines.append(f"  {key}:")
                lines.extend(f"    {k}: {v}" for k, v in val.items())
            else:
                lines.append(f"  {key}: {val}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description without the arrays."""
        return {
            "name": self.name,
            "edges_mm": list(self.edges),
            "scales": [
                {
                    "name": sc.name,
                    "band_mm": list(sc.band),
                    "block_length_mm": sc.block_length,
                    "kind": sc.kind,
                    "measurement": sc.measurement,
                    "dx_mm": sc.profile.dx,
                    "length_mm": sc.profile.length,
                    "rms_height_mm": sc.rms_height,
                    "rms_slope": sc.rms_slope,
                }
                for sc in self.scales
            ],
            "provenance": _jsonable(self.provenance),
        }


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if hasattr(obj, "to_dict"):
        return _jsonable(obj.to_dict())
    return obj


def multiscale_from_measurements(
    measurements: Sequence[Profile],
    edges_mm: Sequence[float],
    *,
    names: Sequence[str] | None = None,
    block_lengths: Sequence[float] | None = None,
    filter: str = "ideal",  # noqa: A002
    transition: float = 0.1,
    min_periods: float = 1.0,
    points_per_wavelength: float = 4.0,
    nyquist_factor: float = 2.0,
    name: str = "",
    provenance: dict[str, Any] | None = None,
) -> MultiScaleSurface:
    """Decompose one surface measured at several resolutions into the scales between ``edges``.

    Each band [lambda_i, lambda_i+1] is taken from the coarsest measurement (largest dx; the
    longest of equals) that :func:`~rubberfriction.driver.surfaces.bands.resolves` it with at
    least ``points_per_wavelength`` samples per shortest wavelength (default 4: the last octave
    below that is spoilt by the instrument's spot size and noise, e.g. the CAPTIF spectrum
    flattens below ~5 dx).  If no measurement does, the finest one that still samples the band
    at Nyquist (``nyquist_factor`` = 2) is used and ``provenance["near_resolution_limit"]``
    lists the band.  A band no measurement resolves raises :class:`BandError` naming what is
    missing.  ``block_lengths`` default to the long edge of each band (thesis ch. 6.5.1: 20, 3,
    0.3, 0.04 mm blocks).  With the thesis's coarse 0.019 mm scan this assigns macro and meso
    to it and both micro scales to the fine scan, as in ch. 6.5.1.
    """
    e = check_edges(edges_mm)
    nb = e.size - 1
    if not measurements:
        raise BandError("no measurement given")
    names = list(names) if names is not None else scale_names(nb)
    if len(names) != nb:
        raise BandError(f"{nb} bands but {len(names)} names")
    blocks = [float(b) for b in (block_lengths if block_lengths is not None else e[:-1])]
    if len(blocks) != nb:
        raise BandError(f"{nb} bands but {len(blocks)} block lengths")
    order = sorted(range(len(measurements)),
                   key=lambda k: (-measurements[k].dx, -measurements[k].length))
    assign: list[int] = []
    near_limit: list[str] = []
    for i in range(nb):
        def ok(k: int, factor: float, i: int = i) -> bool:
            return resolves(measurements[k], e[i], e[i + 1], min_periods=min_periods,
                            nyquist_factor=factor)

        good = [k for k in order if ok(k, points_per_wavelength)]
        fair = [k for k in order[::-1] if ok(k, nyquist_factor)]
        if good:
            assign.append(good[0])  # coarsest with enough samples per wavelength
        elif fair:
            assign.append(fair[0])  # finest at Nyquist
            near_limit.append(names[i])
        else:
            have = "; ".join(f"{p.source or 'profile'}: dx {p.dx:.4g} mm, length {p.length:.4g} mm"
                             for p in measurements)
            raise BandError(
                f"no measurement resolves the band {e[i]:g}-{e[i + 1]:g} mm (needs dx <= "
                f"{e[i + 1] / nyquist_factor:.4g} mm and length >= {min_periods * e[i]:.4g} mm); "
                f"have {have}"
            )
    scales: list[Scale | None] = [None] * nb
    for k in sorted(set(assign)):
        prof = measurements[k]
        mine = [i for i in range(nb) if assign[i] == k]

        def weights(q: np.ndarray, mine: list[int] = mine) -> list[np.ndarray]:
            all_w = band_weights(q, e, filter, transition)  # type: ignore[arg-type]
            out = [all_w[i] for i in mine]
            for i in mine:  # carriers: everything longer than the band, zero mean
                qc = 2.0 * np.pi / e[i]
                if filter == "ideal":
                    w = (q < qc).astype(float)
                else:
                    w = 1.0 - _smooth_step(q, qc, transition)
                w[0] = 0.0
                out.append(w)
            return out

        parts = _filtered(prof, weights)
        kind = provenance_kind(prof)
        for j, i in enumerate(mine):
            band = (float(e[i]), float(e[i + 1]))
            meta = {"band": band, "band_index": i, "filter": filter, "parent": prof.source,
                    "periodic": prof.periodic,
                    "extension": "periodic" if prof.periodic else "mirror",
                    "provenance": prof.meta.get("provenance", {})}
            bp = Profile(prof.x, parts[j], "mm", f"{prof.source} [band {band[0]:g}-{band[1]:g} mm]",
                         meta, prof.repaired)
            cmeta = {"lowpass": band[0], "parent": prof.source, "periodic": prof.periodic}
            cp = Profile(prof.x, parts[len(mine) + j], "mm", f"{prof.source} [> {band[0]:g} mm]",
                         cmeta, prof.repaired)
            scales[i] = Scale(names[i], band, bp, cp, kind, prof.source, blocks[i])
    prov = dict(provenance or {})
    prov.setdefault("assignment", {names[i]: measurements[assign[i]].source for i in range(nb)})
    if near_limit:
        prov["near_resolution_limit"] = (
            f"{', '.join(near_limit)}: fewer than {points_per_wavelength:g} samples per shortest "
            "wavelength in every measurement; taken from the finest one"
        )
    done = [s for s in scales if s is not None]
    return MultiScaleSurface(tuple(float(v) for v in e), done, prov, name)
