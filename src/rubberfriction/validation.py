"""Input validation for the whole project: one vocabulary, one message format.

Every check raises an :class:`InputError` (a ``ValueError``; subclasses name the input kind:
``SceneError``, ``SurfaceError``, ``TheoryInputError``) whose message names the field, the value
and what is expected::

    <where> = <value>: expected <what>

e.g. ``tread_default.toml [hyperelastic].C10 = -0.1: expected a value > 0 in MPa`` or
``scene.toml: [conditions].pressures = [-1.0]: expected a list of numbers > 0``.  ``where`` is
written by the caller (file, table and key, or object and attribute); ``error`` picks the
subclass.  Nothing here knows about physics: forms, surfaces, theories and scenes all use it.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable
from typing import Any, NoReturn

import numpy as np


class InputError(ValueError):
    """Bad input; the message names the field, the value and what is expected."""


def fail(where: str, value: Any, expected: str, error: type[InputError] = InputError) -> NoReturn:
    """Raise ``error("<where> = <value!r>: expected <expected>")``."""
    raise error(f"{where} = {value!r}: expected {expected}")


def suggest(name: str, allowed: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` for a close match among ``allowed``, else ``""``."""
    close = difflib.get_close_matches(name, list(allowed), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def _unit(unit: str) -> str:
    return f" in {unit}" if unit else ""


def number(where: str, value: Any, *, what: str = "a number", minimum: float | None = None,
           above: float | None = None, maximum: float | None = None,
           below: float | None = None, shown: Any = None,
           error: type[InputError] = InputError) -> float:
    """A finite real number (not a bool) with optional bounds: ``>= minimum``, ``> above``,
    ``<= maximum``, ``< below``.  ``shown`` is the value printed in the message (default:
    ``value``)."""
    show = value if shown is None else shown
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        fail(where, show, what, error)
    v = float(value)
    if not math.isfinite(v):
        fail(where, show, f"a finite {what.removeprefix('a ').removeprefix('an ')}", error)
    if minimum is not None and v < minimum:
        fail(where, show, f"{what} >= {minimum:g}", error)
    if above is not None and v <= above:
        fail(where, show, f"{what} > {above:g}", error)
    if maximum is not None and v > maximum:
        fail(where, show, f"{what} <= {maximum:g}", error)
    if below is not None and v >= below:
        fail(where, show, f"{what} < {below:g}", error)
    return v


def real(where: str, value: Any, unit: str = "", *,
         error: type[InputError] = InputError) -> float:
    """A finite real number in ``unit``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        fail(where, value, f"a real number{_unit(unit)}", error)
    v = float(value)
    if not math.isfinite(v):
        fail(where, v, f"a finite number{_unit(unit)}", error)
    return v


def positive(where: str, value: Any, unit: str = "", *,
             error: type[InputError] = InputError) -> float:
    """A finite number > 0 in ``unit``."""
    v = real(where, value, unit, error=error)
    if v <= 0.0:
        fail(where, v, f"a value > 0{_unit(unit)}", error)
    return v


def nonnegative(where: str, value: Any, unit: str = "", *,
                error: type[InputError] = InputError) -> float:
    """A finite number >= 0 in ``unit``."""
    v = real(where, value, unit, error=error)
    if v < 0.0:
        fail(where, v, f"a value >= 0{_unit(unit)}", error)
    return v


def integer(where: str, value: Any, *, minimum: int | None = None,
            error: type[InputError] = InputError) -> int:
    """An integer (not a bool), optionally ``>= minimum``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        fail(where, value, "an integer" + (f" >= {minimum}" if minimum is not None else ""), error)
    if minimum is not None and value < minimum:
        fail(where, value, f"an integer >= {minimum}", error)
    return int(value)


def text(where: str, value: Any, *, empty_ok: bool = True,
         error: type[InputError] = InputError) -> str:
    """A string (non-empty unless ``empty_ok``)."""
    if not isinstance(value, str) or (not empty_ok and not value.strip()):
        fail(where, value, "a string" if empty_ok else "a non-empty string", error)
    return value


def choice(where: str, value: Any, choices: Iterable[Any], *,
           error: type[InputError] = InputError) -> Any:
    """One of ``choices`` (with a did-you-mean hint for strings)."""
    options = tuple(choices)
    if value not in options:
        hint = suggest(value, map(str, options)) if isinstance(value, str) else ""
        fail(where, value, f"one of {', '.join(map(repr, options))}{hint}", error)
    return value


def instance(where: str, value: Any, cls: type, *, optional: bool = False,
             error: type[InputError] = InputError) -> Any:
    """An instance of ``cls`` (or None when ``optional``)."""
    if value is None and optional:
        return None
    if not isinstance(value, cls):
        fail(where, value, f"a {cls.__name__}" + (" or None" if optional else ""), error)
    return value


def float_array(where: str, value: Any, unit: str = "", *,
                error: type[InputError] = InputError) -> np.ndarray:
    """A finite 1-D float array (a scalar becomes one entry); a bad entry is named by index."""
    try:
        arr = np.array(value, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        fail(where, value, f"a 1-D array of numbers{_unit(unit)}", error)
    if arr.ndim != 1:
        raise error(f"{where}: expected a 1-D array{_unit(unit)}, got shape {arr.shape}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        fail(f"{where}[{i}]", arr[i], f"finite values{_unit(unit)}", error)
    return arr


def finite_array(where: str, value: Any, unit: str = "", *,
                 error: type[InputError] = InputError) -> np.ndarray:
    """A finite float array of any shape (0-d for a scalar), in the shape given."""
    if np.ndim(value) <= 1:
        return float_array(where, value, unit, error=error).reshape(np.shape(value))
    arr = np.asarray(value, dtype=float)
    if not np.isfinite(arr).all():
        raise error(f"{where}: expected finite values{_unit(unit)}")
    return arr


def table(where: str, value: Any, allowed: Iterable[str], required: Iterable[str] = (), *,
          error: type[InputError] = InputError) -> dict:
    """A TOML table whose keys are among ``allowed`` (unknown keys named, with a did-you-mean
    hint) and include ``required``."""
    if not isinstance(value, dict):
        raise error(f"{where}: expected a table, got {value!r}")
    allowed = set(allowed)
    unknown = sorted(set(value) - allowed)
    if unknown:
        hint = suggest(unknown[0], allowed) if len(unknown) == 1 else ""
        raise error(f"{where}: unknown key(s) {unknown}{hint}; expected some of {sorted(allowed)}")
    missing = sorted(set(required) - set(value))
    if missing:
        raise error(f"{where}: missing key(s) {missing}")
    return value


def _typed(value: Any) -> str:
    """A command-line value as the user typed it (``-1`` rather than ``-1.0``)."""
    if isinstance(value, (list, tuple)):
        return " ".join(_typed(v) for v in value)
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def option(flag: str, value: Any, *, what: str, unit: str = "", minimum: float | None = None,
           above: float | None = None, maximum: float | None = None, below: float | None = None,
           error: type[InputError] = InputError) -> Any:
    """A command-line option's value (a number or a list of numbers) within bounds, else
    ``error("<flag> <value as typed>: expected <what> > 0 <unit>")``: the option named as the user
    typed it (``--R -1: expected a radius > 0 mm``).  None (option not given) passes."""
    if value is None:
        return None
    values = list(value) if isinstance(value, (list, tuple)) else [value]
    tests = ((minimum, ">=", lambda v, b: v >= b), (above, ">", lambda v, b: v > b),
             (maximum, "<=", lambda v, b: v <= b), (below, "<", lambda v, b: v < b))
    bounds = [f"{op} {b:g}" for b, op, _ in tests if b is not None]
    expected = f"{what} {' and '.join(bounds)}".strip() + _unit(unit)
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise error(f"{flag} {_typed(value)}: expected {expected}")
        if not math.isfinite(float(v)):
            raise error(f"{flag} {_typed(value)}: expected a finite value, {expected}")
        if not all(ok(float(v), b) for b, _, ok in tests if b is not None):
            raise error(f"{flag} {_typed(value)}: expected {expected}")
    return value
