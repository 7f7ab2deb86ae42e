"""Coulomb sliding block, F_x/F_z = mu, and Newton convergence in sliding steps.

Closed forms, evaluated here:

1. finite block (rounded front edge, as the thesis' samples), constant mu = 0.6: once every node
   slips, -F_x/F_z = mu whatever the (non-uniform) pressure -- within 0.5 % (achieved 0.2 %:
   the rounded edge's remaining bias); the same for sharp edges (test_sharp_edged_block_...);
2. periodic layer (no edges: uniform pressure p = F_z/L, every node slips at the master's
   velocity v) with a mu(p, v) law: -F_x/F_z = mu(p, v) exactly -- within 1e-6 (achieved
   <= 1.1e-7, the 6 printed digits of p; the case's own tolerance is 0.5 %).  The law is the
   interpolating cubic spline of MU(p, v) = 0.9 - 0.25 p + 0.15 tanh(log10 v - 1) on a grid
   with a node at v = 10 mm/s, so at v = 10 it is MU exactly (the data are linear in p, which
   the spline reproduces);
3. the Newton residuals of a sliding step converge quadratically: the order
   log(r_k+1/r_k)/log(r_k/r_k-1) of the last three residuals above round-off (1e-13 F) is ~2,
   but the three-point estimate is noisy, so >= 1.6 is required.
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np
import pytest

from fe_helpers import checks_of, rel
from rubberfriction.driver.cli.main import main
from rubberfriction.driver.fe import friction_law as fl
from rubberfriction.driver.verification import SolverFailure
from rubberfriction.driver.verification import sliding_block as sliding_case
from rubberfriction.driver.verification.sliding_block import sliding_block

MU, PRESSURE, VELOCITY, LENGTH = 0.6, 0.2, 10.0, 1.0
CHECKS = {"finite block: slipping nodes", "finite block: -F_x/F_z", "layer: slipping nodes",
          "layer: pressure spread", "layer: slip velocity", "layer: -F_x/F_z = mu(p, v)",
          "Newton order, finite block", "Newton order, layer mu(p,v)"}


def mu_pv(p, v):
    return 0.9 - 0.25 * p + 0.15 * np.tanh(np.log10(v) - 1.0)


P_GRID, V_GRID = np.linspace(0.0, 1.0, 6), np.logspace(-2, 4, 9)  # V_GRID[4] = 10


def newton_order(residuals, floor):
    r = [x for x in residuals if x > floor]
    assert len(r) >= 3, residuals
    return math.log(r[-1] / r[-2]) / math.log(r[-2] / r[-3])


@pytest.mark.parametrize("method,n_contact", [("mortar", 16), ("nts", 32)])
def test_sliding_block(method, n_contact):
    law = fl.fit_mu_pv(P_GRID, V_GRID, mu_pv(P_GRID[:, None], V_GRID[None, :]))
    assert V_GRID[4] == pytest.approx(VELOCITY, rel=1e-15)
    r = sliding_block(method=method, n_contact=n_contact, mu=MU, law=law, pressure=PRESSURE,
                      velocity=VELOCITY, length=LENGTH)
    by = checks_of(r, CHECKS)
    # 1. finite block, constant mu: all active nodes slip, -F_x/F_z = mu
    slipping = by["finite block: slipping nodes"]
    assert slipping["computed"] == slipping["analytical"] > 0
    assert rel(by["finite block: -F_x/F_z"]["computed"], MU) <= 5e-3
    # 2. periodic layer: every slave node in contact and slipping at v under a uniform p
    assert (by["layer: slipping nodes"]["computed"] == by["layer: slipping nodes"]["analytical"]
            == n_contact + 1)
    assert by["layer: pressure spread"]["computed"] < 1e-8
    assert rel(by["layer: slip velocity"]["computed"], VELOCITY) <= 1e-6
    p = float(re.search(r"periodic layer: p = ([0-9.eE+-]+) MPa",  # F_z/L
                        "\n".join(r["notes"])).group(1))
    assert 0.9 * PRESSURE < p < 1.1 * PRESSURE
    mu_exact = 0.9 - 0.25 * p  # MU(p, v = 10)
    # p is printed with 6 digits: |d mu| <= 0.25 x 5e-7, i.e. < 1.5e-7 relative (achieved 1e-7)
    assert rel(by["layer: -F_x/F_z = mu(p, v)"]["computed"], mu_exact) <= 1e-6
    # 3. quadratic Newton convergence: finite block in its last sliding step, the layer in its
    # second (the first after the stick-slip transition, where mu(p, v) and its tangent act)
    floor = 1e-13 * PRESSURE * LENGTH
    order_finite = newton_order(r["newton"]["finite"]["residuals"][-1], floor)
    order_layer = newton_order(r["newton"]["periodic"]["residuals"][1], floor)
    assert order_finite >= 1.6, r["newton"]["finite"]["residuals"][-1]
    assert order_layer >= 1.6, r["newton"]["periodic"]["residuals"][1]


@pytest.mark.parametrize("case", ["sharp, 16 elements", "sharp, 32 elements",
                                  "rounded r = 0.2, 16 elements", "sharp 20 x 8 mm block"])
def test_sharp_edged_block_slides_at_mu(case):
    """Steady Coulomb sliding of a finite block on a rigid flat: every node in contact slips with
    |t_T| = mu p, so -F_x/F_z = mu exactly whatever the corner -- required within 0.5 %.

    Before the chain-end frame (a chain end took the one-sided normal of its end segment, which
    tilts by 5-15 degrees under the corner's pressure peak) the sharp cases gave -1.23 % (16),
    -1.45 % (32: the bias grew under refinement) and -1.30 % (20 x 8 mm block); now -0.16 %,
    -0.16 %, -0.18 %.  The rounded block (its chain end is out of contact) was and is -0.21 %.
    What remains is the averaged normal of the node next to the corner.  The 20 x 8 mm block runs
    at 0.2 MPa: at 0.3 MPa its sharp leading edge tucks under (verification/sliding_block.py)."""
    kw = {"sharp, 16 elements": dict(edge_radius=0.0, n_contact=16),
          "sharp, 32 elements": dict(edge_radius=0.0, n_contact=32),
          "rounded r = 0.2, 16 elements": dict(edge_radius=0.2, n_contact=16),
          "sharp 20 x 8 mm block": dict(edge_radius=0.0, E=3.0, pressure=0.2, mu=0.5, length=20.0,
                                        height=8.0, n_contact=40, steps=40,
                                        step_length=0.125)}[case]
    mu = kw.get("mu", MU)
    r = sliding_block(**{"mu": mu, **kw})
    by = checks_of(r, CHECKS)
    slipping = by["finite block: slipping nodes"]
    # steady sliding: every node in contact slips
    assert slipping["computed"] == slipping["analytical"] > 0
    assert rel(by["finite block: -F_x/F_z"]["computed"], mu) <= 5e-3


#: the sharp-cornered 20 x 8 mm block of issue 42 (item 9) with 80 contact elements, as
#: ``rubberfriction verify sliding-block --length 20 --height 8 --E 3 --nu 0.45 --pressure 0.3
#: --mu 0.5 --edge-radius 0 --n-contact 80 [--frame master]`` runs it (default steps: automatic)
CORNER_80 = dict(edge_radius=0.0, E=3.0, nu=0.45, pressure=0.3, mu=0.5, length=20.0, height=8.0,
                 n_contact=80)


@pytest.mark.parametrize("case", ["sharp, 16 elements", "sharp 20 x 8 mm block at 0.3 MPa",
                                  "sharp 20 x 8 mm block at 0.3 MPa, 80 elements"])
def test_master_frame_makes_full_slip_exact(case):
    """Contact frame "master" (every node's frame is the road's normal averaged over its support):
    in full slip each nodal traction has |t_T| = mu p along the road's tangent and p along its
    normal, so -F_x/F_z = mu to round-off whatever the slave's bending -- required within 1e-9
    (the issue asks for 0.5 %).  Slave frame: -0.16 % (16 elements) and +0.47 % (the 20 x 8 mm
    block at 0.3 MPa, 40 elements).  With 80 elements the master-frame run stopped in Newton
    (step 16 of 40, a traceback on the command line) until the corner's projection normal became
    the road's (cpp_contact/README.md, "Frame of a chain end"); the default steps now slide the
    block past gross sliding (19 steps, sliding_block.gross_sliding_steps; 12 left its corner
    sticking).  This pins the frame and the solver, not the corner: the corner element is folded
    (its end segment reversed, -176 degrees), see test_sharp_corner_at_80_elements_slave_frame."""
    kw = {"sharp, 16 elements": dict(edge_radius=0.0, n_contact=16),
          "sharp 20 x 8 mm block at 0.3 MPa": dict(edge_radius=0.0, E=3.0, pressure=0.3, mu=0.5,
                                                   length=20.0, height=8.0, n_contact=40, steps=40,
                                                   step_length=0.25),
          "sharp 20 x 8 mm block at 0.3 MPa, 80 elements": CORNER_80}[case]
    mu = kw.get("mu", MU)
    r = sliding_block(**{"mu": mu, **kw}, frame="master")
    by = checks_of(r, CHECKS)
    slipping = by["finite block: slipping nodes"]
    assert slipping["computed"] == slipping["analytical"] > 0
    assert rel(by["finite block: -F_x/F_z"]["computed"], mu) <= 1e-9


@pytest.mark.xfail(strict=True, reason="the sharp corner folds under at 80 elements: the front "
                   "face is not a contact surface (issue 42, item 9; docs/notes-corners.md)")
def test_sharp_corner_at_80_elements_slave_frame():
    """The same block in the slave frame must slide at -F_x/F_z = mu within 0.5 % (steady full slip:
    every traction on the road's friction cone).  It gives 0.49646 (-0.71 %; 0.48644, -2.7 %,
    before the corner projected along the road's normal): the whole deficit is the corner's
    neighbour, whose averaged normal (5.36) follows the folded end segment.  The corner is
    pressed 10-20 x the mean pressure and dragged back by its concentrated friction force; the
    front face above it, which is not a contact surface, rolls under the road (its first node
    0.23 mm below the road) and the end segment reverses.  The bias grows with refinement (before:
    -1.7 / -2.7 / -3.6 % with 60 / 80 / 120 elements), so it is no discretisation error of the
    bottom face: the front face has to become a contact surface.  Strict: passing is news."""
    r = sliding_block(**CORNER_80)
    by = checks_of(r, CHECKS)
    slipping = by["finite block: slipping nodes"]
    assert slipping["computed"] == slipping["analytical"] > 0
    assert rel(by["finite block: -F_x/F_z"]["computed"], CORNER_80["mu"]) <= 5e-3


def test_unknown_contact_frame_is_refused():
    with pytest.raises(ValueError, match="frame: got 'road'"):
        sliding_block(frame="road", steps=1)


def test_verify_reports_a_failed_solve_in_one_line(monkeypatch, capsys):
    """A case whose Newton solve fails for the user's parameters ends ``rubberfriction verify``
    with one line naming the case, the step and the reason, and status 1 (it was a traceback)."""
    original = sliding_case.sliding_block

    @functools.wraps(original)
    def failing(**kw):
        raise SolverFailure("sliding block (finite): step 16: Newton failed: no convergence in 40 "
                            "iterations")

    monkeypatch.setattr(sliding_case, "sliding_block", failing)
    rc = main(["verify", "sliding-block", "--frame", "master", "--n-contact", "80"])
    captured = capsys.readouterr()
    assert rc == 1
    assert captured.err.strip().splitlines() == [
        "verify sliding-block: sliding block (finite): step 16: Newton failed: no convergence in "
        "40 iterations"]
    assert "Traceback" not in captured.out + captured.err
