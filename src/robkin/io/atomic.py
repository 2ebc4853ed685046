"""Writing output files all-or-nothing: a temporary file in the same folder, then an atomic rename.

On any failure nothing is written and an existing file is left untouched.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from ..errors import InputError

__all__ = ["write_text_atomic", "check_writable_dir"]


def check_writable_dir(path: str | os.PathLike) -> Path:
    """The folder an output file goes into; InputError if it does not exist or is not writable."""
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise InputError(f"{p}: is a folder; give a file name for the output")
    if not folder.is_dir():
        raise InputError(f"{p}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise InputError(f"{p}: folder {folder} is not writable")
    return folder


def write_text_atomic(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file + rename); InputError if impossible."""
    folder = check_writable_dir(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{Path(path).name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except OSError as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
