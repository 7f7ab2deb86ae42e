"""Periodic wrap-around at FE level: an elastic periodic layer slides with friction over three
periods of a rigid sinusoid wrapped across the cell boundary.

Oracles, evaluated here from the per-period means of F_x, F_z and the frictional dissipation per
step that the case returns:

* periodicity: after the run-in period the response repeats, so the means of the last two
  periods agree -- within 1e-9 relative (achieved ~1e-15; the case's own tolerance is 1e-6);
* energy balance over a period: the block is elastic and its top is held, so the work the master
  does on it (-F_x times the master's advance v dt per step) is dissipated by friction, and per
  step on average  D = -F_x v dt = -F_x lambda/steps_per_period  -- within 0.5 % (achieved 0.15 %:
  first order in the step, 0.077 % with 64 steps per period);
* friction opposes the block's sliding relative to the master (F_x < 0) under a compressive load.
"""

from __future__ import annotations

import numpy as np

from fe_helpers import checks_of, rel
from rubberfriction.driver.verification.periodic_sliding import periodic_sliding

WAVELENGTH, STEPS, PERIODS = 1.0, 32, 3


def test_periodic_sliding_three_periods():
    r = periodic_sliding(wavelength=WAVELENGTH, periods=PERIODS, steps_per_period=STEPS)
    checks_of(r, {"mean F_x, last two periods", "mean F_z, last two periods",
                  "mean dissipation, last two periods"})
    means = np.asarray(r["period_means"])  # (period, [F_x, F_z, dissipation per step])
    assert means.shape == (PERIODS, 3) and np.all(np.isfinite(means))
    last, prev = means[-1], means[-2]
    for k in range(3):
        assert rel(last[k], prev[k]) <= 1e-9, (k, means)
    Fx, Fz, D = last
    assert Fx < 0.0 < Fz and D > 0.0
    assert rel(D, -Fx * WAVELENGTH / STEPS) <= 5e-3, (D, -Fx * WAVELENGTH / STEPS)
