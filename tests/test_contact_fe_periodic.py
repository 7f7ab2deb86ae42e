"""Periodic wrap-around at FE level: an elastic periodic layer slides with friction over three
periods of a rigid sinusoid wrapped across the cell boundary; after the run-in period the
per-period means of F_x, F_z and the frictional dissipation agree within 1e-6 relative."""

from __future__ import annotations

from rubberfriction.driver.verification import contact_cases as cc


def test_periodic_sliding_three_periods():
    r = cc.periodic_sliding(periods=3, steps_per_period=32)
    for c in r["checks"]:
        if c.get("tolerance") is not None:
            assert c["passed"], c
    means = r["period_means"]
    assert means[-1][0] < 0.0 < means[-1][1]  # friction opposes the block's sliding; compressive load
