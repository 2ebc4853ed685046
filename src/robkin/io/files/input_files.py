"""Reading an input file as text: regular files only, a hard byte cap, one clear line for every failure.

Every reader of an input file (robot documents, URDF, MJCF, SDF, the GUI's start file) goes through
``read_text_file``, so the same limits hold for every entry point:

* only a regular file is read: a folder, device (``/dev/zero``), FIFO or socket behind any name is
  refused by ``stat`` before opening, and again by ``fstat`` on the opened descriptor (the name may
  have been swapped in between); the open is non-blocking, so a FIFO cannot hang the reader;
* at most ``max_bytes`` are read, whatever ``stat`` said (a file that grows while it is read is cut
  off and refused), so memory use is bounded by the cap;
* the bytes must be UTF-8 (a BOM is dropped).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from ...errors import InputError

__all__ = ["read_text_file", "read_bytes_file"]

#: Read in pieces of this size: large enough for few system calls, small enough not to over-allocate.
_CHUNK = 1 << 20


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "is a folder, not a file"
    if stat.S_ISFIFO(mode):
        return "is a pipe (FIFO), not a regular file"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "is a device, not a regular file"
    if stat.S_ISSOCK(mode):
        return "is a socket, not a regular file"
    return "is not a regular file"


def read_bytes_file(path: str | os.PathLike, max_bytes: int, kind: str) -> bytes:
    """The bytes of the regular file ``path``, at most ``max_bytes``; InputError naming the file otherwise.

    ``kind`` ("a robot document", "a URDF") words the messages.
    """
    # the name as given (messages repeat it; a Path made here would cost ~10 us of a small file's read)
    p = os.fspath(path)
    try:
        st = os.stat(p)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{p}: {_kind(st.st_mode)}; {kind} is read from a regular file")
        if st.st_size > max_bytes:
            raise InputError(f"{p}: file is {st.st_size} bytes; {kind} is at most {max_bytes}")
        # O_NONBLOCK: should the name have become a FIFO since the stat, open must not wait for a writer.
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
        try:
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode):
                raise InputError(f"{p}: {_kind(st.st_mode)}; {kind} is read from a regular file")
            chunks: list[bytes] = []
            size = 0
            # the first read asks for the size stat gave plus one byte (so that one call reads the
            # whole file and the next finds its end); a buffer of _CHUNK for a small file costs a
            # fresh allocation of that size on every read
            want = st.st_size + 1
            while True:
                chunk = os.read(fd, min(want, _CHUNK, max_bytes + 1 - size))
                want = _CHUNK
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
                if size > max_bytes:
                    raise InputError(f"{p}: file is more than {max_bytes} bytes; {kind} is at most {max_bytes}")
        finally:
            os.close(fd)
    except InputError:
        raise
    except FileNotFoundError:
        raise InputError(f"{p}: no such file") from None
    except NotADirectoryError:
        raise InputError(f"{p}: no such file (a part of the path is not a folder)") from None
    except PermissionError:
        raise InputError(f"{p}: permission denied") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror or exc})") from None
    except ValueError:  # a NUL character in the path
        raise InputError(f"{p}: not a valid file name (it contains a NUL character)") from None
    return b"".join(chunks)


def read_text_file(path: str | os.PathLike, max_bytes: int, kind: str) -> str:
    """UTF-8 text of the regular file ``path`` (a BOM is dropped), at most ``max_bytes``; see the module."""
    data = read_bytes_file(path, max_bytes, kind)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not UTF-8 text (byte {exc.start})") from None
