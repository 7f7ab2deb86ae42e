"""The compiled contact module builds, imports and computes a projection correctly."""

import numpy as np

from rubberfriction import _contact


def test_project_on_polyline_closed_form():
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    seg, xi, dist, pt = _contact.project_on_polyline(np.array([0.25, 0.5]), xy)
    assert seg == 0 and abs(xi - 0.25) < 1e-14 and abs(dist - 0.5) < 1e-14
    np.testing.assert_allclose(pt, [0.25, 0.0], atol=1e-14)
    # a point below the second segment: negative signed distance,
    # distance = |(1.5,0)-(1.5,0.5)|/sqrt2
    seg, xi, dist, pt = _contact.project_on_polyline(np.array([1.5, 0.0]), xy)
    assert seg == 1 and abs(dist + 0.5 / np.sqrt(2.0)) < 1e-14
