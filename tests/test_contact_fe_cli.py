"""``rubberfriction verify patch ... --json FILE`` runs the same code as the tests."""

from __future__ import annotations

import json

from rubberfriction.driver.cli.main import main


def test_verify_patch_cli_json(tmp_path, capsys):
    out = tmp_path / "patch.json"
    rc = main(["verify", "patch", "--n-upper", "6", "--n-lower", "5", "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["case"] == "patch" and data["parameters"]["n_upper"] == 6
    assert all(c["passed"] for c in data["checks"])
    assert "contact pressure" in capsys.readouterr().out
