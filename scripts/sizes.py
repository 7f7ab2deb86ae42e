#!/usr/bin/env python3
"""Print the largest class and the largest function of each package, with their line counts.

Why: issue 46 asks that no class or function grow beyond what one reader holds in mind; this
script names the largest of each package (driver/<pkg>, forms, meshes, src) so the closing note
and later reviews can quote them.  Sizes are source lines from the ``def``/``class`` line
(decorators excluded) to the last line of the body, measured with ``ast``.  Methods count as
functions; nested functions count on their own as well as inside their parent.

Usage: ``/usr/bin/python3 scripts/sizes.py [ROOT]`` (ROOT defaults to the checkout).
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path
from typing import Iterator, List, Optional, Tuple

Entry = Tuple[int, str]  # (lines, "path:line name")


def packages(root: Path) -> List[Tuple[str, Path]]:
    """The packages to measure: each driver/<pkg>, then forms, meshes and src."""
    found = [(f"driver/{p.name}", p) for p in sorted((root / "driver").iterdir())
             if p.is_dir() and (p / "__init__.py").exists()]
    found += [(name, root / name) for name in ("forms", "meshes", "src")]
    return found


def definitions(tree: ast.AST) -> Iterator[Tuple[str, ast.AST]]:
    """Yield ("class" | "function", node) for every class and function in a module tree."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            yield "class", node
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield "function", node


def largest(pkg_dir: Path, root: Path) -> Tuple[Optional[Entry], Optional[Entry]]:
    """The largest class and the largest function under one package directory."""
    best = {"class": None, "function": None}
    for path in sorted(pkg_dir.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for kind, node in definitions(tree):
            size = node.end_lineno - node.lineno + 1
            where = f"{path.relative_to(root)}:{node.lineno} {node.name}"
            if best[kind] is None or size > best[kind][0]:
                best[kind] = (size, where)
    return best["class"], best["function"]


def show(entry: Optional[Entry]) -> str:
    """One column of the table: 'lines  path:line name', or '-' when there is none."""
    return "-" if entry is None else f"{entry[0]:5d}  {entry[1]}"


def main(argv: List[str]) -> int:
    """Print one line per package: largest class, then largest function."""
    root = Path(argv[1]) if len(argv) > 1 else Path(__file__).resolve().parent.parent
    for name, pkg_dir in packages(root):
        cls, func = largest(pkg_dir, root)
        print(f"{name:22s} class    {show(cls)}")
        print(f"{'':22s} function {show(func)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
