"""Strict JSON text of result dictionaries (numpy values, NaN -> null).

JSON has no NaN or infinity; results use ``None`` (``null``) where a quantity does not
exist. Numpy scalars and arrays become Python numbers and lists.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

__all__ = ["plain", "strict_json"]


def plain(v: Any) -> Any:
    """``v`` with numpy values as Python ones and non-finite floats as ``None`` (recursive).

    Parameters
    ----------
    v : object
        A value: dicts (keys become ``str``), lists and tuples (become lists), numpy
        arrays (become nested lists), numpy or Python scalars; other objects are
        returned unchanged.

    Returns
    -------
    object
        The same structure with Python ``bool``, ``int``, ``float`` and ``None`` for NaN
        and infinities.

    Examples
    --------
    >>> import numpy as np
    >>> from gearsim.io.jsonout import plain
    >>> plain({1: np.array([1.5, np.nan]), "n": np.int64(3), "ok": np.bool_(True)})
    {'1': [1.5, None], 'n': 3, 'ok': True}
    """
    if isinstance(v, dict):
        return {str(k): plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return plain(v.tolist())
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(v) if math.isfinite(v) else None
    return v


def strict_json(v: Any, *, indent: int | None = 2) -> str:
    """Strict JSON text of ``v`` (see :func:`plain`); raises ``ValueError`` on leftovers.

    Parameters
    ----------
    v : object
        A value made of dicts, lists, tuples, numpy arrays and scalars.
    indent : int or None, optional
        Indentation of :func:`json.dumps`; ``None``: one line.

    Returns
    -------
    str
        JSON text without ``NaN`` or ``Infinity``.

    Raises
    ------
    ValueError
        If a non-finite float is left after :func:`plain` (``allow_nan=False``).
    TypeError
        If a value is not JSON serialisable.

    Examples
    --------
    >>> from gearsim.io.jsonout import strict_json
    >>> strict_json({"x": float("inf"), "y": (1, 2)}, indent=None)
    '{"x": null, "y": [1, 2]}'
    """
    return json.dumps(plain(v), indent=indent, allow_nan=False)
