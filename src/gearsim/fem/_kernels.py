"""Compiled kernels of the finite-element meshing (numba)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["polygon_crosses_itself"]


@njit(cache=True)
def polygon_crosses_itself(poly: np.ndarray) -> bool:
    """True if two non-adjacent edges of the closed polygon ``poly`` cross properly.

    Edge ``i`` joins vertex ``i`` to ``i + 1`` (the last to the first). Two edges cross
    when each separates the other's end points: the orientation products
    ``orient(a, b, c) orient(a, b, d) < 0`` and ``orient(c, d, a) orient(c, d, b) < 0``
    (de Berg et al., *Computational Geometry*, 3rd ed., 2008, sec. 2.1). Brute force over
    the pairs, stopping at the first crossing: ``n (n - 3) / 2`` tests.

    Parameters
    ----------
    poly : ndarray, shape (n, 2)
        Vertices [m] (any length unit), not repeated at the end.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> bow = np.array([[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]])
    >>> bool(polygon_crosses_itself(square)), bool(polygon_crosses_itself(bow))
    (False, True)
    """
    n = poly.shape[0]
    for i in range(n):
        ax, ay = poly[i, 0], poly[i, 1]
        bx, by = poly[(i + 1) % n, 0], poly[(i + 1) % n, 1]
        last = n - 1 if i == 0 else n
        for j in range(i + 2, last):
            cx, cy = poly[j, 0], poly[j, 1]
            dx, dy = poly[(j + 1) % n, 0], poly[(j + 1) % n, 1]
            o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
            if o1 * o2 >= 0.0:
                continue
            o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
            o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
            if o3 * o4 < 0.0:
                return True
    return False
