"""Exceptions of the adhesion package.

Every failure a user can trigger with bad input (a measurement file, a campaign folder, fit
options) raises :class:`AdhesionInputError`, an :class:`~rubberfriction.validation.InputError`
(a ``ValueError``) whose message names the file, the line or field, the value and what is
expected.
"""

from __future__ import annotations

from rubberfriction.validation import InputError


class AdhesionInputError(InputError):
    """Bad input to the adhesion fit: measurement files, campaign folders, fit options."""
