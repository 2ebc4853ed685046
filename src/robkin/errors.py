"""One exception root for robkin, and the warning issued when an input is nudged onto a valid value.

Every message names the file, field or joint at fault and what would be valid, so the CLI can print
it as one line (exit status 2) and a Python caller can show it as it is.
"""

from __future__ import annotations

__all__ = ["RobkinError", "InputError", "ProjectionWarning", "ConditioningWarning"]


class RobkinError(Exception):
    """Root of every error robkin raises on purpose."""


class InputError(RobkinError, ValueError):
    """The input does not describe a valid robot; the message says where and what would be valid."""

    def __init__(self, message: str, *, source: str | None = None) -> None:
        self.source = source
        super().__init__(f"{source}: {message}" if source else message)

    def in_source(self, source: str) -> "InputError":
        """The same error, prefixed with the file it came from (unless it already is)."""
        if self.source is not None:
            return self
        err = InputError(str(self), source=source)
        return err


class ProjectionWarning(UserWarning):
    """An input was within tolerance of a valid value (e.g. typed with 3 decimals) and was projected."""


class ConditioningWarning(UserWarning):
    """A conversion is exact but numerically ill-conditioned (e.g. nearly parallel joint axes)."""
