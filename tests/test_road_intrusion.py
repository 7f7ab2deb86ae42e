"""The road-intrusion check of a periodic cell (driver.sliding.intrusion).

Constructed faces: a road vertex above a flat face is inside by its height, one below is not,
and the face is read periodically (a vertex between the last node and the first one's image).
"""

from __future__ import annotations

import numpy as np
import pytest

from rubberfriction.driver.sliding.intrusion import road_intrusion


def test_intrusion_of_constructed_faces():
    fx, fz = np.array([0.0, 0.3, 0.6, 0.9]), np.zeros(4)
    assert road_intrusion(fx, fz, [0.45], [0.1], 1.0) == pytest.approx(0.1)
    assert road_intrusion(fx, fz, [0.45, 0.7], [-0.2, -0.01], 1.0) == 0.0
    # a sloped face over the wrap-around: z = 0.9 at x = 0.9, 0 at x = 1.0 (x = 0's image)
    fz = np.array([0.0, 0.0, 0.0, 0.9])
    assert road_intrusion(fx, fz, [0.95], [0.5], 1.0) == pytest.approx(0.05)
    # node order does not matter; the road may be given outside [0, L)
    perm = [2, 0, 3, 1]
    assert road_intrusion(fx[perm], fz[perm], [1.95], [0.5], 1.0) == pytest.approx(0.05)
    with pytest.raises(ValueError, match="periodic"):
        road_intrusion(fx, fz, [0.5], [0.0], 0.0)
