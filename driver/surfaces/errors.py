"""Exceptions of the rough-surface package.

Every failure a user can trigger with bad input raises one of these, each a ``ValueError`` so
that callers that do not care about the detail can catch the standard type.  The messages say
what was wrong, where (line, index, position in mm) and what to do about it.
"""

from __future__ import annotations

from rubberfriction.validation import InputError


class SurfaceError(InputError):
    """Base class of all rough-surface input and processing errors."""


class ProfileFormatError(SurfaceError):
    """A file cannot be read as a line-scan profile (empty, ragged, unknown columns or units)."""


class DefectError(SurfaceError):
    """A profile has defects (dropouts, outliers, long gaps) that cannot be repaired safely."""


class BandError(SurfaceError):
    """A band-pass request does not fit the profile (too short, too coarse, bad edges)."""
