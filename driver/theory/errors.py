"""Exceptions of the analytical-theory package.

Every failure a user can trigger with bad input raises :class:`TheoryInputError`, a
``ValueError``, with a message that names the quantity, the offending value and what is expected
(the project convention, README "Conventions"; :mod:`rubberfriction.validation`).
"""

from __future__ import annotations

from rubberfriction.validation import InputError


class TheoryInputError(InputError):
    """Bad input to an analytical friction theory (PSD, material, conditions, options)."""
