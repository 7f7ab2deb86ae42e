"""Readers for line-scan profiles: delimited text (optionally gzip-compressed) and HDF5.

The text reader detects what it is not told: the delimiter (tab, comma, semicolon or white
space), the number of header lines (the leading lines that are not rows of numbers), the
columns (from header names such as ``Distance (mm)`` / ``Depth (mm)``, or by count) and the units
written in the header (``(mm)``, ``[um]``, ...).  The CAPTIF stationary laser profiler format
(11 header lines, then ``point, distance (mm), depth (mm)``, tab-separated, NaN dropouts) loads
as it is.  CAPTIF's "Depth" column increases upwards (the reference plate lying on the road reads
about +47 mm, and captif-slp treats it as relative height), so it is used as height h directly;
pass ``invert=True`` for formats whose depth increases downwards.

HDF5 files are read with h5py: a dataset of heights (``dataset=``) with positions from a second
dataset (``x_dataset=``) or a spacing (``dx=`` or a ``dx``/``spacing`` attribute), or one
N x 2 / N x 3 table.  Units come from a ``units`` attribute when present.

After reading, :func:`load_profile` converts to millimetres and (by default) cleans the profile
with :func:`rubberfriction.driver.surfaces.defects.clean_profile`; the defect report is in
``profile.meta["defects"]``.
"""

from __future__ import annotations

import gzip
import io
import re
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rubberfriction.driver.surfaces.defects import DEFAULT_SENTINELS, clean_profile
from rubberfriction.driver.surfaces.errors import ProfileFormatError, SurfaceError
from rubberfriction.driver.surfaces.profile import Profile, unit_factor

_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$|^[+-]?(nan|inf|infinity)$", re.I)
_UNIT_IN_NAME = re.compile(r"[\(\[]\s*(mm|µm|μm|um|nm|cm|m|micron|microns|in)\s*[\)\]]", re.I)
_X_NAMES = ("distance", "position", "x", "length", "pos", "s")
_H_NAMES = ("depth", "height", "h", "z", "elevation", "profile", "y")

Units = str | tuple[str, str] | None


def _is_hdf5(path: Path) -> bool:
    if path.suffix.lower() in (".h5", ".hdf5", ".he5", ".hdf"):
        return True
    try:
        with open(path, "rb") as f:
            return f.read(8) == _HDF5_MAGIC
    except OSError:
        return False


def _read_lines(path: Path) -> list[str]:
    opener = gzip.open if path.suffix.lower() == ".gz" else open
    try:
        with opener(path, "rb") as f:
            raw = f.read()
    except FileNotFoundError:
        raise ProfileFormatError(f"profile file not found: {path}") from None
    except OSError as err:
        raise ProfileFormatError(f"cannot read {path}: {err}") from None
    text = raw.decode("utf-8", errors="replace")
    return text.splitlines()


def _split(line: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return line.split()
    parts = [p.strip() for p in line.split(delimiter)]
    while parts and parts[-1] == "":  # trailing delimiter
        parts.pop()
    return parts


def _is_numeric_row(tokens: list[str]) -> bool:
    return bool(tokens) and all(_NUMBER.match(t) for t in tokens)


def _detect_delimiter(lines: list[str]) -> str | None:
    """Most plausible delimiter among tab, comma, semicolon and white space (None)."""
    sample = [ln for ln in lines[-200:] if ln.strip()][:200] or lines[:50]
    best: tuple[int, int, str | None] = (-1, 0, None)
    for cand in ("\t", ",", ";", None):
        counts = [len(_split(ln, cand)) for ln in sample]
        numeric = sum(_is_numeric_row(_split(ln, cand)) for ln in sample)
        width = max(set(counts), key=counts.count) if counts else 0
        score = (numeric, width if width > 1 else 0, cand)
        if score[:2] > best[:2]:
            best = score
    return best[2]


def _detect_header(lines: list[str], delimiter: str | None, need: int = 3) -> int:
    """Number of leading lines before ``need`` consecutive numeric rows of equal width."""
    run, width = 0, -1
    for i, ln in enumerate(lines):
        tokens = _split(ln, delimiter)
        if _is_numeric_row(tokens) and (run == 0 or len(tokens) == width):
            run += 1
            width = len(tokens)
            if run == need:
                return i - need + 1
        elif _is_numeric_row(tokens):
            run, width = 1, len(tokens)
        else:
            run, width = 0, -1
    if run > 0:  # a very short file
        return len(lines) - run
    raise ProfileFormatError("no rows of numbers found (empty file or not a profile)")


def _column_index(spec: int | str, names: list[str], what: str) -> int:
    """The 0-based index of column ``spec`` (an index or a header name) of the ``what`` (x or h)
    column; a bad one is named as the keyword argument ``x_col`` / ``h_col``."""
    if isinstance(spec, (int, np.integer)):
        if not 0 <= spec < max(len(names), 1) and names:
            raise ProfileFormatError(f"{what}_col = {spec}: expected a column index from 0 to "
                                     f"{len(names) - 1} ({len(names)} columns)")
        return int(spec)
    key = spec.strip().lower()
    for i, nm in enumerate(names):
        if nm.lower() == key:
            return i
    for i, nm in enumerate(names):
        if key in nm.lower():
            return i
    raise ProfileFormatError(f"{what}_col = {spec!r}: expected a column index or one of the "
                             f"header columns {names}")


def _guess_columns(names: list[str], ncol: int, first_rows: np.ndarray) -> tuple[int | None, int]:
    """(x column or None, h column) from header names or the column count."""
    low = [re.sub(r"[\(\[].*", "", n).strip().lower().rstrip(":") for n in names]
    xi = next((i for i, n in enumerate(low) for k in _X_NAMES if n == k or n.startswith(k + " ")
               or (len(k) > 2 and k in n)), None) if names else None
    hi = next((i for i, n in enumerate(low) for k in _H_NAMES if (n == k or n.startswith(k + " ")
               or (len(k) > 2 and k in n)) and i != xi), None) if names else None
    if hi is not None:
        return xi, hi
    if ncol == 1:
        return None, 0
    if ncol == 2:
        return 0, 1
    if ncol == 3:
        idx = first_rows[:, 0]
        integer = np.all(np.isfinite(idx)) and np.allclose(idx, np.round(idx))
        if integer and np.all(np.diff(idx) > 0):
            return 1, 2  # point number, x, h (CAPTIF layout)
    raise ProfileFormatError(
        f"cannot tell which of the {ncol} columns are x and h; name them in a header line "
        "(e.g. 'x, h, other') or pass x_col= and h_col="
    )


def _unit_from_name(name: str) -> str | None:
    m = _UNIT_IN_NAME.search(name)
    return m.group(1) if m else None


def _resolve_units(
    units: Units, header_units: tuple[str | None, str | None]
) -> tuple[str, str, str]:
    """(x unit, h unit, note) from the declared units and the header's units."""
    if units is None or units == "auto":
        xu = header_units[0] or header_units[1] or "mm"
        hu = header_units[1] or header_units[0] or "mm"
        note = "units from header" if any(header_units) else "no units in header; assumed mm"
        return xu, hu, note
    xu, hu = (units, units) if isinstance(units, str) else units
    for declared, found, what in ((xu, header_units[0], "x"), (hu, header_units[1], "h")):
        if found and unit_factor(found) != unit_factor(declared):
            raise ProfileFormatError(
                f"the header gives {what} in {found!r} but units={declared!r} was declared; "
                "pass the right units or units='auto'"
            )
    return xu, hu, "declared"


def read_text(
    path: Path,
    *,
    delimiter: str | None = None,
    skiprows: int | None = None,
    x_col: int | str | None = None,
    h_col: int | str | None = None,
) -> tuple[np.ndarray | None, np.ndarray, dict[str, Any]]:
    """Raw columns of a delimited text file: ``(x or None, h, info)``, no unit conversion."""
    lines = _read_lines(path)
    if not any(ln.strip() for ln in lines):
        raise ProfileFormatError(f"{path}: empty file")
    lines = [ln for ln in lines if not ln.lstrip().startswith("#")] or lines
    if delimiter is None:
        delimiter = _detect_delimiter(lines)
    elif delimiter in ("whitespace", " "):
        delimiter = None
    if skiprows is None:
        try:
            skiprows = _detect_header(lines, delimiter)
        except ProfileFormatError as err:
            raise ProfileFormatError(f"{path}: {err}") from None
    header = [ln.rstrip() for ln in lines[:skiprows]]
    body = [ln for ln in lines[skiprows:] if ln.strip()]
    if not body:
        raise ProfileFormatError(f"{path}: no data rows after {skiprows} header lines")
    ncol = len(_split(body[0], delimiter))
    names: list[str] = []
    for ln in reversed(header):
        toks = _split(ln, delimiter)
        if len(toks) == ncol and not _is_numeric_row(toks):
            names = toks
            break
    try:
        data = np.loadtxt(io.StringIO("\n".join(body)), delimiter=delimiter, ndmin=2,
                          comments="#", dtype=float)
    except ValueError as err:
        raise ProfileFormatError(
            f"{path}: data rows after line {skiprows} are not a regular table of numbers: {err}"
        ) from None
    if data.shape[0] == 0:
        raise ProfileFormatError(f"{path}: no data rows")
    if x_col is None and h_col is None:
        try:
            xi, hi = _guess_columns(names, data.shape[1], data[: min(50, data.shape[0])])
        except ProfileFormatError as err:
            raise ProfileFormatError(f"{path}: {err}") from None
    else:
        try:
            hi = _column_index(h_col if h_col is not None else data.shape[1] - 1, names, "h")
            xi = None if x_col is None else _column_index(x_col, names, "x")
        except ProfileFormatError as err:
            raise ProfileFormatError(f"{path}: {err}") from None
    for c, what in ((xi, "x"), (hi, "h")):
        if c is not None and not 0 <= c < data.shape[1]:
            raise ProfileFormatError(
                f"{path}: {what}_col = {c}: expected a column index from 0 to "
                f"{data.shape[1] - 1} ({data.shape[1]} columns)"
            )
    hunit = _unit_from_name(names[hi]) if names else None
    xunit = _unit_from_name(names[xi]) if (names and xi is not None) else None
    info = {
        "format": "text",
        "delimiter": "whitespace" if delimiter is None else delimiter,
        "header_lines": skiprows,
        "header": header,
        "columns": names,
        "x_col": xi,
        "h_col": hi,
        "header_units": (xunit, hunit),
    }
    return (None if xi is None else data[:, xi]), data[:, hi], info


def read_hdf5(
    path: Path,
    *,
    dataset: str | None = None,
    x_dataset: str | None = None,
) -> tuple[np.ndarray | None, np.ndarray, dict[str, Any]]:
    """Raw arrays of an HDF5 profile: ``(x or None, h, info)``, no unit conversion."""
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError as err:
        raise ProfileFormatError(f"cannot open {path} as HDF5: {err}") from None
    with f:
        names: list[str] = []
        f.visit(lambda nm: names.append(nm) if isinstance(f[nm], h5py.Dataset) else None)
        if not names:
            raise ProfileFormatError(f"{path}: HDF5 file has no datasets")

        def pick(cands: tuple[str, ...]) -> str | None:
            for c in cands:
                for nm in names:
                    if nm.split("/")[-1].lower() == c:
                        return nm
            return None

        info: dict[str, Any] = {"format": "hdf5", "datasets": names}
        if dataset is None:
            dataset = pick(_H_NAMES)
            if dataset is None and len(names) == 1:
                dataset = names[0]
            if dataset is None:
                raise ProfileFormatError(f"{path}: which dataset holds the heights? pass dataset= "
                                         f"(datasets: {names})")
        if dataset not in f:
            raise ProfileFormatError(f"{path}: no dataset {dataset!r} (datasets: {names})")
        dset = f[dataset]
        arr = np.asarray(dset[()], dtype=float)
        attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in dset.attrs.items()}
        info["dataset"] = dataset
        info["attrs"] = {k: (v.tolist() if isinstance(v, np.ndarray) else v)
                         for k, v in attrs.items()}
        x = None
        if arr.ndim == 2 and arr.shape[1] in (2, 3):
            x, h = arr[:, -2], arr[:, -1]
        elif arr.ndim == 1:
            h = arr
            if x_dataset is None:
                x_dataset = pick(_X_NAMES)
            if x_dataset is not None:
                if x_dataset not in f:
                    raise ProfileFormatError(f"{path}: no dataset {x_dataset!r}")
                x = np.asarray(f[x_dataset][()], dtype=float)
                if x.shape != h.shape:
                    raise ProfileFormatError(
                        f"{path}: {x_dataset!r} and {dataset!r} differ in shape"
                    )
                info["x_dataset"] = x_dataset
                xattrs = f[x_dataset].attrs
                if "units" in xattrs:
                    xu = xattrs["units"]
                    info["x_units_attr"] = xu.decode() if isinstance(xu, bytes) else str(xu)
        else:
            raise ProfileFormatError(f"{path}: dataset {dataset!r} has shape {arr.shape}; expected "
                                     "(N,) heights or an (N, 2|3) table")
        for key in ("dx", "spacing", "sample_spacing"):
            if key in attrs:
                info["dx_attr"] = float(attrs[key])
        hu = attrs.get("units")
        info["header_units"] = (info.get("x_units_attr") or (str(hu) if hu else None),
                                str(hu) if hu else None)
    return x, h, info


def load_profile(
    path: str | Path,
    *,
    delimiter: str | None = None,
    skiprows: int | None = None,
    x_col: int | str | None = None,
    h_col: int | str | None = None,
    units: Units = "mm",
    dx: float | None = None,
    dataset: str | None = None,
    x_dataset: str | None = None,
    invert: bool = False,
    clean: bool = True,
    sentinels: tuple[float, ...] = DEFAULT_SENTINELS,
    outliers: bool = True,
    max_gap: float | None = None,
    long_gaps: Literal["longest", "error"] = "longest",
    max_dropout_fraction: float = 0.15,
) -> Profile:
    """Read a line-scan profile from text/CSV (optionally ``.gz``) or HDF5, in millimetres.

    Parameters
    ----------
    delimiter, skiprows:
        Column delimiter (``"\\t"``, ``","``, ``";"``, ``"whitespace"``) and header line count;
        detected when None.
    x_col, h_col:
        Column index (0-based) or header name of positions and heights; detected from the header
        names or the column count when None (3 columns with an integer first column = CAPTIF).
    units:
        Units of x and h in the file, one name or ``(x_units, h_units)``.  ``"auto"`` takes them
        from the header (``Distance (mm)``) or an HDF5 ``units`` attribute, mm when absent.  If
        the header states different units from the declared ones, a
        :class:`ProfileFormatError` is raised rather than guessing.
    dx:
        Sample spacing (file units) for files without a position column.
    dataset, x_dataset:
        HDF5 dataset names of heights and positions.
    invert:
        Multiply heights by -1 (for depth-down formats).
    clean:
        Run :func:`~rubberfriction.driver.surfaces.defects.clean_profile` (uniform grid,
        dropouts, outliers, gaps; the other keyword arguments are passed on).  With
        ``clean=False`` the raw profile (NaN kept, x as read) is returned.
    """
    path = Path(path)
    if not path.exists():
        raise ProfileFormatError(f"profile file not found: {path}")
    if path.is_file() and path.stat().st_size == 0:
        raise ProfileFormatError(f"{path}: empty file")
    if _is_hdf5(path):
        x, h, info = read_hdf5(path, dataset=dataset, x_dataset=x_dataset)
        if dx is None:
            dx = info.get("dx_attr")
    else:
        x, h, info = read_text(path, delimiter=delimiter, skiprows=skiprows, x_col=x_col,
                               h_col=h_col)
    try:
        xu, hu, unit_note = _resolve_units(units, info.get("header_units", (None, None)))
    except ProfileFormatError as err:
        raise ProfileFormatError(f"{path}: {err}") from None
    info["units_in_file"] = (xu, hu)
    info["units_note"] = unit_note
    if x is None:
        if dx is None:
            raise ProfileFormatError(f"{path}: no position column; pass dx= (sample spacing)")
        x = float(dx) * np.arange(h.size)
        info["x_from_dx"] = float(dx)
    x = np.asarray(x, dtype=float) * unit_factor(xu)
    h = np.asarray(h, dtype=float) * unit_factor(hu) * (-1.0 if invert else 1.0)
    if not np.all(np.isfinite(x)):
        k = int(np.flatnonzero(~np.isfinite(x))[0])
        raise ProfileFormatError(f"{path}: position in data row {k} is not a number")
    if x.size >= 2:
        d = np.diff(x)
        if np.all(d < 0):
            x, h = x[::-1].copy(), h[::-1].copy()
            info["reversed"] = True
        elif np.any(d <= 0):
            k = int(np.flatnonzero(d <= 0)[0])
            raise ProfileFormatError(
                f"{path}: positions are not monotonic: data row {k} has x = {x[k]:.6g} mm and row "
                f"{k + 1} has x = {x[k + 1]:.6g} mm; sort the scan or fix the file"
            )
    try:
        profile = Profile(x, h, "mm", str(path),
                          {"reader": info, "provenance": {"kind": "measured", "file": str(path)}})
    except SurfaceError as err:
        raise ProfileFormatError(f"{path}: {err}") from None
    if clean:
        profile = clean_profile(profile, sentinels=sentinels, outliers=outliers, max_gap=max_gap,
                                long_gaps=long_gaps, max_dropout_fraction=max_dropout_fraction)
    return profile
