"""The README's first run: ``rubberfriction run first`` finishes and writes what the README says.

A smoke test of the shipped scene ``first`` through the command line (seconds): exit status 0,
6 single-scale runs none failed, and the files the README lists (summary.txt, results.csv,
scales.csv, samples.csv, mu_v.png) with one result row per speed.  The physics of its runs is
pinned elsewhere (the viscoelastic sinusoid and the cascade tests); mu is only required finite
and positive here.
"""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path


def test_first_scene_runs_and_writes_the_readme_files(tmp_path: Path) -> None:
    out = tmp_path / "first"
    r = subprocess.run([sys.executable, "-m", "rubberfriction", "run", "first", "--out", str(out),
                        "--quiet"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    for name in ("summary.txt", "results.csv", "scales.csv", "samples.csv", "mu_v.png"):
        assert (out / name).is_file(), name
    assert "6 single-scale runs (0 reused, 0 failed)" in (out / "summary.txt").read_text()
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert sorted(float(row["velocity_mm_s"]) for row in rows) == [10.0, 100.0]
    assert all(math.isfinite(float(row["mu"])) and float(row["mu"]) > 0 for row in rows)
