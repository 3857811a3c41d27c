"""The one way the program writes a file (SPEC §5): whole or not at all, never through a link.

Every file valterm writes (setup, location and program files, DATFILER.DAT, CHECK.DAT, the
editor's journal, hardcopies, exports, the files seeded into a new workspace) goes through
:func:`write_bytes_atomic`:

* the data goes to a temporary ``.NAME.<random>.tmp`` created exclusively (``O_EXCL``, and
  ``O_NOFOLLOW`` where the platform has it) in the target's own folder, so nothing planted
  under a guessable name is ever written through;
* it is flushed to the disk (``fsync``) and renamed over the target with ``os.replace``:
  readers, and a program killed at any moment, see the old file or the new one, never a part;
* a target that is a symbolic link (dangling or not), a folder or a device is refused with
  :class:`FileWriteError`: the program never writes where a link points.

Reading has its one way too, :func:`open_regular`: only a regular file is opened to be read
(a FIFO would block the reader for ever, /dev/zero never ends); every reader of a workspace
file goes through it (``valterm.core.files._text.read_bytes``).

A kill between creating the temporary and the rename leaves a stray temporary;
:func:`remove_stale_temporaries` (called when a workspace opens) clears them.

Two sessions may share one workspace (a classroom's shared storage). A save given the
``expected`` stamp of the file as its session read it (:func:`file_stamp`) is checked and
written under the folder's lock (:func:`folder_lock`, an ``fcntl`` lock on ``.valterm.lock``):
when the file changed on disk since, :class:`FileChanged` is raised and nothing is written,
so the UI can ask (overwrite / reload / save as) instead of losing the other session's work.
"""

from __future__ import annotations

import os
import re
import stat
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO

from valterm.core.files.errors import FileChanged, FileWriteError, NotAFile

# POSIX: a temporary being written is locked, so a second session never removes it.
# Windows has no flock: there temporaries are not locked.
if sys.platform != "win32":
    import fcntl

TEMP_SUFFIX = ".tmp"
_RANDOM_CHARS = 16  # hex digits of the temporary's random part

# `.NAME.<8-32 random characters>.tmp`: ours, and those of older versions (tempfile.mkstemp).
_TEMPORARY = re.compile(r"\..+\.[A-Za-z0-9_]{8,32}\.tmp")

# the lock file of a workspace folder: saves that check a stamp, and CHECK.DAT's merges, hold it
LOCK_NAME = ".valterm.lock"

# reading: no wait for a FIFO's writer, no terminal made the controlling one (then refused)
_READ = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_BINARY", 0)

_CREATE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_BINARY", 0)


def write_text_atomic(path: str | Path, text: str, encoding: str = "utf-8", expected: str | None = None) -> None:
    """Write ``text`` to ``path`` atomically (see the module docstring)."""
    write_bytes_atomic(path, text.encode(encoding, errors="strict"), expected)


def write_bytes_atomic(path: str | Path, data: bytes, expected: str | None = None) -> None:
    """Write ``data`` to ``path`` through an exclusive temporary in the same folder, then rename.

    Raises FileWriteError (a ValtermError naming the file) when the target is a link or not a
    regular file, or when the disk refuses (full, read-only, no permission). With ``expected``
    (the file's :func:`file_stamp` when it was read; "" for a file that did not exist) the
    file is compared and written under the folder's lock, and FileChanged is raised, nothing
    written, when it differs now: another session saved it meanwhile.
    """
    if expected is None:
        _write(Path(path), data)
        return
    target = Path(path)
    with folder_lock(target.parent):
        if file_stamp(target) != expected:
            raise FileChanged(target)
        _write(target, data)


def file_kind(mode: int) -> str | None:
    """What a file of ``stat`` mode ``mode`` is, when it is no regular file (None when it is)."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO (a named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISLNK(mode):  # looked at without following it
        return "a symbolic link"
    return "a special file"


def open_regular(path: str | Path, follow_links: bool = True) -> tuple[BinaryIO, os.stat_result]:
    """The one way the program opens a file to read it: a regular file, opened, and what
    ``fstat`` says of it (its size: the reader's cap). Anything else is :class:`NotAFile` at
    once, never read: a FIFO would block for ever, /dev/zero never ends. Looked at before the
    open (a device is not even opened) and again after it, on what was opened (the name could
    have been swapped between). ``follow_links=False``: a symbolic link is refused too."""
    kind = file_kind(os.stat(path, follow_symlinks=follow_links).st_mode)
    if kind is not None:
        raise NotAFile(path, kind)
    flags = _READ | (0 if follow_links else getattr(os, "O_NOFOLLOW", 0))
    fd = os.open(path, flags)
    try:
        info = os.fstat(fd)
        kind = file_kind(info.st_mode)
        if kind is not None:
            raise NotAFile(path, kind)
        if flags & getattr(os, "O_NONBLOCK", 0):
            os.set_blocking(fd, True)  # a regular file ignores it; reads as usual
        return os.fdopen(fd, "rb"), info
    except BaseException:
        os.close(fd)
        raise


def file_stamp(path: str | Path) -> str:
    """What a save compares: the SHA-256 of the file's bytes ("" when there is no file).

    The content, not the time: two saves within one clock tick, or a copy that keeps the
    time, are still told apart."""
    try:
        handle, _info = open_regular(path)
        with handle:
            return bytes_stamp(handle.read())
    except FileNotFoundError:
        return ""
    except NotAFile as error:
        raise FileWriteError(path, f"{error.reason}; cannot compare it") from None
    except OSError as error:
        raise FileWriteError(path, f"cannot read the file to compare it: {error.strerror or error}") from None


def text_stamp(text: str, encoding: str = "utf-8") -> str:
    """The :func:`file_stamp` a file holding ``text`` has (what a session just wrote)."""
    return bytes_stamp(text.encode(encoding))


def bytes_stamp(data: bytes) -> str:
    """The :func:`file_stamp` of a file holding ``data`` (what a session read)."""
    import hashlib  # when a save first compares, not at every start (issue 25: OpenSSL's load)

    return hashlib.sha256(data).hexdigest()


@contextmanager
def folder_lock(folder: str | Path) -> Iterator[None]:
    """Hold the folder's lock file (``.valterm.lock``, exclusive ``fcntl.flock``) while the body
    runs: another session's checked save or CHECK.DAT merge waits for it. A folder where no
    lock file can be made (read-only) is not locked: the write itself then says why it fails."""
    fd = -1
    if sys.platform != "win32":  # Windows has no flock: the check still runs, without the lock
        try:
            fd = os.open(Path(folder) / LOCK_NAME, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o666)
        except OSError:
            fd = -1
    try:
        if fd >= 0:
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        if fd >= 0:
            os.close(fd)  # closing releases the lock


def claim(path: str | Path) -> int | None:
    """Hold ``path`` (a lock file, created if missing) for as long as this session wants it:
    the open descriptor, or None when another session holds it now. Close the descriptor
    (:func:`release`) to let it go; a session that ends lets it go too. Windows: always held."""
    if sys.platform == "win32":
        return -1
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o666)
    except OSError:
        return -1  # no lock file can be made (a read-only folder): nothing to share it with
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd


def release(fd: int | None) -> None:
    """Let go of what :func:`claim` returned."""
    if fd is not None and fd >= 0:
        try:
            os.close(fd)
        except OSError:
            pass


def _write(target: Path, data: bytes) -> None:
    import secrets  # with the first write, not at every start (issue 25: the app's start writes nothing)

    mode = check_writable(target)
    temp = target.with_name(f".{target.name}.{secrets.token_hex(_RANDOM_CHARS // 2)}{TEMP_SUFFIX}")
    try:
        fd = os.open(temp, _CREATE, 0o666)  # the umask applies, as for any new file
    except OSError as error:
        raise FileWriteError(target, _reason(error)) from None
    try:
        with os.fdopen(fd, "wb") as handle:
            _lock(handle.fileno())
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
            if mode is not None:
                os.chmod(temp, mode)  # a rewritten file keeps its permissions
            check_writable(target)  # a link planted while we wrote is still refused
            os.replace(temp, target)
    except BaseException as error:
        _unlink(temp)
        if isinstance(error, OSError):
            raise FileWriteError(target, _reason(error)) from None
        raise


def check_writable(target: Path) -> int | None:
    """The permission bits of an existing regular file, None for a new one; FileWriteError
    for a symbolic link, a folder or anything else that is not a plain file."""
    try:
        info = os.lstat(target)
    except FileNotFoundError:
        return None
    except OSError as error:
        raise FileWriteError(target, _reason(error)) from None
    if stat.S_ISLNK(info.st_mode):
        raise FileWriteError(target, "is a symbolic link; refusing to write through it")
    if stat.S_ISDIR(info.st_mode):
        raise FileWriteError(target, "is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise FileWriteError(target, "is not a regular file; refusing to write to it")
    return stat.S_IMODE(info.st_mode)


def is_temporary(name: str) -> bool:
    """True for a name this module (or an older valterm) gives its temporaries."""
    return _TEMPORARY.fullmatch(name) is not None


def remove_stale_temporaries(folder: str | Path) -> list[str]:
    """Remove the temporaries left in ``folder`` by writes that were killed; returns their names.

    A temporary another session is writing right now is locked and left alone (POSIX).
    Links with a temporary's name are removed too (the link only, never what it points to).
    """
    removed: list[str] = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if not is_temporary(entry.name) or entry.is_dir(follow_symlinks=False):
            continue
        if not entry.is_symlink() and _in_use(entry.path):
            continue
        try:
            os.unlink(entry.path)
        except OSError:
            continue
        removed.append(entry.name)
    return removed


def _lock(fd: int) -> None:
    if sys.platform != "win32":
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            pass


def _in_use(path: str) -> bool:
    """True when another process holds the temporary's lock (it is being written)."""
    if sys.platform == "win32":
        return False
    else:  # a block of its own: mypy checks it only where fcntl exists
        try:
            fd = os.open(path, _READ | getattr(os, "O_NOFOLLOW", 0))  # a FIFO does not block
        except OSError:
            return False
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            return True
        finally:
            os.close(fd)
        return False


def _unlink(path: Path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def _reason(error: OSError) -> str:
    return f"cannot write the file: {error.strerror or error}"


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable where the platform allows it (not on Windows)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
