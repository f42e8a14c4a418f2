"""Compressed records: gzip, bz2, xz and single-member zip, recognised by their content.

A file is taken as compressed when its first bytes are the magic number of one of the
:data:`MAGIC` formats, whatever its name: ``rec.csv.gz`` and a gzip stream saved as
``rec.csv`` are both decompressed. The name of the record inside is the file name without
its compression suffix (``rec.csv.gz`` -> ``rec.csv``), or the member's name for a zip
archive. The whole record is decompressed into memory (at most
:data:`MAX_DECOMPRESSED_BYTES`); nothing is written next to the file.
"""

from __future__ import annotations

import bz2
import gzip
import lzma
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from gearsim.errors import InputError

__all__ = ["MAGIC", "MAX_DECOMPRESSED_BYTES", "SUFFIXES", "Decompressed", "decompress",
           "sniff_compression"]

#: Leading bytes of each compressed format (bz2 is followed by a block-size digit 1-9).
MAGIC: dict[str, bytes] = {
    "gzip": b"\x1f\x8b",
    "bz2": b"BZh",
    "xz": b"\xfd7zXZ\x00",
    "zip": b"PK\x03\x04",
}

#: File-name suffixes removed to find the inner record's name.
SUFFIXES: dict[str, str] = {
    ".gz": "gzip", ".gzip": "gzip", ".bz2": "bz2", ".bzip2": "bz2", ".xz": "xz", ".zip": "zip",
}

#: Largest decompressed record accepted (a guard against decompression bombs).
MAX_DECOMPRESSED_BYTES = 4 * 1024**3

_CHUNK = 1 << 20
#: zip entries that are not records (macOS resource forks and folder metadata).
_ZIP_NOISE = ("__MACOSX/", ".DS_Store")


@dataclass(frozen=True)
class Decompressed:
    """A record decompressed into memory (returned by :func:`decompress`).

    Parameters
    ----------
    data : bytes
        The decompressed content.
    inner_name : str
        Name of the record inside: the file name without its compression suffix, or the
        zip member's base name.
    compression : str
        Key of :data:`MAGIC`.
    """

    data: bytes
    inner_name: str
    compression: str


def sniff_compression(path: str | Path) -> str | None:
    """Compression format of a file from its first bytes, or None when it is not compressed.

    Parameters
    ----------
    path : str or Path
        File to inspect (only its first 6 bytes are read).

    Returns
    -------
    str or None
        A key of :data:`MAGIC` (``"gzip"``, ``"bz2"``, ``"xz"``, ``"zip"``) or None.
    """
    with open(path, "rb") as fh:
        head = fh.read(6)
    for kind, magic in MAGIC.items():
        if head.startswith(magic):
            if kind == "bz2" and (len(head) < 4 or head[3:4] not in b"123456789"):
                continue
            return kind
    if head.startswith(b"PK\x05\x06"):  # an empty zip archive
        return "zip"
    return None


def _read_capped(fh, path: Path, kind: str) -> bytes:
    parts = []
    total = 0
    while True:
        chunk = fh.read(_CHUNK)
        if not chunk:
            return b"".join(parts)
        total += len(chunk)
        if total > MAX_DECOMPRESSED_BYTES:
            raise InputError("file", str(path), f"decompresses ({kind}) to more than "
                             f"{MAX_DECOMPRESSED_BYTES / 1024**3:g} GiB (refused)")
        parts.append(chunk)


def _inner_name(path: Path) -> str:
    name = path.name
    suffix = Path(name).suffix.lower()
    if suffix in SUFFIXES and len(name) > len(suffix):
        return name[: -len(suffix)]
    if suffix == ".tgz":
        return name[:-4] + ".tar"
    return name


def decompress(path: str | Path, kind: str | None = None) -> Decompressed | None:
    """Decompress a gzip, bz2, xz or single-member zip file into memory.

    Parameters
    ----------
    path : str or Path
        File to read.
    kind : str, optional
        Compression format (key of :data:`MAGIC`); by default from the content
        (:func:`sniff_compression`).

    Returns
    -------
    Decompressed or None
        The content and the inner record's name; None when the file is not compressed.

    Raises
    ------
    InputError
        A zip archive with no or several members (the message names them), an
        encrypted member, a corrupt or truncated stream, or a record larger than
        :data:`MAX_DECOMPRESSED_BYTES` once decompressed.
    """
    p = Path(path)
    kind = kind or sniff_compression(p)
    if kind is None:
        return None
    inner = _inner_name(p)
    try:
        if kind == "zip":
            with zipfile.ZipFile(p) as zf:
                members = [i for i in zf.infolist() if not i.is_dir()
                           and not any(n in i.filename for n in _ZIP_NOISE)]
                if len(members) != 1:
                    names = [m.filename for m in members]
                    raise InputError("file", str(p), f"zip archive holds {len(names)} members "
                                     f"{names}: must hold exactly one record")
                inner = PurePosixPath(members[0].filename).name
                with zf.open(members[0]) as fh:
                    data = _read_capped(fh, p, kind)
        else:
            opener = {"gzip": gzip.open, "bz2": bz2.open, "xz": lzma.open}[kind]
            with opener(p, "rb") as fh:
                data = _read_capped(fh, p, kind)
    except InputError:
        raise
    except (OSError, EOFError, zlib.error, lzma.LZMAError, zipfile.BadZipFile,
            NotImplementedError, RuntimeError, ValueError) as exc:
        text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError("file", str(p), f"cannot be decompressed as {kind}: {text} "
                         "(corrupt or truncated?)") from None
    return Decompressed(data=data, inner_name=inner, compression=kind)
