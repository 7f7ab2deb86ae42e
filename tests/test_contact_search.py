"""Contact search scales linearly in the slave size and does not grow with the master size.

The master segments are binned in a uniform grid once (rigid master) or per evaluation
(deformable master, O(n)); each slave segment queries only the cells it overlaps.  Timings are
the minimum of a few repetitions; the bounds are loose (a quadratic search would exceed them by
an order of magnitude) so that the test is not sensitive to machine load.
"""

from __future__ import annotations

import time

import numpy as np

from rubberfriction.driver.fe.contact import Contact, DeformableMaster, PenaltySettings, RigidMaster, SlaveSurface


def rough_profile(n, length, seed=0):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, length, n + 1)
    h = np.cumsum(rng.standard_normal(n + 1)) * length / n * 0.3
    h -= np.linspace(h[0], h[-1], n + 1)  # no drift
    return np.column_stack([x, 0.01 * h / max(np.abs(h).max(), 1e-12)])


def slave(n, x0, length):
    x = x0 + np.linspace(0.0, length, n + 1)
    X = np.column_stack([x, np.full(x.size, 0.002)])
    return SlaveSurface(X, np.arange(2 * x.size).reshape(-1, 2), np.column_stack([np.arange(n), np.arange(1, n + 1)]))


def best_time(fn, repeat=3):
    t = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        t = min(t, time.perf_counter() - t0)
    return t


def evaluate_time(c: Contact, offset=(0.0, 0.0)):
    u = np.zeros(c.cpp.max_dof + 1)
    u[1::2] = -0.006
    return best_time(lambda: c.evaluate(u, offset=offset))


def test_time_independent_of_master_size():
    """Same master density (segments per slave segment), 100x longer master."""
    times = []
    for m in (1_000, 100_000):
        c = Contact(slave(400, 0.3, 0.5), RigidMaster(rough_profile(m, m * 1e-3)), penalty=PenaltySettings(c_N=100.0),
                    search_radius=0.02)
        times.append(evaluate_time(c))
        assert c.state()["n_active"] > 50
    assert times[1] < 4.0 * times[0], times  # 100x more master segments


def test_time_linear_in_slave_size():
    master = RigidMaster(rough_profile(20_000, 10.0))
    times = []
    for n in (250, 2000):
        c = Contact(slave(n, 1.0, 8.0), master, penalty=PenaltySettings(c_N=100.0), search_radius=0.02)
        times.append(evaluate_time(c))
    assert times[1] < 20.0 * times[0], times  # 8x more slave segments (quadratic: 64x)


def test_long_sliding_does_not_slow_down():
    """Sliding by many block lengths over a long non-periodic sample: same cost anywhere."""
    c = Contact(slave(400, 0.0, 1.0), RigidMaster(rough_profile(50_000, 200.0)), penalty=PenaltySettings(c_N=100.0),
                search_radius=0.02)
    t0 = evaluate_time(c, offset=(-1.0, 0.0))
    t1 = evaluate_time(c, offset=(-150.0, 0.0))
    assert c.state()["n_active"] > 0
    assert t1 < 4.0 * t0 + 1e-3


def test_deformable_master_rebuild_is_linear():
    times = []
    for m in (2_000, 32_000):
        V = rough_profile(m, 10.0)[::-1]  # counter-clockwise around the lower body: right to left
        master = DeformableMaster(V, 10_000 + np.arange(2 * V.shape[0]).reshape(-1, 2),
                                  np.column_stack([np.arange(m), np.arange(1, m + 1)]))
        c = Contact(slave(200, 4.0, 1.0), master, penalty=PenaltySettings(c_N=100.0), search_radius=0.02)
        u = np.zeros(10_000 + 2 * V.shape[0])
        u[1:402:2] = -0.006
        times.append(best_time(lambda: c.evaluate(u)))
        assert c.state()["n_active"] > 20
    assert times[1] < 40.0 * times[0], times  # 16x more master segments, O(n) grid rebuild
