"""The scales of a scene and their periodic surface samples (thesis 6.3.1, eq. 6.10, 6.14).

A rough scene's surface (the default road or measured profiles) is split into band-pass scales
by :mod:`rubberfriction.driver.surfaces`; a sines scene gives one sine wave per scale.  Each scale
carries the periodic samples its runs slide over.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from rubberfriction.driver.multiscale.results import ScaleSet
from rubberfriction.driver.scenes import Scene, SceneError, surface_scale_names
from rubberfriction.driver.surfaces.roads import road_builder, tip_rows
from rubberfriction.driver.surfaces import SurfaceError, extract_samples, polish_sample


@dataclass(frozen=True)
class PeriodicSample:
    """A periodic surface sample built here (sine waves): x 0..period inclusive, h[-1] == h[0]."""

    x: np.ndarray
    h: np.ndarray
    period: float
    source: str = "generated"

    @property
    def rms_height(self) -> float:
        return float(np.std(self.h[:-1]))

    @property
    def rms_slope(self) -> float:
        return float(np.sqrt(np.mean((np.diff(self.h) / np.diff(self.x)) ** 2)))


def sine_sample(amplitudes: list[float], wavelengths: list[float], length: float,
                points_per_wavelength: int) -> PeriodicSample:
    """sum_i a_i sin(2 pi x / lambda_i) on [0, length], sampled with points_per_wavelength vertices
    per shortest wavelength (endpoint included)."""
    m = int(round(points_per_wavelength * length / min(wavelengths)))
    x = np.linspace(0.0, length, m + 1)
    h = sum(a * np.sin(2.0 * np.pi * x / lam) for a, lam in zip(amplitudes, wavelengths))
    h = np.asarray(h, dtype=float)
    h[-1] = h[0]
    return PeriodicSample(x, h, float(length))


@dataclass
class Scales:
    """The scales of a scene with their samples (and the full-profile sample for a reference)."""

    sets: list[ScaleSet]
    full_sample: Any = None
    description: str = ""
    provenance: dict = field(default_factory=dict)


def build_scales(scene: Scene, n_samples: int) -> Scales:
    """Band-pass scales (eq. 6.10, 6.14) and ``n_samples`` periodic samples per scale (6.3.1).

    The road's heights are ``[surface] height_scale`` times the stated road's (thesis 6.5.2;
    sines: the amplitudes); the samples of the polished scales have their tips truncated
    (``polish_fraction``, thesis 6.5.3, :func:`~rubberfriction.driver.surfaces.polish.
    truncate_tips`).  Both settings are in the provenance (``campaign.json``)."""
    scales = _build_scales(scene, n_samples)
    s = scene.surface
    polished = set(s.polished)
    scales.sets = [replace(ss, samples=tuple(polish_sample(smp, s.polish_fraction)
                                             for smp in ss.samples))
                   if ss.name in polished else ss for ss in scales.sets]
    scales.provenance["height_scale"] = s.height_scale
    scales.provenance["polish"] = {"fraction": s.polish_fraction, "scales": list(s.polished)}
    return scales


def _build_scales(scene: Scene, n_samples: int) -> Scales:
    """The scales and their samples of :func:`build_scales` before polishing."""
    s = scene.surface
    k = s.height_scale
    if s.source == "sines":
        sets = []
        names = surface_scale_names(s)
        for i, (a, lam) in enumerate(zip([k * a for a in s.amplitudes], s.wavelengths)):
            L = s.block_lengths[i] if s.block_lengths else s.periods_per_block * lam
            if abs(L / lam - round(L / lam)) > 1e-9:
                raise SceneError(f"{scene.source}: [surface].block_lengths[{i}] = {L:g}: expected "
                                 f"a whole number of wavelengths {lam:g} mm (a periodic sample)")
            band = (s.edges[i], s.edges[i + 1]) if s.edges else (lam, lam)
            smp = sine_sample([a], [lam], L, s.points_per_wavelength)
            sets.append(ScaleSet(names[i], band, tuple([smp] * n_samples)))
        L0 = sets[0].samples[0].period
        full = None
        for lam in s.wavelengths:
            if abs(L0 / lam - round(L0 / lam)) > 1e-9:
                break
        else:
            full = sine_sample([k * a for a in s.amplitudes], list(s.wavelengths), L0,
                               s.points_per_wavelength)
        desc = "sines: " + " + ".join(f"{k * a:g} sin(2 pi x / {lam:g})" for a,
                                      lam in zip(s.amplitudes, s.wavelengths))
        return Scales(sets, full, desc, {"source": "sines", "amplitudes": list(s.amplitudes),
                                         "wavelengths": list(s.wavelengths)})
    try:
        road = _multiscale_road(scene)
        samples = road.extract_samples(n=n_samples, seed=s.seed, top_fraction=s.top_fraction)
    except SurfaceError as err:
        raise SceneError(f"{scene.source}: [surface] (source = {s.source!r}, edges = "
                         f"{list(s.edges)}): {err}") from None
    sets = [ScaleSet(sc.name, tuple(sc.band), tuple(smp)) for sc, smp in zip(road.scales, samples)]
    full = None
    if scene.variant == "separated" and scene.separated is not None and scene.separated.reference:
        full = _full_sample(scene, road)
    provenance = road.to_dict()
    if s.cutoff_report is not None:  # the lowest-scale rule and what it kept (campaign.json)
        provenance["cutoff"] = s.cutoff_report.to_dict()
    return Scales(sets, full, road.describe(), provenance)


def surface_lines(scene: Scene, scales: Scales) -> list[str]:
    """What ``run --check`` and the report say of the scales: the cut-off rule's table (each
    stated band measured or generated, its 1D rms slope, the cumulative 2D slope, kept, shortened
    or dropped and why) and the sharpest tip of each scale's samples against its element size."""
    report = scene.surface.cutoff_report
    lines = [] if report is None else report.lines()
    tips = tip_rows(scales.sets,
                    lambda name: scene.numerics.for_scale(name).elements_per_wavelength)
    lines.append("  resolution (sharpest asperity tip of the samples / contact element size):")
    lines.extend("  " + t.line() + ("  <- a tip narrower than one element" if t.ratio < 1 else "")
                 for t in tips)
    return lines


def _multiscale_road(scene: Scene) -> Any:
    """The band profiles of a road (``[surface]`` source default_road, four_scale or files) at the
    edges its cut-off rule kept."""
    s = scene.surface
    return road_builder(s.source, s.files, surface_scale_names(s), s.block_lengths,
                        scene.name, s.height_scale)(tuple(s.edges))


def macro_road(scene: Scene, start: float, length: float,
               dx: float) -> tuple[np.ndarray, np.ndarray]:
    """A non-periodic road for the thermal macro block: the first (macro) band of the scene's
    surface from ``start`` mm along its profile for ``length`` mm, sampled every ``dx`` mm; x from
    0.  Sines: the first sine.  The band is zero-mean; heights in mm."""
    s = scene.surface
    x = np.arange(0.0, length + 0.5 * dx, dx)
    if s.source == "sines":
        a, lam = s.height_scale * s.amplitudes[0], s.wavelengths[0]
        return x, a * np.sin(2.0 * np.pi * (x + start) / lam)
    try:
        band = _multiscale_road(scene).scales[0].profile
    except SurfaceError as err:
        raise SceneError(f"{scene.source}: [surface] (source = {s.source!r}): {err}") from None
    x0 = float(band.x[0]) + start
    if x0 + length > float(band.x[-1]):
        raise SceneError(f"{scene.source}: [thermal] road_surface = 'macro': the macro band is "
                         f"{band.x[-1] - band.x[0]:.1f} mm long; road_start = {start:g} mm plus "
                         f"the {length:.1f} mm the slide needs does not fit")
    return x, np.interp(x0 + x, band.x, band.h)


def _full_sample(scene: Scene, road: Any) -> Any:
    """A macro-length sample of the sum of both bands (reference run of the separated variant)."""
    a, b = road.scales
    if a.profile.x.shape != b.profile.x.shape or not np.allclose(a.profile.x, b.profile.x):
        raise SceneError(f"{scene.source}: [separated].reference = true needs both scales cut from "
                         f"one "
                         "measurement (the full profile is their sum); set reference = false")
    full = a.profile.with_h(a.profile.h + b.profile.h)
    full.meta.update(a.profile.meta)
    return extract_samples(full, a.block_length, 1, scene.surface.seed, carrier=a.carrier,
                           top_fraction=scene.surface.top_fraction)[0]
