"""How deep the rigid road pokes into the rubber between contact nodes (a resolution check).

Penalty contact lets the road into the rubber by p / c_N at the contact nodes; between nodes a
road feature narrower than the contact elements can cut through the rubber face unseen by a
formulation that checks the nodes only (node-to-surface) and partly unseen by the mortar
integrals.  The deepest road vertex inside the rubber face, relative to the contact element
length, says whether a run resolves its road: well below 1 it does; at 1 and above the road's
peaks reach an element deep into the rubber and the contact state is a property of the mesh.
"""

from __future__ import annotations

import numpy as np


def road_intrusion(face_x: np.ndarray, face_z: np.ndarray, road_x: np.ndarray,
                   road_h: np.ndarray, period: float) -> float:
    """Largest height of a road vertex above the rubber's contact face (0 if none is inside).

    face_x, face_z: current positions of the face's nodes (any order); road_x, road_h: the road's
    vertices in the same frame; period > 0: both are periodic with it (the face read as a graph
    z(x) over one period, which a face folded over itself is not: then a lower bound).
    """
    if not period > 0.0:
        raise ValueError(f"road_intrusion: period = {period!r}, expected a periodic cell (> 0)")
    fx, fz = np.asarray(face_x, float), np.asarray(face_z, float)
    order = np.argsort(fx)
    z_face = np.interp(np.asarray(road_x, float), fx[order], fz[order], period=period)
    return float(max(0.0, np.max(np.asarray(road_h, float) - z_face)))
