"""A first script with the rubberfriction Python API (docs/api.md); about half a minute.

    python3 docs/tutorial.py            # writes its campaign into ./rf-results/first_script/

1. build a small scene in code (two sine waves, 5 mm and 0.5 mm long: a two-scale rough-surface
   cascade, one sample per scale, two speeds), check it, run it, print mu and the result table;
2. the PSD of the road profile shipped with the package, and its Parseval check;
3. the Hertz verification case (plane-strain cylinder on a flat) with its error.

Units: mm, s, N, MPa, K; speeds mm/s.  ``tests/test_api.py`` runs this script and checks its
numbers.
"""

from __future__ import annotations

import numpy as np

import rubberfriction as rf

# --- 1. a scene built in code (keys: rf.scene_schema(); shipped scenes: rf.shipped_scenes()) ---
SCENE = """
name = "first_script"
variant = "rough"
output = "rf-results/{name}"

[surface]
source = "sines"
amplitudes = [0.05, 0.01]     # mm, one sine wave per scale
wavelengths = [5.0, 0.5]      # mm
points_per_wavelength = 32

[samples]
pressure = 1                  # k: samples per scale passing the pressure down
friction = 1                  # j: samples per scale passing mu up

[conditions]
compounds = ["tread_default"]
pressures = [0.3]             # MPa
velocities = [10.0, 100.0]    # mm/s

[numerics]                    # coarse and short: a first look, not a converged study
elements_per_wavelength = 8
window = "fixed"
slide_periods = 1.5
window_start = 0.33
"""

scene = rf.scene_from_toml(SCENE)
print(rf.check(scene))                      # what `rubberfriction run --check` prints
result = rf.run(scene)                       # progress line, then the summary
for point in result.points:
    print(f"mu at {point.point.id}: {point.mu.mean:.6g}  ({point.status})")
rows = rf.table(result)                     # the rows of results.csv, plain dicts
print(rf.format_table(rows, ["compound", "pressure_MPa", "velocity_mm_s", "mu", "status"]))
cols = rf.arrays(result)                    # the same as numpy columns
print(f"mu(v): v = {cols['velocity_mm_s']} mm/s, mu = {cols['mu']}")
print(f"report written to {result.output}")

# --- 2. PSD of the shipped road profile (CAPTIF chipseal laser scan) ---
profile = rf.default_profile()
q, c1d = rf.psd(profile, window=None)       # Persson convention: h_rms^2 = 2 Int_0^inf C1D dq
variance_psd = 2.0 * np.sum(c1d) * q[0]     # q is the uniform grid 2 pi k / L: dq = q[0]
print(f"profile: {profile.n} points, dx = {profile.dx:.6g} mm, length {profile.length:.6g} mm")
print(f"PSD: 2 sum(C1D) dq = {variance_psd:.15e} mm^2; "
      f"variance of the profile = {np.var(profile.h):.15e} mm^2")
lam, c_hdc = rf.hdc(profile)
print(f"HDC fit (eq. 2.5): H = {rf.fit_hdc(lam, c_hdc).H:.3f}")

# --- 3. Hertz verification: FE contact pressure vs the plane-strain closed form ---
hertz = rf.verify("hertz", elements_per_a=(8, 16))  # n elements per Hertz half-width a
par = hertz["parameters"]
print(f"Hertz: R = {par['R']!r} mm, E = {par['E']!r} MPa, nu = {par['nu']!r}, "
      f"P = {par['P']!r} N/mm")
for check in hertz["checks"]:
    if check["tolerance"] is not None:
        print(f"Hertz {check['quantity']}: computed {check['computed']!r}, closed form "
              f"{check['analytical']!r}, relative error {check['rel_error']:.3e} "
              f"(tolerance {check['tolerance']!r})")
