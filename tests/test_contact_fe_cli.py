"""``rubberfriction verify patch ... --json FILE`` runs the same code as the tests: its JSON holds
the computed values, checked here against the patch test's closed form (see
``test_contact_fe_patch.py``): contact pressure = -sigma_zz = q/lambda_x of the homogeneous
plane-strain solution, total force q L, every slave node in contact."""

from __future__ import annotations

import json

from fe_helpers import checks_of, plane_strain_compression, rel
from rubberfriction.driver.cli.main import main


def test_verify_patch_cli_json(tmp_path, capsys):
    out = tmp_path / "patch.json"
    rc = main(["verify", "patch", "--n-upper", "6", "--n-lower", "5", "--E", "10", "--nu", "0.3",
               "--pressure", "0.1", "--length", "1", "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["case"] == "patch" and data["parameters"]["n_upper"] == 6
    assert data["parameters"]["method"] == "mortar"
    by = checks_of(data, {"slave nodes in contact", "contact pressure min", "contact pressure max",
                          "total contact force F_z", "sigma_zz upper (max dev.)",
                          "sigma_zz lower (max dev.)"})
    lam_x, _ = plane_strain_compression(10.0, 0.3, 0.1)
    p_exact = 0.1 / lam_x
    assert by["slave nodes in contact"]["computed"] == 7
    assert rel(by["contact pressure min"]["computed"], p_exact) <= 1e-10  # product: 1e-8
    assert rel(by["contact pressure max"]["computed"], p_exact) <= 1e-10
    assert rel(by["total contact force F_z"]["computed"], 0.1 * 1.0) <= 1e-10
    assert rel(by["sigma_zz upper (max dev.)"]["computed"], -p_exact) <= 1e-10
    assert rel(by["sigma_zz lower (max dev.)"]["computed"], -p_exact) <= 1e-10
    assert "contact pressure" in capsys.readouterr().out
