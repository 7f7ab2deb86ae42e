"""Shared test set-up: the repository's own reference data (the package is imported installed, see
scripts/setup.sh).

Every file a test reads is in the repository: the pyvisco DMA/Prony files in ``tests/data/``
(see its README) and the CAPTIF scan as the gzip copy the package ships in
``driver/surfaces/data/``.  The ``shared_data`` fixture gathers them, uncompressed, in one
temporary folder laid out like the project's ``../shared/data``.  A missing file is a broken
checkout: under CI (``CI=true``, set by ``.ci/run``) the test fails, elsewhere it is skipped
with the reason.
"""

from __future__ import annotations

import gzip
import hashlib
import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TEST_DATA = ROOT / "tests" / "data"
EMBEDDED_CAPTIF = ROOT / "driver" / "surfaces" / "data" / "captif_chipseal_station0.dat.gz"

#: sha256 of the original, uncompressed files (``../shared/data``); the copies must be identical.
SHA256 = {
    "captif_chipseal_station0.dat":
        "ea097ad417d64eeb9dd7db2ad5eb7ed5f1f4410d57a00ea336ae76a7fd88f52a",
    "pyvisco_freq_master.csv": "bd8d877ba95bba874ec927afcc5ddc64373688738acb03b6ae661497dc764810",
    "pyvisco_time_user_master.csv":
        "a925a5b1906af78f31d7bb61301b158cc38bd34081fc8368a0b279075511077b",
    "pyvisco_prony_terms_KPf_MD.csv":
        "969243a958babc9ed8875bae9a085bcbcb50d5497200bc50db4a5b60a6d74248",
    "pyvisco_freq_master_shift_factors.csv":
        "61347b02bf8ea0f77c8fc110487c7fa8627d851c5eddb4073cb49677ab2fc3d5",
}


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("true", "1", "yes")


def missing(reason: str) -> None:
    """A prerequisite that the repository or scripts/setup.sh provides is absent: fail under CI,
    skip (with the reason) elsewhere."""
    if in_ci():
        pytest.fail(f"{reason} (CI=true: required)", pytrace=False)
    pytest.skip(reason)


def sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


@pytest.fixture(scope="session")
def shared_data(tmp_path_factory) -> Path:
    """Folder with the real measurements (CAPTIF scan, pyvisco DMA data), each file checked
    against the sha256 of the original."""
    sources = {name: TEST_DATA / name for name in SHA256}
    sources["captif_chipseal_station0.dat"] = EMBEDDED_CAPTIF
    absent = [str(p) for p in sources.values() if not p.is_file()]
    if absent:
        missing(f"test data missing from the checkout: {', '.join(absent)}")
    out = tmp_path_factory.mktemp("shared_data")
    for name, src in sources.items():
        dst = out / name
        if src.suffix == ".gz":
            with gzip.open(src, "rb") as fin, open(dst, "wb") as fout:
                shutil.copyfileobj(fin, fout)
        else:
            shutil.copyfile(src, dst)
        got = sha256(dst)
        assert got == SHA256[name], \
            f"{src}: sha256 {got} differs from the original's {SHA256[name]}"
    return out
