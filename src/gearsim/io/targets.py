"""Output targets, checked before any work starts, and folders replaced as a whole.

Every verb that writes checks each of its output targets first
(:func:`check_output_file`, :func:`check_output_folder`), so that a run never computes
for minutes and then fails on a path. Folder outputs are written into a temporary
folder beside the target and swapped in at the end (:func:`atomic_folder`): a killed
run leaves the old folder whole (or, after the swap, the new one whole), never a mix.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from gearsim.errors import InputError
from gearsim.io.atomic import current_umask

__all__ = ["atomic_folder", "check_output_file", "check_output_folder"]


def _writable_parent(path: Path, parameter: str) -> None:
    parent = path.parent if str(path.parent) else Path(".")
    probe = parent
    while not probe.exists():  # the nearest existing ancestor must be a writable folder
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir():
        raise InputError(parameter, str(path), f"{probe} is not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(parameter, str(path), f"folder {probe} is not writable")
    try:  # permissions do not tell (root, read-only or pseudo file systems): try it
        fd, tmp = tempfile.mkstemp(prefix=".gearsim-probe-", dir=probe)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise InputError(parameter, str(path), f"folder {probe} cannot be written "
                         f"({exc.strerror or exc})") from None


def _one_of(suffixes: Sequence[str]) -> str:
    """``".a"``, ``".a or .b"``, ``".a, .b or .c"``."""
    items = list(suffixes)
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " or " + items[-1]


def check_output_file(path: str | Path, parameter: str,
                      suffixes: Sequence[str] | None = None) -> Path:
    """Check that ``path`` can be written as a file, before any work.

    Parameters
    ----------
    path : str or Path
        The output file.
    parameter : str
        Name of the option or key for the message (e.g. ``"--out"``).
    suffixes : sequence of str, optional
        Allowed suffixes (lower case, with the dot), e.g. ``(".nc",)``.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        An empty path, an existing folder, a wrong suffix, or a folder that cannot be
        created or written.

    Examples
    --------
    >>> check_output_file("run.nc", "--out", (".nc",)).name
    'run.nc'
    """
    if str(path).strip() == "":
        raise InputError(parameter, '""', "must name a file")
    p = Path(path)
    if p.is_dir():
        raise InputError(parameter, str(p), "is a folder; give a file name")
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise InputError(parameter, str(p), "must end in " + _one_of(suffixes))
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(parameter, str(p), "exists and is not writable")
    _writable_parent(p, parameter)
    return p


def check_output_folder(path: str | Path, parameter: str,
                        owned: Callable[[str], bool] | None = None) -> Path:
    """Check that ``path`` can be written as a folder, before any work.

    Parameters
    ----------
    path : str or Path
        The output folder (it may exist; it is replaced as a whole by
        :func:`atomic_folder`).
    parameter : str
        Name of the option for the message.
    owned : callable, optional
        ``owned(name) -> bool``: whether an entry of an existing folder is one the verb
        writes (an earlier output). If given, an existing folder holding any other entry
        is refused, since replacing the folder would delete it; so is the working folder
        or a folder that contains it.

    Returns
    -------
    Path

    Raises
    ------
    InputError
        An empty path, an existing file, a parent that cannot be written, or (with
        ``owned``) a folder holding entries the verb did not write.

    Examples
    --------
    >>> check_output_folder("results", "--out").name
    'results'
    """
    if str(path).strip() == "":
        raise InputError(parameter, '""', "must name a folder")
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(parameter, str(p), "must be a folder (a file of that name exists)")
    if owned is not None and p.is_dir():
        here = Path.cwd().resolve()
        full = p.resolve()
        if full == here or full in here.parents:
            raise InputError(parameter, str(p), "is the working folder or contains it; the "
                             "output folder is replaced as a whole: give a new folder")
        foreign = sorted(e.name for e in os.scandir(p) if not owned(e.name))
        if foreign:
            more = f" and {len(foreign) - 1} more" if len(foreign) > 1 else ""
            raise InputError(parameter, str(p), f"holds {foreign[0]!r}{more}, not written by "
                             "this command; the output folder is replaced as a whole: give "
                             "a new or empty folder")
        if not os.access(p, os.W_OK | os.X_OK):
            raise InputError(parameter, str(p), "exists and is not writable")
    _writable_parent(p, parameter)
    return p


_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one step (Linux ``renameat2(RENAME_EXCHANGE)``); False if not
    available here (other system, old kernel or C library, file system without it)."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        func = libc.renameat2
    except (OSError, AttributeError):
        return False
    func.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                     ctypes.c_uint]
    func.restype = ctypes.c_int
    if func(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _link_or_copy(src: str, dst: str) -> None:
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def _carry(old: Path, new: Path, keep: Callable[[str], bool]) -> None:
    """Carry the entries of ``old`` that ``keep`` selects into ``new``: files as hard
    links (else copies), folders as trees of such links, symbolic links as links."""
    for entry in os.scandir(old):
        if not keep(entry.name):
            continue
        dst = new / entry.name
        if entry.is_symlink():
            os.symlink(os.readlink(entry.path), dst)
        elif entry.is_dir():
            shutil.copytree(entry.path, dst, symlinks=True, copy_function=_link_or_copy)
        else:
            _link_or_copy(entry.path, str(dst))


@contextmanager
def atomic_folder(path: str | Path,
                  keep: Callable[[str], bool] | None = None) -> Iterator[Path]:
    """Write a folder's content into a temporary folder, then swap it in.

    Yields the temporary folder (beside ``path``, same file system). On normal exit the
    new folder replaces the old one in one step where the system allows it (Linux
    ``renameat2`` exchange), else by two renames, and the old one is removed; on an
    exception the temporary folder is removed and ``path`` is left as it was. With two
    renames, a kill between them leaves the old folder under ``.NAME.old-*`` beside the
    target (never a mix of old and new files). A kill before the swap leaves the
    temporary folder ``.NAME.*.tmp`` beside the target, which may be deleted.

    Parameters
    ----------
    path : str or Path
        The final folder.
    keep : callable, optional
        ``keep(name) -> bool``: entries of the old folder to carry over into the new
        one before the caller writes (files as hard links, else copies; folders as
        trees of them); files the caller writes replace them (write new files, never
        modify a carried one in place). Default: nothing is carried over.

    Yields
    ------
    Path
        The temporary folder to write into.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent))
    try:
        if keep is not None and target.is_dir():
            _carry(target, tmp, keep)
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    os.chmod(tmp, 0o777 & ~current_umask())
    if target.is_dir() and _exchange(tmp, target):
        shutil.rmtree(tmp, ignore_errors=True)  # now the old folder
        return
    old = None
    if target.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-", dir=target.parent))
        os.rmdir(old)
        os.replace(target, old)
    os.replace(tmp, target)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
