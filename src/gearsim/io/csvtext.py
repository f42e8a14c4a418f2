"""Delimited text tables (CSV/TXT) as instruments and scripts write them.

What is recognised, from the text itself:

* **comment lines** start with ``#``, ``%`` or ``//``. A comment ``key = value`` or
  ``key: value`` is metadata (``# fs = 25600``, ``# fs: 25.6 kHz``, ``# units = m/s^2``,
  ``# rpm = 1480``): kept in :attr:`TextTable.metadata` (numbers as float, else the
  text), keys lower-case with spaces as ``_``. The sampling rate keys of :data:`FS_KEYS`
  give :attr:`TextTable.fs` (a bare number is Hz; ``kHz``, ``S/s`` and ``samples/s`` are
  understood). ``units`` gives the units of every column, or of each column when it lists
  one per column;
* **delimiter**: tab, semicolon, comma (the first found the same number of times on the
  first lines), else runs of whitespace; with a semicolon, tab or whitespace delimiter a
  **decimal comma** (``1,25``) is recognised;
* **header row**: the first non-comment line is a header when one of its fields is not a
  number (an empty field counts as a missing number), otherwise it is the first data row
  and the columns are named ``"0", "1", ...``. Without one, a last comment line just
  above the data with as many fields (``np.savetxt`` writes ``# time,acc``) is the
  header. A header name ``acc [m/s^2]`` or ``acc (g)`` is the column ``acc`` in those
  units (``acc[label]``, no space, keeps its name);
* **missing values**: an empty field, ``NaN``, ``NA``, a row cut short (the missing
  fields) are NaN; a blank line between data rows is refused (a missing sample that
  would otherwise shift the rest of the record).
"""

from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError

__all__ = ["FS_KEYS", "TextTable", "decode_text", "parse_table"]

#: Metadata keys read as the sampling rate.
FS_KEYS = ("fs", "sampling_rate", "sample_rate", "samplerate", "sampling_frequency",
           "sample_frequency", "sampling_freq", "rate")

_COMMENTS = ("#", "%", "//")
_META = re.compile(r"^(?:#|%|//)\s*([A-Za-z_][\w .\-]*?)\s*[:=]\s*(.*?)\s*$")
_UNIT_IN_NAME = re.compile(r"^(.*?)\s*[\[(]\s*([^\])]*?)\s*[\])]\s*$")
_DECIMAL_COMMA = re.compile(r"^[+-]?(\d+,\d*|,\d+)([eE][+-]?\d+)?$")
_SAMPLE_LINES = 20
_PER_SECOND = re.compile(r"\s*(S/s|Sa/s|samples?/s|sps)\s*$", re.IGNORECASE)


@dataclass(frozen=True)
class TextTable:
    """A numeric table read from text (returned by :func:`parse_table`).

    Parameters
    ----------
    names : tuple of str
        Column names (from the header, else ``"0", "1", ...``).
    columns : ndarray, shape (n_rows, n_columns)
        Values (float64); missing values are NaN.
    metadata : dict
        ``key = value`` comment lines (numbers as float, else the text).
    fs : float or None
        Sampling rate from a comment (:data:`FS_KEYS`) [Hz].
    units : dict, optional
        Column name -> units (from the header name or a ``units`` comment).
    delimiter : str, optional
        ``","``, ``";"``, ``"\\t"`` or ``"whitespace"``.
    decimal : str, optional
        ``"."`` or ``","``.
    header : bool, optional
        Whether the names came from a header line.
    """

    names: tuple[str, ...]
    columns: np.ndarray
    metadata: dict
    fs: float | None
    units: dict[str, str] = field(default_factory=dict)
    delimiter: str = ","
    decimal: str = "."
    header: bool = False


def decode_text(raw: bytes) -> str:
    """Decode the bytes of a text record: UTF-8 (with or without BOM), UTF-16, or Latin-1.

    Parameters
    ----------
    raw : bytes
        File content.

    Returns
    -------
    str
        The text.
    """
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        return raw.decode("utf-16", errors="replace")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")  # Windows exports (e.g. "µm" in cp1252)


def _fail(shown: str, reason: str) -> InputError:
    return InputError("file", shown, f"cannot be read as CSV: {reason}")


def _number(text: str) -> float | str:
    try:
        return float(text)
    except ValueError:
        return text


def _parse_fs(value: str, shown: str, key: str) -> float:
    text = _PER_SECOND.sub(" Hz", value).strip()
    try:
        fs = float(text)
    except ValueError:
        from gearsim.units import to_si  # pint: loaded only for a rate with a unit

        fs = to_si(text, "frequency", f"{shown}: comment {key}")
    if not (np.isfinite(fs) and fs > 0):
        raise InputError(f"{shown}: comment {key}", value, "must be a sampling rate > 0 (Hz)")
    return fs


def _split(line: str, sep: str) -> list[str]:
    if sep == "whitespace":
        return line.split()
    return [f.strip() for f in next(csv.reader([line], delimiter=sep))]


def _delimiter(sample: list[str]) -> str:
    first, rest = sample[0], sample[1:]
    for sep in ("\t", ";", ","):
        n = first.count(sep)
        if n > 0 and all(line.count(sep) == n for line in rest):
            return sep
    for sep in ("\t", ";", ","):
        if first.count(sep) > 0:
            return sep  # rows disagree; the parser names the line
    return "whitespace" if len(first.split()) > 1 else ","


def _is_number(token: str, decimal: str) -> bool:
    if token == "":
        return True
    try:
        float(token.replace(",", ".") if decimal == "," else token)
    except ValueError:
        return False
    return True


def _metadata(key: str, value: str, meta: dict) -> None:
    key = re.sub(r"\s+", "_", key.strip().lower())
    meta[key] = _number(value)


def parse_table(text: str, shown: str) -> TextTable:
    """Parse a delimited numeric text table (see the module notes for what is recognised).

    Parameters
    ----------
    text : str
        Content of the file.
    shown : str
        File name used in messages.

    Returns
    -------
    TextTable

    Raises
    ------
    InputError
        No data row, a row with more fields than the first, a field that is not a number,
        a blank line between data rows, a header whose number of names differs from the
        number of columns, or a sampling-rate comment that is not a positive rate.
    """
    meta: dict = {}
    fs_key = None
    content: list[tuple[int, str, bool]] = []  # (line number, text, blank line before it)
    comment_header = None
    blank = None
    lines = text.splitlines()
    tail: str | None = None  # the data rows after the sampled lines, when plain
    for number, line in enumerate(lines, start=1):
        if len(content) > _SAMPLE_LINES and blank is None:
            # every line sampled: a plain rest is data rows only, one per line
            rest = "\n".join(lines[number - 1:])
            if _plain(rest):
                tail = rest
                break
        s = line.strip()
        if not s:
            if content and blank is None:
                blank = number
            continue
        if s.startswith(_COMMENTS):
            m = _META.match(s)
            if m:
                _metadata(m.group(1), m.group(2), meta)
                if re.sub(r"\s+", "_", m.group(1).strip().lower()) in FS_KEYS:
                    fs_key = m.group(1).strip()
            elif not content:
                comment_header = s.lstrip("#%/").strip() or None
            continue
        if "#" in s:
            s = s.split("#", 1)[0].strip()
            if not s:
                continue
        content.append((number, s, blank))
        blank = None
    if not content:
        raise _fail(shown, "holds no data row")
    sample = [s for _, s, _ in content[:_SAMPLE_LINES]]
    sep = _delimiter(sample)
    tokens = [t for s in sample[1:] for t in _split(s, sep)] or _split(sample[0], sep)
    decimal = "."
    if sep != "," and any(_DECIMAL_COMMA.match(t) for t in tokens) and not any(
            "." in t for t in tokens if _is_number(t, ".")):
        decimal = ","
    first = _split(content[0][1], sep)
    header = None
    if not all(_is_number(t, decimal) for t in first):
        header = first
        content = content[1:]
        if content:  # a blank line between the header and the data is harmless
            content[0] = (content[0][0], content[0][1], None)
    elif comment_header is not None:
        names = _split(comment_header, sep)
        if len(names) == len(first) and not all(_is_number(t, decimal) for t in names):
            header = names
    if not content:
        raise _fail(shown, "holds a header but no data row")
    for _, _, gap in content[1:]:
        if gap is not None:
            raise InputError(f"{shown}: line {gap}", "empty",
                             "every row must hold a finite number (a blank line inside the "
                             "data is a missing sample)")
    columns = _fast_numbers(content, tail, sep, decimal)
    if columns is None:
        if tail is not None:
            start = content[-1][0] + 1
            content += [(start + k, t, None) for k, t in enumerate(tail.split("\n"))]
        columns = _numbers(content, sep, decimal, shown, header or [])
    names = [str(j) for j in range(columns.shape[1])] if header is None else \
        [n.strip().strip("\"'") for n in header]
    # a delimiter at the end of every row makes an empty, unnamed last column
    while columns.shape[1] > len(names) and np.all(np.isnan(columns[:, -1])):
        columns = columns[:, :-1]
    while len(names) > columns.shape[1] and names[-1] == "":
        names.pop()
    if len(names) != columns.shape[1]:
        raise _fail(shown, f"the header names {len(names)} columns {names} but the data rows "
                    f"hold {columns.shape[1]}")
    # "a1 [g]" or "a1 (g)": channel a1 in g (a unit after a space: "var[label]" keeps
    # its name, the labels of gearsim's records)
    found = []
    for n in names:
        m = _UNIT_IN_NAME.match(n)
        ok = bool(m and m.group(1) and m.group(2))
        found.append((m.group(1) if ok and n[len(m.group(1))].isspace() else n,
                      m.group(2) if ok else None))
    names = _unique([n or str(j) for j, (n, _) in enumerate(found)])
    units: dict[str, str] = {n: u for n, (_, u) in zip(names, found, strict=True) if u}
    given = meta.get("units", meta.get("unit"))
    if isinstance(given, str) and given:
        parts = _split(given, sep if sep != "whitespace" else ",")
        if len(parts) == len(names) and len(names) > 1:
            units.update({n: u for n, u in zip(names, parts, strict=True) if u})
        else:
            units.update({n: given for n in names if n not in units})
    fs = None if fs_key is None else _parse_fs(
        str(meta[re.sub(r"\s+", "_", fs_key.lower())]), shown, fs_key)
    return TextTable(names=tuple(names), columns=columns, metadata=meta, fs=fs, units=units,
                     delimiter="whitespace" if sep == "whitespace" else sep,
                     decimal=decimal, header=header is not None)


def _unique(names: list[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for n in names:
        k = seen.get(n, 0)
        out.append(n if k == 0 else f"{n}.{k}")
        seen[n] = k + 1
    return out


_NOT_PLAIN = ("#", "%", "/", '"', "'", "_", "\n\n", " \n", "\t\n", "\n ", "\n\t")


def _plain(rest: str) -> bool:
    """Whether ``rest`` (lines joined by newlines) is data rows only: no comment, quote,
    blank line or space around a line, ASCII (numpy reads it as pandas would)."""
    return (rest.isascii() and not rest[:1].isspace() and not rest[-1:].isspace()
            and not any(p in rest for p in _NOT_PLAIN))


def _fast_numbers(content: list[tuple[int, str, object]], tail: str | None, sep: str,
                  decimal: str) -> np.ndarray | None:
    """The table by :func:`numpy.loadtxt` for plain rows of one delimiter, else None.

    The fast path of a long record (no pandas import, no row-by-row Python): only when
    every row after the sampled lines is plain (:func:`_plain`), with a dot decimal and a
    tab, semicolon or comma delimiter. Anything numpy refuses (missing fields, ``NA``,
    rows of other lengths, ...) goes to :func:`_numbers`, which names the line.
    """
    if tail is None or decimal != "." or sep not in ("\t", ";", ","):
        return None
    body = "\n".join([s for _, s, _ in content] + [tail])
    try:
        out = np.loadtxt(io.StringIO(body), delimiter=sep, dtype=np.float64, ndmin=2,
                         comments=None, quotechar=None)
    except ValueError:
        return None
    return out if out.shape[0] == len(content) + tail.count("\n") + 1 else None


def _numbers(content: list[tuple[int, str, object]], sep: str, decimal: str, shown: str,
             header: list[str]) -> np.ndarray:
    import pandas as pd

    body = "\n".join(s for _, s, _ in content)
    kwargs = {"sep": r"\s+"} if sep == "whitespace" else {"sep": sep, "skipinitialspace": True}
    try:
        df = pd.read_csv(io.StringIO(body), header=None, decimal=decimal, engine="c",
                         skip_blank_lines=False, **kwargs)
    except pd.errors.ParserError as exc:
        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
        if m:
            number = content[int(m.group(2)) - 1][0]
            raise _fail(shown, f"line {number} holds {m.group(3)} fields, the rows above "
                        f"{m.group(1)}") from None
        raise _fail(shown, str(exc).strip().splitlines()[-1]) from None
    except Exception as exc:  # pandas raises many types for malformed text
        raise _fail(shown, str(exc).strip().splitlines()[0] or type(exc).__name__) from None
    out = np.empty(df.shape, dtype=np.float64)
    for j in range(df.shape[1]):
        col = df.iloc[:, j]
        if not pd.api.types.is_numeric_dtype(col.dtype):
            text = col.astype(str).str.strip()
            num = pd.to_numeric(text.str.replace(",", ".") if decimal == "," else text,
                                errors="coerce")
            bad = np.flatnonzero(num.isna().to_numpy() & col.notna().to_numpy())
            if bad.size:
                i = int(bad[0])
                name = header[j].strip().strip("\"'") if j < len(header) else str(j)
                raise InputError(f"{shown}: column {name!r} data row {i + 1}", str(col.iloc[i]),
                                 f"must be a number (line {content[i][0]})")
            col = num
        out[:, j] = col.to_numpy(dtype=np.float64)
    return out
