"""Warm starts (``SlidingSpec.initial_state``): a run that slides on from an earlier run's final
state instead of from rest, as the thermal loop's homogenisation points do
(``driver.multiscale.thermal_loop``: the rubber keeps its deformation and history while it heats).

The full-contact sinusoid (tread_default, a 1 mm wave of 2 um amplitude, 0.1 MPa, 10 mm/s, the
case of ``tests/test_temperature_layers.py``) converges from rest at T_ref and is then slid on:

* under the same conditions: already steady, so the window rule, which leaves no run-in out of a
  warm run, passes at its first chance (2 w = 4 periods) with the mu of the run from rest;
* with a hot bottom partition (0.2 mm at T_ref + 20 K): the layered strip's closed form within
  3 % (measured 0.05 %), and the run from rest with the same layers within 0.1 % (0.01 %);
* on another mesh the state is not taken: the run starts from rest (stats ``warm_start`` 0);
* a state computed on the refined fallback's mesh starts the run on that mesh.

The store keeps the state bit for bit (``Store.load_state``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rubberfriction.driver.runtime.store import Store, run_key
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.sinusoid import layered_strip_mu
from rubberfriction.driver.sliding.spec import InitialState, SlidingSpec
from rubberfriction.forms.material_files import load_compound

TREAD = load_compound("tread_default")
T_REF = TREAD.wlf.T_ref
HOT = T_REF + 20.0
AMPLITUDE, PRESSURE, VELOCITY = 0.002, 0.1, 10.0


def _spec(layer_T: float, **kw) -> SlidingSpec:
    x = np.linspace(0.0, 1.0, 129)[:-1]
    hc = 1.0 / 16
    return SlidingSpec(surface_x=x, surface_h=AMPLITUDE * np.cos(2.0 * np.pi * x), period=1.0,
                       pressure=PRESSURE, velocity=VELOCITY, compound=TREAD, h_contact=hc,
                       slide_distance=12.0, step_length=0.5 * hc, converge_tol=0.01,
                       temperature_layers=((0.2, layer_T),), keep_state=True, **kw)


@pytest.fixture(scope="module")
def from_rest():
    res = run_sliding(_spec(T_REF))
    assert res.ok and res.converged == 1.0, res.reason
    assert res.final_state is not None and res.stats["warm_start"] == 0.0
    return res


def _stored_pair(folder, from_rest, child: SlidingSpec) -> tuple[Store, str, SlidingSpec]:
    """A store holding the run from rest (the parent, with its state) and ``child`` warm-started
    from the state read back; returns the store, the parent's key and the warm spec."""
    store = Store(folder / "store")
    parent = _spec(T_REF)
    key = run_key(parent)
    store.put(key, parent, from_rest, wall_time=1.0)
    warm = dataclasses.replace(child, initial_state=InitialState.stored(store.load_state(key), key))
    store.put(run_key(warm), warm, dataclasses.replace(from_rest, final_state=None), wall_time=1.0)
    return store, key, warm


def _warm(spec: SlidingSpec, res) -> SlidingSpec:
    return dataclasses.replace(spec, initial_state=dataclasses.replace(res.final_state, source="x"))


def test_a_steady_state_slid_on_stays_steady(from_rest):
    """Same conditions: the warm run converges after exactly 4 periods (the window rule's two
    blocks of w = 2, no run-in) with mu and contact fraction of the run from rest within 0.1 %
    (measured 0.012 % and 1e-11), and it ends where a period ends (the road's offset 0 again)."""
    warm = run_sliding(_warm(_spec(T_REF), from_rest))
    assert warm.ok and warm.converged == 1.0, warm.reason
    assert warm.stats["warm_start"] == 1.0
    assert warm.stats["periods"] == 4.0
    assert from_rest.stats["periods"] > 4.0  # from rest the run-in comes on top
    assert warm.mu_force == pytest.approx(from_rest.mu_force, rel=1e-3)
    assert warm.contact_fraction == pytest.approx(from_rest.contact_fraction, rel=1e-3)
    assert warm.final_state.offset == pytest.approx(0.0, abs=1e-9) or \
        warm.final_state.offset == pytest.approx(1.0, abs=1e-9)


def test_a_warm_run_into_a_hot_layer_gives_the_layered_closed_form(from_rest):
    """A hot bottom partition (T_ref + 20 K) on the state converged at T_ref: the layered strip's
    linear viscoelastic mu within 3 % (the tolerance of the runs from rest; measured 0.05 %) and
    the run from rest under the same layers within 0.1 % (0.01 %); the hot layer moves mu by
    more than 20 %."""
    hot = _spec(HOT)
    warm = run_sliding(_warm(hot, from_rest))
    cold = run_sliding(hot)
    assert warm.ok and cold.ok and warm.converged == 1.0, (warm.reason, cold.reason)
    assert warm.stats["warm_start"] == 1.0
    exact = layered_strip_mu(TREAD, 1.0, AMPLITUDE, PRESSURE, VELOCITY, 1.0, ((0.2, HOT),), T_REF)
    assert abs(warm.mu_force - exact) < 0.03 * exact, (warm.mu_force, exact)
    assert abs(warm.mu_force - cold.mu_force) < 1e-3 * cold.mu_force, (warm.mu_force, cold.mu_force)
    assert abs(from_rest.mu_force - warm.mu_force) > 0.2 * warm.mu_force


def test_a_state_of_another_mesh_is_not_taken(from_rest):
    """Contact elements twice as short (another mesh, as in the refined fallback): the state does
    not fit, so the run starts from rest and gives what a run from rest gives, to round-off."""
    other = dataclasses.replace(_spec(T_REF), h_contact=1.0 / 32, step_length=1.0 / 64)
    warm = run_sliding(_warm(other, from_rest))
    assert warm.ok and warm.stats["warm_start"] == 0.0
    cold = run_sliding(other)
    assert warm.mu_force == pytest.approx(cold.mu_force, rel=1e-9)


def test_a_state_from_a_refined_fallback_starts_the_run_on_that_mesh(from_rest, monkeypatch):
    """A parent that converged only on the refined fallback's mesh (``InitialState.refine`` 2)
    puts that attempt first: the warm run slides on from its state there (fallback level 0,
    warm start), into the hot layer, with the mu of the refined run from rest within 0.1 %
    (measured 0.011 %).  A run that converges on a refined attempt records its refinement."""
    from rubberfriction.driver.sliding.run import Attempt, SlidingRun
    from rubberfriction.driver.sliding.spec import refined

    parent = run_sliding(refined(_spec(T_REF), 2))  # the mesh of the refined fallback
    assert parent.ok and parent.final_state.refine == 1
    hot = _spec(HOT)
    warm = run_sliding(dataclasses.replace(
        hot, initial_state=dataclasses.replace(parent.final_state, source="x", refine=2)))
    assert warm.ok, warm.reason
    assert warm.stats["warm_start"] == 1.0 and warm.stats["fallback_level"] == 0
    assert warm.stats["attempt"] == "mortar x2 mesh" and warm.final_state.refine == 2
    # the chain keeps every other attempt behind the lead, once each
    chain = SlidingRun(dataclasses.replace(hot, initial_state=warm.final_state)).attempts()
    assert chain[0] == Attempt("mortar", refine=2) and len(set(chain)) == len(chain)
    assert set(chain) == set(SlidingRun(hot).attempts())
    # the refined run from rest, as a fallback would run it
    monkeypatch.setattr(SlidingRun, "attempts", lambda self: [Attempt("mortar", refine=2)])
    cold = run_sliding(hot)
    assert cold.ok and cold.final_state.refine == 2 and cold.stats["warm_start"] == 0.0
    assert abs(warm.mu_force - cold.mu_force) < 1e-3 * cold.mu_force, (warm.mu_force, cold.mu_force)


def test_the_store_keeps_the_final_state(tmp_path, from_rest):
    """Store.put writes /state, Store.load_state gives it back bit for bit; the key of a spec
    that starts from it depends on the state's bytes."""
    store = Store(tmp_path / "store")
    spec = _spec(T_REF)
    key = run_key(spec)
    store.put(key, spec, from_rest, wall_time=1.0)
    state = InitialState.stored(store.load_state(key), key)
    kept = from_rest.final_state
    for name in ("w", "history", "sbar"):
        assert np.array_equal(getattr(state, name), getattr(kept, name))
    assert (state.offset, state.mesh, state.refine) == (kept.offset, kept.mesh, kept.refine)
    fine = dataclasses.replace(spec, slide_distance=13.0)  # another key, a state of a refined mesh
    store.put(run_key(fine), fine,
              dataclasses.replace(from_rest, final_state=dataclasses.replace(kept, refine=2)),
              wall_time=1.0)
    assert InitialState.stored(store.load_state(run_key(fine)), "x").refine == 2
    warm = dataclasses.replace(spec, initial_state=state)
    moved = dataclasses.replace(state, w=state.w + 1e-12)
    assert run_key(warm) != run_key(dataclasses.replace(spec, initial_state=moved))
    assert run_key(warm) == run_key(dataclasses.replace(spec, initial_state=state))
    plain = dataclasses.replace(spec, keep_state=False)
    store.put(run_key(plain), plain, dataclasses.replace(from_rest, final_state=None),
              wall_time=1.0)
    assert store.load_state(run_key(plain)) is None and store.load_state("0" * 64) is None


def test_a_warm_run_is_rebuilt_from_the_store(tmp_path, from_rest):
    """``rubberfriction rerun`` of a warm-started run: its spec is rebuilt with the initial state
    read back from the run it came from (same key); without that run the error names it."""
    from rubberfriction.driver.multiscale.specs import stored_spec

    store, parent, warm = _stored_pair(tmp_path, from_rest, _spec(HOT))
    rebuilt = stored_spec(store.load(run_key(warm)), states=store.load_state)
    assert run_key(rebuilt) == run_key(warm)
    store.remove(parent)
    with pytest.raises(ValueError, match=f"final state of run {parent[:12]}"):
        stored_spec(store.load(run_key(warm)), states=store.load_state)


def test_a_frictional_run_slides_on_with_its_stick_history():
    """With friction (mu 0.5) the state carries the contact's committed tangential elastic gaps
    (nonzero on the contact nodes: the traction mu p over c_T where they slip); the warm run
    starts from exactly them (read back when sliding starts), converges after 4 periods and
    keeps the mu of the run from rest within 0.1 %."""

    class Gap:
        def on_start(self, run):
            self.gap = run.contact.elastic_gap()

    spec = _spec(T_REF, friction=0.5)
    rest = run_sliding(spec)
    assert rest.ok and rest.converged == 1.0, rest.reason
    kept = rest.final_state.elastic_gap
    assert kept.size and np.count_nonzero(kept) > kept.size // 2
    seen = Gap()
    warm = run_sliding(_warm(spec, rest), observers=[seen])
    assert warm.ok and warm.stats["warm_start"] == 1.0 and warm.stats["periods"] == 4.0
    assert np.array_equal(seen.gap, kept)
    assert warm.mu_force == pytest.approx(rest.mu_force, rel=1e-3)


def test_rerun_from_rest_drops_the_initial_state(tmp_path, from_rest, capsys):
    """``rubberfriction rerun DIR KEY --from-rest``: the warm run of the store again, from rest;
    it reports the result of the run from rest (same inputs otherwise)."""
    import json

    from rubberfriction.driver.cli.main import main

    _, _, warm = _stored_pair(tmp_path, from_rest, _spec(T_REF))
    out = tmp_path / "rerun.json"
    args = ["rerun", str(tmp_path), run_key(warm)[:10], "--from-rest", "--json", str(out)]
    assert main(args) == 0
    rerun = json.loads(out.read_text())
    assert rerun["rerun"]["stats"]["warm_start"] == 0.0
    assert rerun["rerun"]["mu_force"] == pytest.approx(from_rest.mu_force, rel=1e-9)
