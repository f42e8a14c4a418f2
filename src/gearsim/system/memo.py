"""A bounded in-memory cache shared by the threads of a process (Dask workers run tasks in
threads): the least recently used entry is dropped first.

Used for results that cases of a study share instead of recomputing them: the mesh
stiffness tables (:meth:`gearsim.system.GearTrain.mesh_stiffness`) and the centre-distance
derivative of a mesh's stiffness (:func:`gearsim.dynamics.tables.centre_distance_derivative`).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Hashable
from typing import Any

__all__ = ["Memo"]


class Memo:
    """Least-recently-used cache of at most ``size`` entries, thread-safe.

    Parameters
    ----------
    size : int
        Entries kept (>= 1).

    Examples
    --------
    >>> m = Memo(2)
    >>> m.put("a", 1); m.put("b", 2); m.get("a"); m.put("c", 3)
    1
    >>> m.get("b") is None, len(m)
    (True, 2)
    """

    def __init__(self, size: int) -> None:
        self.size = size
        self._entries: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Hashable) -> Any | None:
        """The value stored under ``key`` (now the most recently used), or ``None``.

        Parameters
        ----------
        key : hashable
            Everything the value depends on.

        Returns
        -------
        object or None
        """
        with self._lock:
            hit = self._entries.get(key)
            if hit is not None:
                self._entries.move_to_end(key)
            return hit

    def put(self, key: Hashable, value: Any) -> None:
        """Store ``value`` under ``key``, dropping the least recently used beyond ``size``.

        Parameters
        ----------
        key : hashable
            Everything the value depends on.
        value : object
            The value (not ``None``).
        """
        with self._lock:
            self._entries[key] = value
            while len(self._entries) > self.size:
                self._entries.popitem(last=False)

    def clear(self) -> None:
        """Drop every entry."""
        with self._lock:
            self._entries.clear()

    def __len__(self) -> int:
        return len(self._entries)
