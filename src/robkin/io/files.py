"""Reading an input file as text, with one clear line for every way that can fail."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError

__all__ = ["read_text_file"]


def read_text_file(path: str | os.PathLike, max_bytes: int, kind: str) -> str:
    """UTF-8 text of ``path`` (a BOM is dropped); InputError naming the file if it cannot be had.

    ``max_bytes`` stops accidental huge inputs before they are read; ``kind`` ("a robot document",
    "a URDF") words the messages.
    """
    p = Path(path)
    try:
        size = p.stat().st_size
        if size > max_bytes:
            raise InputError(f"{p}: file is {size} bytes; {kind} is at most {max_bytes}")
        data = p.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{p}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{p}: is a folder, not a file") from None
    except PermissionError:
        raise InputError(f"{p}: permission denied") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror or exc})") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{p}: not UTF-8 text (byte {exc.start})") from None
