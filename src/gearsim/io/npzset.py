"""A small ``xarray.Dataset`` as NumPy ``.npz`` bytes: the part files of a study.

A study's part (one simulation group's table, :mod:`gearsim.studies.sweep_run`) is
written once and read once, by gearsim, and holds tens of 1-element variables. As a
NetCDF-4 file it cost ~0.25 s to write and ~0.14 s to read (h5netcdf creates every
variable with its HDF5 dimension scales: ~7 ms each; measured on 64-variable parts), more
than the analysis of the case. The same table as an uncompressed ``.npz`` (a zip of
``.npy`` arrays, NumPy's own format) with a JSON header costs about a millisecond each way.
Nothing is pickled: arrays are numeric, boolean or fixed-width text (``U``); object
arrays of strings are stored as ``U``; anything else is refused.

The format (:data:`FORMAT`, version 2): the variables (data, then coordinates) packed
by dtype, member ``d0``, ``d1``, ... holding the flattened arrays of one dtype end to end,
and ``__meta__`` (a 0-d text array), the JSON of ``{"format": FORMAT, "attrs": {...},
"blocks": [dtype, ...], "variables": [{"name", "dims", "attrs", "coord", "block",
"offset", "shape"}, ...]}``. A part holds tens of one-element variables of three or four
dtypes: reading an archive member costs ~50 us, so one member per dtype reads a
64-variable part in well under a millisecond where one member per variable (version 1:
members ``v0``, ``v1``, ... and no ``blocks``) took ~3.5 ms. Version 1 archives are still
read.
"""

from __future__ import annotations

import io
import json
import zipfile
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["FORMAT", "FORMAT_V1", "from_bytes", "to_bytes"]

#: Format tag written in the header; a part with another tag is unreadable (recomputed).
FORMAT = "gearsim-npzset-2"
#: The earlier tag, one archive member per variable: still read.
FORMAT_V1 = "gearsim-npzset-1"


def _plain(value):
    """An attribute value as JSON (NumPy scalars and arrays as Python numbers and lists)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _array(values: np.ndarray, name: str) -> np.ndarray:
    """``values`` in a dtype ``np.load(allow_pickle=False)`` reads back."""
    a = np.asarray(values)
    if a.dtype.kind == "O":
        if not all(isinstance(v, str) for v in a.flat):
            raise TypeError(f"variable {name!r}: object array of non-strings cannot be stored")
        a = a.astype(str) if a.size else a.astype("U1")
    if a.dtype.kind not in "biufcUSMm?":
        raise TypeError(f"variable {name!r}: dtype {a.dtype} cannot be stored")
    return a


def to_bytes(ds: xr.Dataset) -> bytes:
    """Encode ``ds`` (variables, coordinates, attributes) as ``.npz`` bytes.

    Parameters
    ----------
    ds : xarray.Dataset
        A dataset of in-memory NumPy variables; attributes must be JSON values
        (strings, numbers, lists of them; NumPy scalars and arrays are converted).

    Returns
    -------
    bytes
        An uncompressed ``.npz`` archive (see the module docstring).

    Raises
    ------
    TypeError
        A variable of object dtype holding non-strings, or an attribute that is not JSON.
    """
    blocks: dict[str, list[np.ndarray]] = {}  # dtype -> flattened arrays, end to end
    used: dict[str, int] = {}
    meta = []
    names = list(ds.data_vars) + list(ds.coords)
    for name in names:
        var = ds.variables[name]
        a = _array(var.values, str(name))
        key = a.dtype.str
        blocks.setdefault(key, []).append(a.ravel())
        meta.append({"name": name, "dims": list(var.dims), "coord": name in ds.coords,
                     "attrs": {k: _plain(v) for k, v in var.attrs.items()},
                     "block": list(blocks).index(key), "offset": used.get(key, 0),
                     "shape": list(a.shape)})
        used[key] = used.get(key, 0) + a.size
    head = {"format": FORMAT, "attrs": {k: _plain(v) for k, v in ds.attrs.items()},
            "blocks": list(blocks), "variables": meta}
    arrays = {f"d{i}": np.concatenate(parts) for i, parts in enumerate(blocks.values())}
    arrays["__meta__"] = np.array(json.dumps(head))
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def from_bytes(data: bytes) -> xr.Dataset:
    """Decode bytes of :func:`to_bytes` into an ``xarray.Dataset``.

    Parameters
    ----------
    data : bytes
        The archive.

    Returns
    -------
    xarray.Dataset
        The dataset as encoded (object string arrays come back as ``U`` text).

    Raises
    ------
    ValueError
        Not such an archive, or one of another format.
    """
    import xarray as xr

    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            head = json.loads(str(z["__meta__"][()]))
            fmt = head.get("format") if isinstance(head, dict) else None
            if fmt == FORMAT:
                blocks = [z[f"d{i}"] for i in range(len(head["blocks"]))]
                variables = []
                for m in head["variables"]:
                    a = blocks[m["block"]]
                    n = int(np.prod(m["shape"], dtype=np.int64))
                    if a.dtype.str != head["blocks"][m["block"]] or m["offset"] + n > a.size:
                        raise ValueError(f"variable {m['name']!r} outside its block")
                    variables.append((m, a[m["offset"]:m["offset"] + n].reshape(m["shape"])))
            elif fmt == FORMAT_V1:
                variables = [(m, z[f"v{i}"]) for i, m in enumerate(head["variables"])]
            else:
                variables = []
    except (OSError, EOFError, KeyError, TypeError, ValueError, zipfile.BadZipFile) as exc:
        # not a zip (np.load then refuses it as a pickle), truncated, a member missing
        raise ValueError(f"not a gearsim part archive: {exc}") from exc
    if fmt not in (FORMAT, FORMAT_V1):
        raise ValueError(f"not a gearsim part archive: format {fmt!r}, expected {FORMAT!r}")
    data_vars = {m["name"]: xr.Variable(m["dims"], a, m["attrs"])
                 for m, a in variables if not m["coord"]}
    coords = {m["name"]: xr.Variable(m["dims"], a, m["attrs"])
              for m, a in variables if m["coord"]}
    return xr.Dataset(data_vars, coords=coords, attrs=head["attrs"])
