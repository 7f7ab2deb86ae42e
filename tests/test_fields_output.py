"""Outputs people open elsewhere (issue 45 item 5): XDMF fields of chosen campaign runs, and the
PSD/HDC arrays of ``surface analyse --json``.

* ``run SCENE --fields SELECT`` reruns the selected stored runs with the field writer into
  ``<output>/fields/<point>_<branch>_<scale>_s<sample>/``: the .h5 holds a displacement function
  per output step with one row per mesh node (XDMF pads the plane-strain 2-vector to 3
  components, the third exactly 0); the rerun is the stored run again (deterministic: its
  mu_force equals the stored one within 1e-9 relative; on the same code and machine it is bit
  for bit).  A selection that names no scale, sample or branch of the scene is one line naming
  ``--fields``.  ``rerun FOLDER KEY --fields DIR --fields-every N`` writes every N-th step.
* ``surface analyse --json``: ``psd.q_1_per_mm`` / ``psd.C1D_mm3`` are the N/2 bins of the
  record (q_k = 2 pi k / L) and ``hdc`` the lags; without window and with mean detrending the
  PSD's integral 2 sum C1D dq is the written rms_height^2 exactly (Parseval, psd.py) within
  1e-12 relative; with the default periodic Hann window it holds in expectation only: for white
  noise of N points the relative spread of the windowed estimate is sqrt(2 <w^4>/<w^2>^2 / N)
  = sqrt(2 (35/18) / N) = 3.1 % at N = 4096, and the test allows 10 % (above 3 sigma).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from tiny_scenes import two_sines

from rubberfriction.driver.cli.main import main
from rubberfriction.driver.multiscale.campaign import run_scene
from rubberfriction.driver.multiscale.fields import parse_selection, write_fields
from rubberfriction.driver.scenes import SceneError, load_scene, parse_scene

#: two sines, one sample per branch, one speed: three runs of about a second in all
SCENE = two_sines("fields", [100.0])


def _scene_file(tmp_path: Path) -> Path:
    path = tmp_path / "fields.toml"
    path.write_text(SCENE.replace('name = "fields"',
                                  f'name = "fields"\noutput = "{tmp_path / "out"}"'))
    return path


def _displacements(h5: Path) -> tuple[int, list[np.ndarray]]:
    with h5py.File(h5, "r") as f:
        nodes = f["Mesh/mesh/geometry"].shape[0]
        group = f["Function/displacement"]
        return nodes, [np.asarray(group[k]) for k in group]


def test_run_fields_writes_xdmf_of_the_selected_run_and_reproduces_it(tmp_path: Path, capsys):
    scene_file = _scene_file(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--fields", "up:micro:0", "--no-theory"]) == 0
    printed = capsys.readouterr().out
    (folder,) = (out / "fields").iterdir()
    assert folder.name == "tread_default_p=0.3_v=100_up_micro_s0"
    assert f"fields: {folder} (ok" in printed
    assert (folder / "fields.xdmf").is_file() and (folder / "contact_pressure.csv").is_file()
    nodes, u = _displacements(folder / "fields.h5")
    assert len(u) >= 2
    for arr in u:
        assert arr.shape == (nodes, 3)          # one row per node, padded 2-vector
        assert np.all(arr[:, 2] == 0.0)
    assert np.max(np.abs(u[-1][:, :2])) > 0.0   # the block moved

    # the rerun is the stored run: the same mu_force (library path, which the CLI calls)
    scene = load_scene(str(scene_file))
    result = run_scene(scene, quiet=True, report=False)  # all reused from the store
    assert result is not None and result.n_reused == result.n_runs == 3
    (run,) = write_fields(result, parse_selection("up:macro:0", scene), every=2)
    stored = run.rerun.stored.values["mu_force"]
    assert run.rerun.result.ok and math.isfinite(stored)
    assert abs(run.rerun.result.mu_force - stored) <= 1e-9 * abs(stored)
    assert run.folder.name == "tread_default_p=0.3_v=100_up_macro_s0"
    _, every2 = _displacements(run.folder / "fields.h5")
    # the rerun command writes the same run's fields every 4th step: half as many outputs
    key = run.key
    assert main(["rerun", str(out), key[:8], "--fields", str(tmp_path / "f4"),
                 "--fields-every", "4"]) == 0
    assert "reproduces the stored mu_force: difference 0" in capsys.readouterr().out
    _, every4 = _displacements(tmp_path / "f4" / "fields.h5")
    assert len(every4) == len(every2) // 2


def test_field_selection_grammar(tmp_path: Path, capsys):
    scene = parse_scene(SCENE, origin="fields.toml")
    items = parse_selection("all", scene)
    assert items[0].matches({"branch": "up", "scale_name": "macro", "sample": 0})
    (item,) = parse_selection("macro:0", scene)
    assert (item.branch, item.scale, item.sample) == (None, "macro", 0)
    (item,) = parse_selection("down:micro", scene)
    assert (item.branch, item.scale, item.sample) == ("down", "micro", None)
    (item,) = parse_selection("up", scene)
    assert item.matches({"branch": "up", "scale_name": "micro", "sample": 0})
    assert not item.matches({"branch": "down", "scale_name": "micro", "sample": 0})
    for bad, words in (("meso", ["no scale 'meso'", "macro, micro"]),
                       ("up:micro:1", ["sample 1 does not exist"]),
                       ("side:micro:0", ["branch 'side'"]),
                       ("macro:x", ["sample 'x'"]), ("", ["expected all"]),
                       ("up::0", ["expected all"])):
        with pytest.raises(SceneError) as err:
            parse_selection(bad, scene)
        assert str(err.value).startswith("--fields") and all(w in str(err.value) for w in words)
    # on the command line: one line naming the option, exit 2, nothing written
    scene_file = _scene_file(tmp_path)
    capsys.readouterr()
    assert main(["run", str(scene_file), "--check", "--fields", "up:nano:0"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--fields 'up:nano:0'" in err and "Traceback" not in err
    assert main(["run", str(scene_file), "--check", "--fields", "up", "--fields-every",
                 "0"]) == 2
    assert "--fields-every 0" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_surface_analyse_json_holds_the_psd_and_hdc_arrays(tmp_path: Path):
    rng = np.random.default_rng(45)
    n, dx = 4096, 0.01
    h = rng.normal(0.0, 0.05, n)
    prof = tmp_path / "white.csv"
    np.savetxt(prof, np.column_stack([np.arange(n) * dx, h]), delimiter=",")
    exact = tmp_path / "exact.json"
    assert main(["surface", "analyse", str(prof), "--window", "none", "--detrend", "mean",
                 "--json", str(exact)]) == 0
    doc = json.loads(exact.read_text())
    q, c = np.array(doc["psd"]["q_1_per_mm"]), np.array(doc["psd"]["C1D_mm3"])
    assert q.size == c.size == n // 2
    assert q[0] == pytest.approx(2 * math.pi / (n * dx), rel=1e-12)
    assert np.allclose(np.diff(q), q[0], rtol=1e-9)
    lam, ch = np.array(doc["hdc"]["lambda_mm"]), np.array(doc["hdc"]["C_HDC_mm2"])
    assert lam.size == ch.size > 10 and np.all(np.diff(lam) > 0) and np.all(ch > 0)
    rms2 = doc["rms_height_mm"] ** 2
    assert abs(2.0 * np.sum(c) * q[0] - rms2) <= 1e-12 * rms2      # Parseval, exact
    hann = tmp_path / "hann.json"
    assert main(["surface", "analyse", str(prof), "--json", str(hann)]) == 0
    doc = json.loads(hann.read_text())
    assert doc["psd"]["window"] == "hann"
    q, c = np.array(doc["psd"]["q_1_per_mm"]), np.array(doc["psd"]["C1D_mm3"])
    assert abs(2.0 * np.sum(c) * q[0] / doc["rms_height_mm"] ** 2 - 1.0) < 0.10
