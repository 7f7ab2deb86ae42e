"""What a sliding run attempts: the inputs it refuses before any set-up, and its fallback chain.

A run (``driver.sliding.run.SlidingRun``) tries the attempts of :func:`fallback_chain` in turn
until one succeeds; each is the spec's run with another contact formulation, shorter sliding
steps, shorter contact elements or a softer tangential penalty.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rubberfriction.driver.sliding.spec import (
    MESH_REFINEMENT,
    SOFT_TANGENT,
    SlidingSpec,
    has_friction,
)
from rubberfriction.driver.sliding.temperature import check_layers
from rubberfriction.driver.sliding.window import WINDOW_QUANTITIES

#: globalisations of the Newton solves (SlidingSpec.newton)
NEWTON_METHODS = ("line-search", "trust-region", "hybrid")


def check_inputs(spec: SlidingSpec) -> None:
    """ValueError for a spec no attempt can run (bad input raises before any set-up)."""
    check_layers(spec.temperature_layers, spec.compound)
    if not (np.isfinite(spec.edge_radius) and spec.edge_radius >= 0.0):
        raise ValueError(f"edge_radius = {spec.edge_radius!r} mm: expected >= 0")
    if spec.edge_radius > 0.0 and spec.period > 0:
        raise ValueError("edge_radius: a periodic cell has no edges; round only a finite block "
                         "(period = 0)")
    if not (np.isfinite(spec.stabilisation) and spec.stabilisation >= 0.0):
        raise ValueError(f"stabilisation = {spec.stabilisation!r}: expected beta >= 0 (0: off)")
    if spec.window_quantity not in WINDOW_QUANTITIES:
        raise ValueError(f"window_quantity = {spec.window_quantity!r}: expected one of "
                         f"{tuple(WINDOW_QUANTITIES)}")
    if spec.newton not in NEWTON_METHODS:
        raise ValueError(f"newton = {spec.newton!r}: expected one of {NEWTON_METHODS}")
    if spec.newton != "line-search" and spec.element == "Q1P0s":
        raise ValueError(f"newton = {spec.newton!r} with element = 'Q1P0s': the trust region "
                         "eliminates the cell pressures, which the pressure-jump term couples; "
                         "expected element Q1P0 or Q1")
    if not 0.0 <= spec.min_jacobian < 1.0:
        raise ValueError(f"min_jacobian = {spec.min_jacobian!r}: expected 0 <= det F limit < 1")


class Attempt(NamedTuple):
    """One attempt of the fallback chain (:func:`fallback_chain`)."""

    formulation: str  # "mortar", "nts" or "surface" (driver.fe.contact.Contact)
    step_factor: float = 1.0  # sliding steps this many times the spec's
    refine: int = 1  # contact elements this many times shorter (spec.refined)
    tangent: float = 1.0  # c_T this many times the spec's (spec.softened)

    @property
    def label(self) -> str:
        """e.g. "mortar", "nts x0.25 step", "mortar x2 mesh", "mortar c_T x0.1"."""
        return (self.formulation
                + (f" x{self.step_factor:g} step" if self.step_factor != 1.0 else "")
                + (f" x{self.refine} mesh" if self.refine != 1 else "")
                + (f" c_T x{self.tangent:g}" if self.tangent != 1.0 else ""))


def fallback_chain(spec: SlidingSpec) -> list[Attempt]:
    """The attempts of a run of ``spec``: contact formulation, sliding step factor, mesh
    refinement and tangential penalty factor of each.

    Mortar, then (frictional runs) mortar with c_T SOFT_TANGENT times softer (stick/slip
    cycling at the first sliding steps, see ``spec.SOFT_TANGENT``; a finite block tries the
    soft one first), node-to-segment, smaller sliding steps (stabilisation), then contact
    elements MESH_REFINEMENT times shorter with each formulation: a slave bent over master
    features sharper than its elements (a peak poking through a contact element) has no smooth
    solution path at that resolution, and no step length fixes that.  A warm start whose state
    was computed on a refined mesh (``InitialState.refine``) begins with that mesh: the same slot
    at the previous temperature converged only there, and only there does its state fit.
    """
    base = spec.contact
    first = [Attempt(base)]
    if has_friction(spec):
        soft = Attempt(base, tangent=SOFT_TANGENT)
        # a finite block (macro scale) tries the soft stick first: its first sliding step puts
        # the nodes far outside the stick cone (docs/performance.md)
        first = [soft, Attempt(base)] if spec.period == 0 else [Attempt(base), soft]
    if base == "mortar":
        first.append(Attempt("nts"))
    chain = first + [Attempt(first[-1].formulation, step_factor=0.25)]
    formulations = dict.fromkeys(a.formulation for a in first)
    chain += [Attempt(f, refine=MESH_REFINEMENT) for f in formulations]
    state = spec.initial_state
    if state is not None and state.refine > 1:
        lead = first[0]._replace(refine=int(state.refine))
        chain = [lead] + [a for a in chain if a != lead]
    return chain
