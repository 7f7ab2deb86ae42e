"""Coulomb sliding block: F_x/F_z = mu within 0.5 % (constant mu; a mu(p, v) spline at the known
(p, v) of a periodic layer), and quadratic Newton convergence in sliding steps (order >= 1.8 from
the last iterations above round-off), for mortar and node-to-segment."""

from __future__ import annotations

import pytest

from rubberfriction.driver.verification import contact_cases as cc


@pytest.mark.parametrize("method", ["mortar", "nts"])
def test_sliding_block(method):
    r = cc.sliding_block(method=method)
    by = {c["quantity"]: c for c in r["checks"]}
    for c in r["checks"]:
        if c.get("tolerance") is not None:
            assert c["passed"], c
    assert by["layer: pressure spread"]["computed"] < 1e-8  # uniform p: the (p, v) is known
    assert by["Newton order, finite block"]["computed"] >= 1.8, r["newton"]["finite"]
    assert by["Newton order, layer mu(p,v)"]["computed"] >= 1.8, r["newton"]["periodic"]
