"""Atomic file output: write to a temporary file beside the target, then rename.

A failed or interrupted write never destroys an existing result file.
"""

from __future__ import annotations

import os
import tempfile
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_write", "current_umask", "exclusive"]

_UMASK_LOCK = threading.Lock()


def current_umask() -> int:
    """The process umask (read under a lock: reading it means setting it briefly).

    Returns
    -------
    int
    """
    with _UMASK_LOCK:
        mask = os.umask(0o022)
        os.umask(mask)
    return mask


def _file_mode() -> int:
    """Mode of a new file under the process umask (``mkstemp`` itself creates 0600)."""
    return 0o666 & ~current_umask()


def atomic_write(path: str | Path, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp_path)`` and move the temporary file onto ``path``.

    Parameters
    ----------
    path
        Final file name; its directory is created if needed.
    write
        Function that writes the complete file to the path it is given.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        write(tmp_path)
        os.chmod(tmp_path, _file_mode())
        os.replace(tmp_path, target)
    except BaseException:
        tmp_path.unlink(missing_ok=True)
        raise
    return target


@contextmanager
def exclusive(path: str | Path) -> Iterator[None]:
    """Hold an exclusive lock on the file ``path`` (created if needed) for the block.

    Processes that compute the same cache entry take turns: the second one waits, then
    finds the first one's result (the caller reads the cache again inside the block).
    POSIX advisory lock (``fcntl.flock``); released when the block ends or the process
    dies. Where ``fcntl`` does not exist the block runs unlocked (each process computes).

    Parameters
    ----------
    path
        The lock file (its folder is created if needed); left in place.
    """
    try:
        import fcntl
    except ImportError:  # not POSIX
        yield
        return
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    with open(target, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)
