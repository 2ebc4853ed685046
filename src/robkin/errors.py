"""One exception root for robkin, and the warning issued when an input is nudged onto a valid value.

Every message names the file, field or joint at fault and what would be valid, so the CLI can print
it as one line (exit status 2) and a Python caller can show it as it is.

This is also the one place that bounds what a message quotes from an input: ``quote`` shows a value
(a name, a number, a nested list) shortened and with control characters escaped, and every
InputError message is itself made printable and cut to ``MAX_MESSAGE`` characters, so a hostile
input (a 10 MB attribute, a name with a newline or a lone surrogate) can never make a huge, multi-line
or unprintable error line.
"""

from __future__ import annotations

import reprlib
import unicodedata

__all__ = ["RobkinError", "InputError", "ProjectionWarning", "ConditioningWarning", "quote", "printable", "unprintable",
           "MAX_MESSAGE", "MAX_QUOTE"]

#: Longest error message (characters): room for two file paths, a field, a quoted value and the valid
#: choices, and still one line of a wide terminal or of the GUI's message bar.
MAX_MESSAGE = 400
#: Longest quotation of an input value inside a message: enough to recognise a name or a number.
MAX_QUOTE = 80
#: Characters that would break a one-line message or hide text: control characters (Cc), lone
#: surrogates (Cs), line/paragraph separators (Zl, Zp) and the bidirectional overrides and isolates.
_UNPRINTABLE_CATEGORIES = frozenset({"Cc", "Cs", "Zl", "Zp"})
_BIDI_CONTROLS = frozenset("\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


def unprintable(c: str) -> bool:
    """True for a character that must not appear in a name or a message (see _UNPRINTABLE_CATEGORIES).

    ``c``: one character.
    """
    return c in _BIDI_CONTROLS or unicodedata.category(c) in _UNPRINTABLE_CATEGORIES


def printable(text: str) -> str:
    """``text`` with every unprintable character written as an escape (\\n, \\x1b, \\ud800)."""
    if text.isprintable():
        return text  # fast path: nothing to escape (isprintable is stricter than unprintable)
    return "".join(c.encode("unicode_escape").decode("ascii") if unprintable(c) else c for c in text)


def _shorten(text: str, limit: int) -> str:
    if len(text) <= limit:
        return text
    keep = max(limit - 40, 8)
    return f"{text[:keep * 3 // 4]}...({len(text)} characters)...{text[len(text) - keep // 4:]}"


_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxtuple, _REPR.maxdict = 2, 6, 6, 4
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = MAX_QUOTE


def quote(value: object, limit: int = MAX_QUOTE) -> str:
    """``value`` as it may appear in a message: a string in quotes, anything else as a short repr.

    Bounded whatever the value: long strings and numbers are cut in the middle, nested lists and
    mappings are shown to two levels and a few items, and control characters are escaped.

    ``limit``: the longest text (characters) a value becomes.
    """
    if isinstance(value, str):
        return "'" + printable(_shorten(value, limit)) + "'"
    try:
        text = _REPR.repr(value)
    except ValueError:  # an integer beyond Python's 4300-digit str() limit
        return f"<{type(value).__name__} too large to show>"
    return printable(_shorten(text, limit))


class RobkinError(Exception):
    """Root of every error robkin raises on purpose."""


class InputError(RobkinError, ValueError):
    """The input does not describe a valid robot; the message says where and what would be valid.

    ``message``: the one line; ``source``: the file it is about, put in front of the message.
    """

    def __init__(self, message: str, *, source: str | None = None) -> None:
        self.source = source
        text = f"{source}: {message}" if source else str(message)
        super().__init__(printable(_shorten(text, MAX_MESSAGE)))

    def in_source(self, source: str) -> "InputError":
        """The same error, prefixed with the file it came from (unless it already names it first).

        ``source``: the file name.
        """
        if self.source is not None or str(self).startswith(f"{printable(source)}:"):
            return self
        return InputError(str(self), source=source)


class ProjectionWarning(UserWarning):
    """An input was within tolerance of a valid value (e.g. typed with 3 decimals) and was projected."""


class ConditioningWarning(UserWarning):
    """A conversion is exact but numerically ill-conditioned (e.g. nearly parallel joint axes)."""
