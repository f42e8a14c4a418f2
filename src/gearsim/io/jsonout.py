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
    """``v`` with numpy values as Python ones and non-finite floats as ``None`` (recursive)."""
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
    """Strict JSON text of ``v`` (see :func:`plain`); raises ``ValueError`` on leftovers."""
    return json.dumps(plain(v), indent=indent, allow_nan=False)
