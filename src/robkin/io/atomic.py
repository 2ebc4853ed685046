"""Writing output files all-or-nothing: a temporary file in the same folder, then an atomic rename.

On any failure nothing is written and an existing file is left untouched.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Iterator

from ..errors import InputError

__all__ = ["write_text_atomic", "atomic_file", "check_writable_dir"]


def check_writable_dir(path: str | os.PathLike) -> Path:
    """The folder an output file goes into; InputError if it does not exist or is not writable."""
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    try:
        if p.is_dir():
            raise InputError(f"{p}: is a folder; give a file name for the output")
        if not folder.is_dir():
            raise InputError(f"{p}: folder {folder} does not exist")
    except OSError as exc:  # e.g. a name longer than the file system allows
        raise InputError(f"{p}: cannot write there ({exc.strerror or exc})") from None
    if not os.access(folder, os.W_OK):
        raise InputError(f"{p}: folder {folder} is not writable")
    return folder


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_file(path: str | os.PathLike, binary: bool = False) -> Iterator[IO]:
    """A file handle whose content replaces ``path`` only if the ``with`` block completes.

    The file gets ordinary permissions (0666 less the umask), not mkstemp's private 0600.
    """
    folder = check_writable_dir(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{Path(path).name}.", suffix=".tmp", dir=folder)
    try:
        os.chmod(tmp, 0o666 & ~_current_umask())
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8", "newline": "\n"})) as fh:
            yield fh
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None
    except BaseException:
        _remove(tmp)
        raise


def _remove(tmp: str) -> None:
    try:
        os.unlink(tmp)
    except OSError:
        pass


def write_text_atomic(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file + rename); InputError if impossible."""
    with atomic_file(path) as fh:
        fh.write(text)
