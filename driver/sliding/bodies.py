"""The two bodies of a sliding run: the graded rubber block and its contact with the road sample."""

from __future__ import annotations

import numpy as np

from rubberfriction.driver.fe.contact import (
    DEFAULT_TANGENTIAL_FRACTION,
    Contact,
    PenaltySettings,
    RigidMaster,
    SlaveSurface,
)
from rubberfriction.driver.sliding.spec import PENALTY_ALPHA, penalty_modulus
from rubberfriction.driver.sliding.temperature import surface_temperature
from rubberfriction.meshes.block import rubber_block


def block_mesh(L: float, H: float, hc: float, grading: float, z0: float, levels=(),
               edge_radius: float = 0.0):
    """Graded rubber block with its contact face at z = z0 (``meshes.block.rubber_block``);
    ``levels``: heights above the face that must be mesh lines (temperature layer bounds); a
    level below the contact spacing makes the first element row that thin.  ``edge_radius``:
    the leading edge (+x: the front, the road moves by -v t) rounded with this radius."""
    levels = list(levels)
    first = min(hc, levels[0]) if levels else None
    body = rubber_block(L, H, h_contact=hc, grading=grading, first_layer=first,
                        partitions=levels or None, leading_edge_radius=edge_radius,
                        leading_edge="right")
    body.mesh.geometry.x[:, 1] += z0
    return body


def sliding_contact(sp, spec, formulation: str) -> Contact:
    """Contact for ``driver.sliding.run.SlidingRun``: the block's facets tagged 1 against the rigid
    (periodic) surface of a SlidingSpec.  Automatic penalty c_N = alpha |E*_eff(omega)| / h from the
    modulus at the run's excitation frequency (``sliding.penalty_modulus``) unless ``spec.penalty``
    > 0; history referenced to the current state.  A periodic cell's contact face is a chain
    closed by the cell's constraint: its ends are a seam, not corners."""
    slave = SlaveSurface.from_boundary(sp.boundary(1), periodic_seam=spec.period > 0)
    master = RigidMaster(np.column_stack([np.asarray(spec.surface_x, float),
                                          np.asarray(spec.surface_h, float)]),
                         float(spec.period))
    frac = float(getattr(spec, "tangential_penalty", DEFAULT_TANGENTIAL_FRACTION))
    if getattr(spec, "penalty", 0.0) > 0:
        pen = PenaltySettings(c_N=float(spec.penalty), tangential_fraction=frac)
        E_eff = None
    else:
        alpha = float(getattr(spec, "penalty_alpha", PENALTY_ALPHA))
        pen, E_eff = PenaltySettings(alpha=alpha, tangential_fraction=frac), penalty_modulus(spec)
    contact = Contact(slave, master, method=formulation, friction=spec.friction, E_eff=E_eff,
                      penalty=pen, frame=getattr(spec, "contact_frame", "slave"),
                      comm=sp.mesh.comm)
    T_face = surface_temperature(getattr(spec, "temperature_layers", ()),
                                 getattr(spec, "temperature", None))
    if T_face is not None:  # a mu(p, v, T) law sees the contact face's temperature
        contact.set_temperature(float(T_face))
    contact.reset_history(sp.w.x.array)
    return contact
