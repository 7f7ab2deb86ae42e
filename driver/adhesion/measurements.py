"""Friction measurement files and speed curves: a quantity over sliding speed with stated units.

One file per surface condition (thesis 7.2, fig. 7.2: dry, water, soap-water) holds the measured
coefficient of friction over sliding speed; the same format carries a simulated hysteresis
curve mu_H(v) or a relative real contact area A_r(v) (eq. 7.5)::

    # compound A, dry, p = 0.2 MPa          <- comment lines start with '#'
    v [m/s], mu                             <- header: the speed with its unit, the quantity
    1e-05, 0.912
    1e-04, 1.034

* the speed column is named ``v`` (or ``speed``, ``velocity``) with its unit in brackets or
  parentheses: ``m/s``, ``mm/s``, ``um/s`` or ``km/h``; speeds are converted to mm/s, the unit
  inside the code (DESIGN.md);
* the second column is the quantity: ``mu`` (a measurement), ``mu_H`` (hysteresis) or ``A_r``
  (relative contact area); an optional ``[-]`` says it is dimensionless;
* delimiter: comma, semicolon, tab or white space (detected from the header);
* speeds are > 0, strictly ascending (no duplicates); mu >= 0; 0 < A_r <= 1; at least two rows.

Every violation raises :class:`~rubberfriction.driver.adhesion.errors.AdhesionInputError` naming
the file, the line and what is expected.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rubberfriction.driver.adhesion.errors import AdhesionInputError

#: speed unit in a file header -> factor to mm/s
SPEED_UNITS: dict[str, float] = {"m/s": 1000.0, "mm/s": 1.0, "um/s": 1e-3, "µm/s": 1e-3,
                                 "km/h": 1e6 / 3600.0}
#: quantity -> the column names accepted for it (case-insensitive)
QUANTITIES: dict[str, tuple[str, ...]] = {"mu": ("mu",), "mu_H": ("mu_h",),
                                          "A_r": ("a_r", "a/a0")}
#: surface conditions of the thesis (7.2): dry (alpha = 1), water, soap-water
CONDITIONS = ("dry", "water", "soap")

_SPEED_NAMES = ("v", "speed", "velocity", "sliding speed", "sliding velocity")
_UNIT = re.compile(r"^(?P<name>[^\[\(]*?)\s*[\[\(]\s*(?P<unit>[^\]\)]*?)\s*[\]\)]\s*$")


@dataclass(frozen=True)
class SpeedCurve:
    """A quantity over sliding speed: ``v`` in mm/s (> 0, strictly ascending) and ``values``.

    ``quantity`` is ``"mu"``, ``"mu_H"`` or ``"A_r"``; ``unit`` the speed unit the file used;
    ``notes`` its comment lines (provenance).
    """

    v: np.ndarray
    values: np.ndarray
    quantity: str
    source: str = ""
    unit: str = "mm/s"
    notes: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        where = self.source or self.quantity
        v = np.asarray(self.v, dtype=float)
        y = np.asarray(self.values, dtype=float)
        if v.ndim != 1 or v.shape != y.shape or v.size < 2:
            raise AdhesionInputError(f"{where}: expected two equally long 1-D arrays of at least "
                                     f"2 values, got shapes {v.shape} and {y.shape}")
        _check_values(where, v, y, self.quantity, lines=None)
        object.__setattr__(self, "v", v)
        object.__setattr__(self, "values", y)

    @property
    def range(self) -> tuple[float, float]:
        """Speed range (mm/s)."""
        return float(self.v[0]), float(self.v[-1])


def _check_values(where: str, v: np.ndarray, y: np.ndarray, quantity: str,
                  lines: list[int] | None) -> None:
    """Speeds > 0 and strictly ascending; mu >= 0; 0 < A_r <= 1 (``lines``: file line numbers)."""
    def at(i: int) -> str:
        return f"{where}, line {lines[i]}" if lines is not None else f"{where}[{i}]"

    for i in range(v.size):
        if not (math.isfinite(v[i]) and math.isfinite(y[i])):
            raise AdhesionInputError(f"{at(i)}: v = {v[i]!r}, {quantity} = {y[i]!r}: expected "
                                     "finite numbers")
        if v[i] <= 0:
            raise AdhesionInputError(f"{at(i)}: v = {v[i]!r}: expected a speed > 0")
        if i and v[i] == v[i - 1]:
            raise AdhesionInputError(f"{at(i)}: duplicate speed v = {v[i]!r} (also on "
                                     f"{at(i - 1)}): expected each speed once")
        if i and v[i] < v[i - 1]:
            raise AdhesionInputError(f"{at(i)}: v = {v[i]!r} after {v[i - 1]!r}: expected speeds "
                                     "sorted ascending")
        if quantity == "A_r" and not 0.0 < y[i] <= 1.0:
            raise AdhesionInputError(f"{at(i)}: A_r = {y[i]!r}: expected a relative contact area "
                                     "0 < A_r <= 1")
        if quantity != "A_r" and y[i] < 0:
            raise AdhesionInputError(f"{at(i)}: {quantity} = {y[i]!r}: expected a coefficient of "
                                     "friction >= 0")


def _delimiter(header: str) -> str | None:
    for d in (",", ";", "\t"):
        if d in header:
            return d
    return None  # white space


def _split(line: str, delimiter: str | None) -> list[str]:
    parts = line.split(delimiter) if delimiter else line.split()
    return [p.strip() for p in parts]


def _speed_unit(where: str, column: str) -> str:
    """The speed unit of the header's first column (``v [m/s]``)."""
    m = _UNIT.match(column)
    name = (m.group("name") if m else column).strip().lower()
    if name not in _SPEED_NAMES:
        raise AdhesionInputError(f"{where}: first header column {column!r}: expected the sliding "
                                 "speed with its unit, e.g. 'v [m/s]' or 'v [mm/s]'")
    if m is None or not m.group("unit"):
        raise AdhesionInputError(f"{where}: first header column {column!r} states no unit: "
                                 "expected e.g. 'v [m/s]' or 'v [mm/s]' (units: "
                                 f"{', '.join(SPEED_UNITS)})")
    unit = m.group("unit").replace(" ", "")
    if unit.lower() not in {u.lower() for u in SPEED_UNITS}:
        raise AdhesionInputError(f"{where}: speed unit {unit!r}: expected one of "
                                 f"{', '.join(SPEED_UNITS)}")
    return next(u for u in SPEED_UNITS if u.lower() == unit.lower())


def _quantity(where: str, column: str, quantity: str) -> None:
    m = _UNIT.match(column)
    name = (m.group("name") if m else column).strip().lower()
    if m is not None and m.group("unit") not in ("-", "1", ""):
        raise AdhesionInputError(f"{where}: second header column {column!r}: {quantity} is "
                                 "dimensionless; expected no unit or '[-]'")
    if name not in QUANTITIES[quantity]:
        raise AdhesionInputError(f"{where}: second header column {column!r}: expected "
                                 f"{quantity!r} (a {_WHAT[quantity]})")


_WHAT = {"mu": "measured coefficient of friction", "mu_H": "hysteresis coefficient of friction",
         "A_r": "relative real contact area"}


def read_curve(path: str | Path, quantity: str = "mu") -> SpeedCurve:
    """Read a speed curve file (module docstring): speeds in mm/s, the values of ``quantity``.

    ``quantity``: ``"mu"`` (friction measurement), ``"mu_H"`` (hysteresis) or ``"A_r"``.
    """
    if quantity not in QUANTITIES:
        raise AdhesionInputError(f"quantity = {quantity!r}: expected one of {list(QUANTITIES)}")
    path = Path(path)
    where = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise AdhesionInputError(f"{where}: file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise AdhesionInputError(f"{where}: cannot read: {err}") from None
    notes: list[str] = []
    header: tuple[int, str] | None = None
    rows: list[tuple[int, str]] = []
    for n, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line:
            continue
        if line.startswith("#"):
            notes.append(line.lstrip("#").strip())
        elif header is None:
            header = (n, line)
        else:
            rows.append((n, line))
    if header is None:
        raise AdhesionInputError(f"{where}: empty file: expected a header such as 'v [m/s], "
                                 f"{quantity}' and rows of numbers")
    delim = _delimiter(header[1])
    cols = _split(header[1], delim)
    if all(_is_number(c) for c in cols):
        raise AdhesionInputError(f"{where}, line {header[0]}: {header[1]!r} is a row of numbers, "
                                 f"not a header: expected a header with units first, e.g. "
                                 f"'v [m/s], {quantity}'")
    if len(cols) != 2:
        raise AdhesionInputError(f"{where}, line {header[0]}: header {header[1]!r}: expected two "
                                 f"columns, e.g. 'v [m/s], {quantity}'")
    unit = _speed_unit(f"{where}, line {header[0]}", cols[0])
    _quantity(f"{where}, line {header[0]}", cols[1], quantity)
    if not rows:
        raise AdhesionInputError(f"{where}: no data rows after the header: expected at least 2")
    v, y, lines = [], [], []
    for n, line in rows:
        tok = _split(line, delim)
        if len(tok) != 2:
            raise AdhesionInputError(f"{where}, line {n}: {line!r}: expected 2 values (v, "
                                     f"{quantity}), got {len(tok)}")
        for t, name in zip(tok, ("v", quantity)):
            if not _is_number(t):
                raise AdhesionInputError(f"{where}, line {n}: {name} = {t!r}: expected a number")
        v.append(float(tok[0]) * SPEED_UNITS[unit])
        y.append(float(tok[1]))
        lines.append(n)
    if len(v) < 2:
        raise AdhesionInputError(f"{where}: {len(v)} data row: expected at least 2")
    va, ya = np.array(v), np.array(y)
    _check_values(where, va, ya, quantity, lines)
    return SpeedCurve(va, ya, quantity, where, unit, tuple(notes))


def _is_number(token: str) -> bool:
    try:
        return math.isfinite(float(token))
    except ValueError:
        return False


def read_measurement(path: str | Path) -> SpeedCurve:
    """A friction measurement file (v, mu), speeds in mm/s."""
    return read_curve(path, "mu")


def write_curve(path: str | Path, curve: SpeedCurve, unit: str = "m/s",
                notes: tuple[str, ...] | list[str] = ()) -> Path:
    """Write ``curve`` in the file format of :func:`read_curve` (speeds in ``unit``), with
    ``notes`` as comment lines (say where the numbers come from)."""
    if unit not in SPEED_UNITS:
        raise AdhesionInputError(f"unit = {unit!r}: expected one of {', '.join(SPEED_UNITS)}")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [f"# {n}" for n in notes]
    lines.append(f"v [{unit}], {curve.quantity}")
    lines += [f"{v / SPEED_UNITS[unit]:.10g}, {y:.10g}" for v, y in zip(curve.v, curve.values)]
    path.write_text("\n".join(lines) + "\n")
    return path
