"""The generated docs pages stay what their generator makes of the code.

``docs/scene-reference.md`` is written by ``rubberfriction scene reference`` from the scene
schema (``driver/scenes/schema.py``, SCHEMA and UNITS): a key added, renamed, re-defaulted
or re-bounded in the schema without regenerating the page fails here, naming the command.
"""

from __future__ import annotations

from pathlib import Path

from rubberfriction.driver.cli.main import main
from rubberfriction.driver.cli.scene import REGENERATE, SECTION_INTRO, reference_markdown
from rubberfriction.driver.scenes import SCHEMA, UNITS

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "scene-reference.md"

#: kinds of key that hold real numbers (each needs a unit, "1" when dimensionless)
REAL_KINDS = ("float", "floats", "opt_float", "cutoff")


def test_committed_scene_reference_is_current(tmp_path: Path) -> None:
    """The command line writes exactly the committed page."""
    out = tmp_path / "scene-reference.md"
    assert main(["scene", "reference", "--out", str(out)]) == 0
    assert out.read_text() == PAGE.read_text(), (
        f"docs/scene-reference.md is out of date with the scene schema; regenerate it from the "
        f"repository root: {REGENERATE}")


def test_every_key_is_in_the_page_with_its_default_and_unit() -> None:
    """Each schema key has one table row naming it, its default and its unit."""
    text = reference_markdown()
    rows = [line for line in text.splitlines() if line.startswith("| `")]
    assert len(rows) == sum(len(keys) for keys in SCHEMA.values())
    for section, keys in SCHEMA.items():
        heading = f"## [{section}]\n" if section else "## top level\n"
        block = text.split(heading)[1].split("\n## ")[0]
        for name, key in keys.items():
            row = next(r for r in block.splitlines() if r.startswith(f"| `{name}` |"))
            cells = [c.strip() for c in row.strip("|").split(" | ")]
            assert cells[3] == key.unit, (section, name)
    assert "| `pressures` | list of numbers | `[0.3]` | MPa | non-empty, each (0, 1000] |" in text
    assert "| `grading` | number | `1.2` | 1 | [1, 3] |" in text


def test_every_real_valued_key_states_its_unit() -> None:
    """A new number key needs an entry in scene.UNITS; a unit of a non-number key is an error."""
    missing = [f"[{s}].{n}" for s, keys in SCHEMA.items() for n, k in keys.items()
               if k.kind in REAL_KINDS and not k.unit]
    assert not missing, f"add these keys to UNITS in driver/scenes/schema.py: {missing}"
    for where in UNITS:
        section, name = where[1:].split("].")
        assert SCHEMA[section][name].kind in REAL_KINDS, where


def test_every_table_has_an_introduction() -> None:
    assert set(SECTION_INTRO) == set(SCHEMA)
