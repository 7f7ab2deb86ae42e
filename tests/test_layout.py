"""The dependency rule of the layout (README "Layout"), checked on every import statement.

Command line and benchmarks on top, physics at the bottom; dependencies point one way:

    cli -> bench, study -> verification -> multiscale -> sliding -> fe -> forms, meshes
                                    forms, meshes -> rubberfriction
                                    multiscale -> thermal -> sliding, theory
                                    multiscale -> runtime, surfaces, theory, adhesion
                                    multiscale -> scenes -> surfaces, theory, forms
                                    adhesion -> theory -> surfaces
                                                theory -> forms (the Prony modulus)

Nothing imports ``cli``; only ``cli`` imports ``bench``; ``study`` (the trend study, which
runs a verification case as one of its rows) sits beside ``bench``; production code never
imports ``verification``; ``forms`` and ``meshes`` import nothing from ``driver``.  Function-local
imports count like module-level ones.

The Python API ``rubberfriction.api`` sits beside ``cli`` on top (a facade: it may import every
layer but ``cli`` and ``bench``); the package's ``__init__`` imports it only lazily, inside its
PEP 562 ``__getattr__`` (the one import of a higher layer the root may make).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = {"src/rubberfriction": "rubberfriction", "forms": "rubberfriction.forms",
           "meshes": "rubberfriction.meshes", "driver": "rubberfriction.driver"}

#: layer -> the project layers its modules may import (besides their own layer)
ALLOWED: dict[str, set[str]] = {
    "root": set(),
    "forms": {"root"},
    "meshes": {"root"},
    "surfaces": {"root"},
    "theory": {"root", "surfaces", "forms"},
    "adhesion": {"root", "surfaces", "theory"},
    "runtime": {"root"},
    "fe": {"root", "forms", "meshes"},
    "sliding": {"root", "forms", "meshes", "fe"},
    "thermal": {"root", "forms", "meshes", "fe", "sliding", "theory", "surfaces"},
    "scenes": {"root", "surfaces", "theory", "forms"},
    "multiscale": {"root", "forms", "meshes", "fe", "sliding", "thermal", "runtime", "surfaces",
                   "theory", "adhesion", "scenes"},
    "verification": {"root", "forms", "meshes", "fe", "sliding", "thermal", "runtime", "surfaces",
                     "theory", "adhesion", "scenes", "multiscale"},
    "bench": {"root", "forms", "meshes", "fe", "sliding", "thermal", "runtime", "surfaces",
              "theory", "adhesion", "scenes", "multiscale", "verification"},
    "cli": {"root", "forms", "meshes", "fe", "sliding", "thermal", "runtime", "surfaces", "theory",
            "adhesion", "scenes", "multiscale", "verification", "bench", "study"},
}
ALLOWED["study"] = ALLOWED["bench"]
ALLOWED["api"] = ALLOWED["cli"] - {"bench"}
#: module -> layers it may import besides ALLOWED (lazily: the package exposes the API, PEP 562)
FACADE: dict[str, set[str]] = {"rubberfriction": {"api"}}


def layer_of(module: str) -> str | None:
    """The layer of a module name (None: not a project module)."""
    parts = module.split(".")
    if parts[0] != "rubberfriction":
        return None
    if module in ("rubberfriction.__main__", "rubberfriction.driver"):
        return "cli" if parts[1] == "__main__" else "root"  # the command; an empty package
    if len(parts) > 1 and parts[1] == "api":
        return "api"
    if len(parts) == 1 or parts[1] in ("validation", "_contact"):
        return "root"
    if parts[1] in ("forms", "meshes"):
        return parts[1]
    if parts[1] == "driver" and len(parts) > 2:
        return parts[2]
    raise AssertionError(f"{module}: not in a layer of the rule")


def modules() -> list[tuple[str, Path]]:
    out = []
    for folder, package in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT / folder).with_suffix("")
            parts = [p for p in rel.parts if p != "__init__"]
            out.append((".".join([package, *parts]), path))
    return out


def imported_modules(module: str, path: Path) -> list[tuple[int, str]]:
    """Every project module an import statement of the file names (absolute, resolved)."""
    found = []
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            # "from pkg import name" may import a submodule: count both
            found.append((node.lineno, base))
            found += [(node.lineno, f"{base}.{a.name}") for a in node.names]
    return [(n, m) for n, m in found if m.startswith("rubberfriction")]


def test_the_rule_covers_every_driver_folder() -> None:
    folders = {p.name for p in (ROOT / "driver").iterdir() if (p / "__init__.py").is_file()}
    assert folders == set(ALLOWED) - {"root", "forms", "meshes", "api"}


@pytest.mark.parametrize("module,path", modules(), ids=[m for m, _ in modules()])
def test_imports_follow_the_dependency_rule(module: str, path: Path) -> None:
    own = layer_of(module)
    bad = []
    for line, name in imported_modules(module, path):
        target = layer_of(name)
        if target is None or target == own or target in ALLOWED[own] \
                or target in FACADE.get(module, set()):
            continue
        bad.append(f"{path.relative_to(ROOT)}:{line}: {own} imports {name} ({target})")
    assert not bad, "\n".join(bad)


def test_the_checker_sees_a_violation(tmp_path: Path) -> None:
    """The parser finds a function-local import of cli/ from production code."""
    bad = tmp_path / "x.py"
    bad.write_text("def f():\n    from rubberfriction.driver.cli import main\n")
    names = [m for _, m in imported_modules("rubberfriction.driver.fe.x", bad)]
    assert "rubberfriction.driver.cli" in names and layer_of(names[0]) == "cli"
    assert "cli" not in ALLOWED["fe"]


def test_the_api_is_a_facade_beside_cli() -> None:
    """The API module is its own layer: it may not import cli or bench, nothing but the
    package's __init__ (lazily) may import it, and that __init__ does import it."""
    assert layer_of("rubberfriction.api") == "api"
    assert not {"cli", "bench"} & ALLOWED["api"]
    assert all("api" not in allowed for allowed in ALLOWED.values())
    init = ROOT / "src" / "rubberfriction" / "__init__.py"
    assert ("rubberfriction.api" in [m for _, m in imported_modules("rubberfriction", init)])
