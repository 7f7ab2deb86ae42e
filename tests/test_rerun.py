"""``rubberfriction rerun FOLDER KEY``: a stored run rebuilt from its run file and run again.

* Reproducibility: a real FE run (viscoelastic sinusoid, one period) stored under its key and
  rerun from the store gives the same mu_force bit for bit (same code, same machine: the run
  is deterministic), and the rebuilt spec has the stored key.
* The rerun options (first attempt only, another contact formulation, another volumetric
  energy) run that attempt.
* Inputs a run file cannot rebuild are refused with the reason: a friction law object, a
  compound whose file changed since the run; an unknown or ambiguous key.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from rubberfriction.driver.cli.main import main
from rubberfriction.driver.fe.friction_law import fit_mu_pv
from rubberfriction.driver.multiscale.specs import find_key, stored_spec
from rubberfriction.driver.runtime.store import Store, run_key
from rubberfriction.driver.sliding.run import run_sliding
from rubberfriction.driver.sliding.spec import SlidingResult, SlidingSpec
from rubberfriction.forms import material_files
from rubberfriction.forms.material_files import load_compound


def sinusoid_spec(**kw) -> SlidingSpec:
    x = np.linspace(0.0, 1.0, 65)[:-1]
    base = dict(surface_x=x, surface_h=0.002 * np.cos(2.0 * np.pi * x), period=1.0, pressure=0.1,
                velocity=10.0, compound=load_compound("tread_default"), h_contact=1.0 / 12,
                slide_distance=1.0, window_start=0.5)
    base.update(kw)
    return SlidingSpec(**base)


def put(store: Store, spec: SlidingSpec, result: SlidingResult) -> str:
    key = run_key(spec)
    store.put(key, spec, result, wall_time=1.0,
              label={"point": "test", "branch": "down", "scale_name": "s0", "sample": 0})
    return key


def test_a_stored_run_reruns_bit_for_bit(tmp_path: Path, capsys):
    spec = sinusoid_spec()
    result = run_sliding(spec)
    assert result.ok, result.reason
    store = Store(tmp_path / "store")
    key = put(store, spec, result)
    rebuilt = stored_spec(store.load(find_key(store, key[:8])))
    assert run_key(rebuilt) == key
    out = tmp_path / "rerun.json"
    assert main(["rerun", str(tmp_path), key[:8], "--json", str(out),
                 "--out", str(tmp_path / "o")]) == 0
    doc = json.loads(out.read_text())
    assert doc["rerun"]["mu_force"] == result.mu_force  # bit for bit
    assert "reproduces the stored mu_force: difference 0" in capsys.readouterr().out
    assert (tmp_path / "o" / "mu.png").is_file() and (tmp_path / "o" / "series.csv").is_file()
    # another formulation, first attempt only: that attempt ran
    assert main(["rerun", str(tmp_path / "store"), key[:8], "--contact", "surface",
                 "--first-attempt", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["contact"] == "surface" and doc["rerun"]["stats"]["attempt"] == "surface"
    # the other volumetric energy: the same small-strain K, so on this 2 um sinusoid the same mu
    # within 1 % (the strains are 1e-2), and no claim to reproduce the stored run
    other = {"quadratic": "logarithmic", "logarithmic": "quadratic"}[
        spec.compound.hyperelastic.volumetric]
    capsys.readouterr()
    assert main(["rerun", str(tmp_path), key[:8], "--volumetric", other, "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["rerun"]["mu_force"] == pytest.approx(result.mu_force, rel=1e-2)
    assert doc["rerun"]["mu_force"] != result.mu_force
    assert "reproduces" not in capsys.readouterr().out


def test_inputs_that_cannot_be_rebuilt_are_refused(tmp_path: Path, capsys):
    store = Store(tmp_path / "store")
    p, v = np.linspace(0.0, 1.0, 5), np.logspace(0, 3, 5)
    law = fit_mu_pv(p, v, 0.5 + 0.0 * p[:, None] * v[None, :])
    k_law = put(store, sinusoid_spec(friction=law), SlidingResult("failed", reason="not run"))
    with pytest.raises(ValueError, match="friction is a .* law"):
        stored_spec(store.load(k_law))
    comp = load_compound("tread_default")
    changed = dataclasses.replace(comp, hyperelastic=dataclasses.replace(comp.hyperelastic,
                                                                         C10=0.17574))
    k_comp = put(store, sinusoid_spec(compound=changed), SlidingResult("failed", reason="not run"))
    with pytest.raises(ValueError, match="compound file changed"):
        stored_spec(store.load(k_comp))
    # the folder keeps the compound file as the run had it: taken before the shipped one
    kept = tmp_path / "compounds"
    kept.mkdir()
    with pytest.raises(ValueError, match="compound file changed"):  # no file there: the shipped one
        stored_spec(store.load(k_comp), compound_dir=kept)
    text = (material_files.DATA_DIR / "tread_default.toml").read_text()
    assert text.count("C10 = 0.174  #") == 1
    (kept / "tread_default.toml").write_text(text.replace("C10 = 0.174  #", "C10 = 0.17574  #"))
    assert stored_spec(store.load(k_comp), compound_dir=kept).compound == changed
    assert main(["rerun", str(tmp_path), "zzzzzzzz"]) == 2
    assert "no such run" in capsys.readouterr().err
    assert main(["rerun", str(tmp_path), k_law[:3]]) == 2
    assert "at least 6 characters" in capsys.readouterr().err


FAILING = Path(__file__).parent / "data" / "failing_runs"


@pytest.mark.parametrize("prefix,pressure", [("6b9a9635", 7.647690314749106),
                                             ("f280d52c", 7.647690314749106)])
def test_the_kept_failing_inputs_rebuild_exactly(prefix, pressure):
    """The default scene's failing micro2 runs (issue 14's regression inputs) rebuild from their
    run files: every field equal to the stored canonical image (stored_spec checks it)."""
    store = Store(FAILING)
    spec = stored_spec(store.load(find_key(store, prefix)), compound_dir=FAILING / "compounds")
    assert (spec.pressure == pressure and spec.friction is None
            and spec.period == pytest.approx(0.04))
    # written before the volumetric energy was a choice: rebuilt with what they computed with
    assert spec.compound.hyperelastic.volumetric == "quadratic"


def test_overrides_are_checked(tmp_path: Path, capsys):
    assert main(["rerun", str(FAILING), "6b9a9635", "--set", "no_such_field=1"]) == 2
    assert "SlidingSpec field" in capsys.readouterr().err
    assert main(["rerun", str(FAILING), "6b9a9635", "--set", "steady_state=maybe"]) == 2
    assert "not true or false" in capsys.readouterr().err
