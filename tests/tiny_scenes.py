"""The two-sine scene the campaign tests share: two scales (2 mm and 0.2 mm sines, 20 um and
2 um high), one sample per branch, coarse and short numerics (8 elements per wavelength, 1.5
block lengths, one contact element per step): a few seconds per speed."""

from __future__ import annotations

from collections.abc import Sequence


def two_sines(name: str, velocities: Sequence[float], *, T0: float | None = None,
              run_timeout: float | None = None) -> str:
    """The scene's TOML text with its name, speeds (mm/s) and optionally T0 (K) and a run
    timeout (s)."""
    speeds = ", ".join(f"{v!r}" for v in velocities)
    lines = [f'name = "{name}"', "[surface]", 'source = "sines"', "amplitudes = [0.02, 0.002]",
             "wavelengths = [2.0, 0.2]", "[samples]", "pressure = 1", "friction = 1",
             "[conditions]", "pressures = [0.3]", f"velocities = [{speeds}]"]
    if T0 is not None:
        lines.append(f"T0 = {T0!r}")
    lines += ["[numerics]", "elements_per_wavelength = 8", "slide_periods = 1.5",
              "step_per_element = 1.0"]
    if run_timeout is not None:
        lines.append(f"run_timeout = {run_timeout:g}")
    return "\n".join(lines) + "\n"
