"""Synthetic profiles: self-affine random profiles, sums of sinusoids, sawtooth profiles.

All generators return exactly periodic profiles (``meta["periodic"] = True``, period
L = n dx) in millimetres with ``meta["provenance"] = {"kind": "generated", ...}``.

* :func:`self_affine_profile`: Gaussian random profile with the 1D PSD (Persson convention)

      C1D(q) = C0                        for q_min <= q < q_r   (roll-off plateau)
      C1D(q) = C0 (q / q_r)^-(1+2H)      for q_r <= q <= q_s    (self-affine, thesis ch. 2.3.1)
      C1D(q) = 0                         otherwise              (q_s: short-wavelength cut-off)

  realised by Fourier filtering: each rfft coefficient is a complex Gaussian with
  E|H_k|^2 = N^2 C1D(q_k) dq, so E[mean(h^2)] = 2 sum C1D(q_k) dq.  C0 is set so that this
  expected mean square equals rms_height^2 *on the generated grid* (so no discretisation bias);
  a single realisation scatters around it.  ``amplitudes="fixed"`` keeps |H_k| at its expected
  value with random phases only (the rms is then exact).
* :func:`profile_from_psd`: the same for any C1D(q) function.
* :func:`sinusoid_sum_profile`, :func:`two_sine_profile`: sums of sines; the two-sine case is
  the validation geometry of thesis eqs. (6.7)-(6.8).
* :func:`sawtooth_profile`: sawtooth in the two mirrored orientations of thesis ch. 6.4.1.
"""

from __future__ import annotations

from typing import Callable, Literal, Sequence

import numpy as np
import scipy.fft as sfft

from rubberfriction.driver.surfaces.errors import SurfaceError
from rubberfriction.driver.surfaces.profile import Profile

__all__ = [
    "self_affine_psd",
    "self_affine_profile",
    "profile_from_psd",
    "sinusoid_sum_profile",
    "two_sine_profile",
    "sawtooth_profile",
    "TWO_SINE_AMPLITUDES",
    "TWO_SINE_WAVELENGTHS",
]

#: Thesis eq. (6.8): z1 = 0.075 sin(2 pi x / 5), z2 = 0.01 sin(2 pi x / 0.5)  (mm).
TWO_SINE_AMPLITUDES = (0.075, 0.01)
TWO_SINE_WAVELENGTHS = (5.0, 0.5)


def _grid(length: float, dx: float) -> tuple[int, float]:
    if not (length > 0 and dx > 0):
        raise SurfaceError(f"length and dx must be positive, got {length}, {dx}")
    n = int(round(length / dx))
    if n < 4:
        raise SurfaceError(f"length {length} mm at dx {dx} mm gives only {n} points")
    return n, dx


def self_affine_psd(
    q: np.ndarray,
    *,
    H: float,
    C0: float,
    q_rolloff: float,
    q_cutoff: float,
    q_min: float = 0.0,
) -> np.ndarray:
    """The model C1D(q) of the module docstring (mm^3), for q in 1/mm."""
    q = np.asarray(q, dtype=float)
    c = np.where(q < q_rolloff, C0, C0 * (np.maximum(q, 1e-300) / q_rolloff) ** (-(1.0 + 2.0 * H)))
    return np.where((q >= q_min) & (q <= q_cutoff * (1 + 1e-12)) & (q > 0), c, 0.0)


def _provenance(model: str, **params: object) -> dict[str, object]:
    return {"kind": "generated", "model": model, **params}


def profile_from_psd(
    c1d: Callable[[np.ndarray], np.ndarray],
    length: float,
    dx: float,
    *,
    seed: int | None = 0,
    amplitudes: Literal["gaussian", "fixed"] = "gaussian",
    source: str = "generated: profile_from_psd",
    provenance: dict[str, object] | None = None,
) -> Profile:
    """Periodic random profile whose expected 1D PSD (Persson convention) is ``c1d(q)``.

    ``amplitudes="gaussian"``: Gaussian random field (random amplitude and phase per mode);
    ``"fixed"``: |H_k| = N sqrt(C1D dq), random phase only.  The Nyquist mode is left out.
    """
    n, dx = _grid(length, dx)
    L = n * dx
    k = np.arange(n // 2 + 1)
    q = 2.0 * np.pi * k / L
    dq = 2.0 * np.pi / L
    c = np.zeros(k.size)
    c[1:] = np.asarray(c1d(q[1:]), dtype=float)
    if n % 2 == 0:
        c[-1] = 0.0
    if np.any(c < 0) or not np.all(np.isfinite(c)):
        raise SurfaceError("the PSD must be finite and non-negative")
    rng = np.random.default_rng(seed)
    if amplitudes == "gaussian":
        gauss = rng.standard_normal(k.size) + 1j * rng.standard_normal(k.size)
        coef = n * np.sqrt(c * dq / 2.0) * gauss
    elif amplitudes == "fixed":
        coef = n * np.sqrt(c * dq) * np.exp(2j * np.pi * rng.random(k.size))
    else:
        raise SurfaceError(f"amplitudes must be 'gaussian' or 'fixed', got {amplitudes!r}")
    h = sfft.irfft(coef, n=n)
    prov = dict(provenance or {"kind": "generated", "model": "profile_from_psd"})
    prov.update({"seed": seed, "amplitudes": amplitudes, "length_mm": L, "dx_mm": dx})
    return Profile(dx * np.arange(n), h, "mm", source, {"periodic": True, "provenance": prov})


def self_affine_profile(
    length: float,
    dx: float,
    *,
    H: float,
    rms_height: float,
    q_rolloff: float | None = None,
    q_cutoff: float | None = None,
    q_min: float = 0.0,
    seed: int | None = 0,
    amplitudes: Literal["gaussian", "fixed"] = "gaussian",
) -> Profile:
    """Self-affine random profile (thesis ch. 2.3.1) with Hurst exponent H and given rms height.

    Parameters (lengths in mm, wavenumbers q = 2 pi / lambda in 1/mm): ``q_rolloff`` (default
    2 pi / L: no plateau), ``q_cutoff`` (default Nyquist pi / dx), ``q_min`` (modes below are
    absent).  The expected mean square on the generated grid is ``rms_height**2`` (module
    docstring); ``meta["provenance"]`` records all parameters and C0.
    """
    n, dx = _grid(length, dx)
    L = n * dx
    if not 0.0 < H <= 1.5:
        raise SurfaceError(f"Hurst exponent should lie in (0, 1.5], got {H}")
    if not rms_height > 0:
        raise SurfaceError("rms height must be positive")
    q_r = 2.0 * np.pi / L if q_rolloff is None else float(q_rolloff)
    q_s = np.pi / dx if q_cutoff is None else float(q_cutoff)
    if not 0 < q_r <= q_s:
        raise SurfaceError(f"need 0 < q_rolloff <= q_cutoff, got {q_r}, {q_s}")
    q = 2.0 * np.pi * np.arange(1, (n - 1) // 2 + 1) / L  # modes used (Nyquist excluded)
    shape = self_affine_psd(q, H=H, C0=1.0, q_rolloff=q_r, q_cutoff=q_s, q_min=q_min)
    ms_unit = 2.0 * np.sum(shape) * (2.0 * np.pi / L)
    if ms_unit <= 0:
        raise SurfaceError("no Fourier mode of the grid lies between q_min and q_cutoff")
    C0 = rms_height**2 / ms_unit
    prov = _provenance("self-affine", H=H, rms_height_mm=rms_height, q_rolloff=q_r, q_cutoff=q_s,
                       q_min=q_min, C0_mm3=C0)
    p = profile_from_psd(
        lambda qq: self_affine_psd(qq, H=H, C0=C0, q_rolloff=q_r, q_cutoff=q_s, q_min=q_min),
        L, dx, seed=seed, amplitudes=amplitudes,
        source=f"generated: self-affine H={H:g}, rms={rms_height:g} mm, seed={seed}",
        provenance=prov,
    )
    return p


def sinusoid_sum_profile(
    length: float,
    dx: float,
    amplitudes: Sequence[float],
    wavelengths: Sequence[float],
    phases: Sequence[float] | None = None,
) -> Profile:
    """h(x) = sum_i A_i sin(2 pi x / lambda_i + phi_i) on [0, length) (mm).

    Periodic (``meta["periodic"]``) when the length is a whole number of every wavelength.
    """
    n, dx = _grid(length, dx)
    a = np.asarray(amplitudes, dtype=float)
    lam = np.asarray(wavelengths, dtype=float)
    ph = np.zeros_like(a) if phases is None else np.asarray(phases, dtype=float)
    if not (a.shape == lam.shape == ph.shape) or a.ndim != 1:
        raise SurfaceError("amplitudes, wavelengths and phases must be 1D of equal length")
    if np.any(lam <= 0):
        raise SurfaceError("wavelengths must be positive")
    x = dx * np.arange(n)
    h = np.sin(np.outer(x, 2.0 * np.pi / lam) + ph) @ a
    L = n * dx
    cycles = L / lam
    periodic = bool(np.allclose(cycles, np.round(cycles), rtol=0, atol=1e-9))
    prov = _provenance("sum of sinusoids", amplitudes_mm=a.tolist(), wavelengths_mm=lam.tolist(),
                       phases_rad=ph.tolist())
    return Profile(x, h, "mm", "generated: " + " + ".join(
        f"{ai:g} sin(2 pi x / {li:g})" for ai, li in zip(a, lam)),
        {"periodic": periodic, "provenance": prov})


def two_sine_profile(
    length: float = 10.0,
    dx: float = 0.005,
    amplitudes: Sequence[float] = TWO_SINE_AMPLITUDES,
    wavelengths: Sequence[float] = TWO_SINE_WAVELENGTHS,
) -> Profile:
    """The two-scale validation profile of thesis eqs. (6.7)-(6.8): z = z1 + z2 with
    z1 = 0.075 sin(2 pi x / 5), z2 = 0.01 sin(2 pi x / 0.5) (mm)."""
    if len(amplitudes) != 2 or len(wavelengths) != 2:
        raise SurfaceError("the two-sine profile has two amplitudes and two wavelengths")
    return sinusoid_sum_profile(length, dx, amplitudes, wavelengths)


def sawtooth_profile(
    length: float = 20.0,
    dx: float = 0.01,
    *,
    wavelength: float = 5.0,
    height: float = 1.0,
    orientation: Literal["sharp", "smooth"] = "sharp",
    steep_fraction: float = 0.1,
) -> Profile:
    """Sawtooth profile of thesis ch. 6.4.1 (fig. 6.10) in either orientation, zero mean.

    The rubber block slides in +x (CONTRIBUTING: x = sliding direction) over the fixed road.
    ``"sharp"``: each tooth rises steeply over ``steep_fraction`` of the wavelength and falls
    gently, so the steep flank faces the oncoming rubber (the thesis finds ~40 % more friction
    for this orientation).  ``"smooth"``: the mirror image h_smooth(x) = h_sharp(-x), gentle
    rise and steep drop.  Both have the same PSD; only their slope distribution differs.
    ``height`` is peak to valley (mm); the geometry defaults are illustrative (the thesis gives
    the block, 20 mm x 8 mm, not the teeth).
    """
    n, dx = _grid(length, dx)
    if not 0 < steep_fraction < 1:
        raise SurfaceError("steep_fraction must lie in (0, 1)")
    if orientation not in ("sharp", "smooth"):
        raise SurfaceError(f"orientation must be 'sharp' or 'smooth', got {orientation!r}")
    x = dx * np.arange(n)
    sign = 1.0 if orientation == "sharp" else -1.0
    u = np.mod(sign * x / wavelength, 1.0)
    f = steep_fraction
    h = np.where(u < f, height * u / f, height * (1.0 - (u - f) / (1.0 - f))) - 0.5 * height
    L = n * dx
    periodic = bool(abs(L / wavelength - round(L / wavelength)) < 1e-9)
    prov = _provenance("sawtooth", orientation=orientation, wavelength_mm=wavelength,
                       height_mm=height, steep_fraction=f)
    return Profile(x, h, "mm", f"generated: sawtooth ({orientation}), lambda={wavelength:g} mm",
                   {"periodic": periodic, "provenance": prov})
