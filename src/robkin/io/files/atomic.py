"""Writing output files all-or-nothing: temporary files in the target folders, then atomic renames.

On any failure nothing is written and existing files are left untouched:

* ``atomic_file`` / ``write_text_atomic`` write one file through a temporary file and ``os.replace``;
* ``write_texts_atomic`` writes several (a batch conversion): every temporary file is written first,
  and only when all of them are complete are they renamed into place, so a target that cannot be
  written (a full disk, a read-only file system) leaves every other target as it was;
* a SIGTERM, SIGHUP or Ctrl-C between creating a temporary file and renaming it removes the
  temporary file before the program stops (the signal is turned into an exception for the duration,
  when called from the main thread), so no hidden ``.name.*.tmp`` file is left behind.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Iterator, Sequence

from ...errors import InputError

__all__ = ["write_text_atomic", "write_texts_atomic", "atomic_file", "check_writable_dir", "check_inside",
           "signals_as_exit"]

#: Names of the signals that would otherwise end the process without running ``finally`` blocks.
_FATAL_SIGNALS = ("SIGTERM", "SIGHUP")


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


def check_inside(root: str | os.PathLike, folder: str | os.PathLike) -> Path:
    """``folder`` (``root`` joined with a relative name, e.g. ``OUT/meshes``) if files written into it
    stay inside ``root``; InputError naming the path if a part of it below ``root`` is a symbolic link
    leading outside ``root`` (writing, or creating the folder, would follow it), or it climbs out with '..'.

    Only the folders on the way are looked at: a link as the final file name is replaced by the rename,
    never followed.
    """
    root_path, target = Path(root), Path(folder)
    try:
        rel = target.relative_to(root_path)
    except ValueError:
        raise InputError(f"{target}: not inside the output folder {root_path}; nothing written") from None
    try:
        base = root_path.resolve()
        current = root_path
        for part in rel.parts:
            current = current / part
            if part == ".." or (current.is_symlink() and not current.resolve().is_relative_to(base)):
                raise InputError(f"{current}: a symbolic link (or '..') leading outside the output folder "
                                 f"{root_path}; nothing written")
    except (OSError, RuntimeError) as exc:  # a loop of links, a name too long
        raise InputError(f"{target}: cannot write there ({getattr(exc, 'strerror', None) or exc})") from None
    return target


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _exit_on_signal(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)  # unwinds through the cleanup below; the usual shell status


@contextmanager
def signals_as_exit() -> Iterator[None]:
    """While inside, SIGTERM/SIGHUP raise SystemExit (so ``finally`` blocks run); Ctrl-C already raises.

    Only the main thread can install signal handlers; elsewhere (a GUI worker) this does nothing.
    """
    import signal  # here, like threading: only a command that writes files needs them (start-up)
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for sig in (getattr(signal, name) for name in _FATAL_SIGNALS if hasattr(signal, name)):
        handler = signal.getsignal(sig)
        if handler in (signal.SIG_DFL, None):  # leave a handler the embedding program installed alone
            previous[sig] = handler
            signal.signal(sig, _exit_on_signal)
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler if handler is not None else signal.SIG_DFL)


def _temp_for(path: str | os.PathLike, folder: Path, created: list[str]) -> int:
    import tempfile  # here, not at the top: it pulls in shutil, bz2, lzma and random (~3 ms of start-up)

    fd, tmp = tempfile.mkstemp(prefix=f".{Path(path).name}.", suffix=".tmp", dir=folder)
    created.append(tmp)
    os.chmod(tmp, 0o666 & ~_current_umask())  # ordinary permissions, not mkstemp's private 0600
    return fd


def _open(fd: int, binary: bool) -> IO:
    return os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8", "newline": "\n"}))


def _remove_all(paths: list[str]) -> None:
    for tmp in paths:
        try:
            os.unlink(tmp)
        except OSError:
            pass


@contextmanager
def atomic_file(path: str | os.PathLike, binary: bool = False) -> Iterator[IO]:
    """A file handle whose content replaces ``path`` only if the ``with`` block completes.

    The file gets ordinary permissions (0666 less the umask), not mkstemp's private 0600.
    """
    folder = check_writable_dir(path)
    created: list[str] = []
    with signals_as_exit():
        try:
            with _open(_temp_for(path, folder, created), binary) as fh:
                yield fh
            os.replace(created[0], path)
        except OSError as exc:
            _remove_all(created)
            raise InputError(f"{path}: cannot write ({exc.strerror or exc})") from None
        except BaseException:
            _remove_all(created)
            raise


def write_text_atomic(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file + rename); InputError if impossible."""
    with atomic_file(path) as fh:
        fh.write(text)


def write_texts_atomic(items: Sequence[tuple[str | os.PathLike, str]]) -> None:
    """Write several (path, text) pairs all-or-nothing: all temporary files first, then the renames.

    If any file cannot be written, no target is created or changed and InputError names that file.
    Renames need no space and do not fail in practice; should one fail anyway, the message says how
    many targets were already replaced.
    """
    folders = [check_writable_dir(path) for path, _ in items]
    created: list[str] = []
    current: str | os.PathLike = ""
    renamed = 0
    with signals_as_exit():
        try:
            for (path, text), folder in zip(items, folders):
                current = path
                with _open(_temp_for(path, folder, created), False) as fh:
                    fh.write(text)
            for (path, _), tmp in zip(items, list(created)):
                current = path
                os.replace(tmp, path)
                created.remove(tmp)
                renamed += 1
        except OSError as exc:
            _remove_all(created)
            done = f"{renamed} file(s) of the batch were already replaced" if renamed else "no file was written"
            raise InputError(f"{current}: cannot write ({exc.strerror or exc}); {done}") from None
        except BaseException:
            _remove_all(created)
            raise

