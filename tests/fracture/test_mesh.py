"""Cracked meshes: the split along a polyline crack gives two free faces."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import MeshTri

from gearsim.errors import InputError
from gearsim.fracture.mesh import CrackPath, mesh_cracked_polygon

SQUARE = np.array([[0.0, -1.0], [2.0, -1.0], [2.0, 1.0], [0.0, 1.0], [0.0, 0.0]]) * 1e-2


def _boundary_length(p: np.ndarray, t: np.ndarray) -> float:
    m = MeshTri(p, t)
    f = m.facets[:, m.boundary_facets()]
    return float(np.sum(np.hypot(*(p[:, f[0]] - p[:, f[1]]))))


def _areas(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    a, b, c = (p[:, t[i]] for i in range(3))
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


@pytest.mark.parametrize("points", [
    ((0.0, 0.0), (0.6e-2, 0.0)),                                   # straight edge crack
    ((0.0, 0.0), (0.5e-2, 0.0), (0.8e-2, 0.25e-2)),                # kinked (grown) crack
    ((0.0, 0.0), (0.4e-2, -0.1e-2), (0.7e-2, 0.1e-2), (0.9e-2, 0.0)),  # zig-zag
])
def test_split_edge_crack_has_two_free_faces(points) -> None:
    crack = CrackPath(points=points, tips=(False, True))
    cm = mesh_cracked_polygon(SQUARE, crack, h=0.4e-2, h_tip=0.05e-2)
    perimeter = 2 * (2e-2 + 2e-2)
    # both faces of the crack are boundary: perimeter + 2 crack lengths
    assert _boundary_length(cm.p, cm.t) == pytest.approx(perimeter + 2 * crack.length,
                                                         rel=1e-12)
    assert np.all(np.abs(_areas(cm.p, cm.t)) > 0.0)
    # every crack node but the tip duplicated, at the same place
    np.testing.assert_array_equal(cm.p[:, cm.pairs[0]], cm.p[:, cm.pairs[1]])
    tip = cm.tip_nodes[1]
    np.testing.assert_allclose(cm.p[:, tip], points[-1], atol=1e-15)
    assert tip not in cm.pairs


def test_split_internal_crack_keeps_both_tips() -> None:
    outline = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * 1e-2
    crack = CrackPath(points=((-0.3e-2, -0.1e-2), (0.3e-2, 0.1e-2)), tips=(True, True))
    cm = mesh_cracked_polygon(outline, crack, h=0.4e-2, h_tip=0.05e-2)
    assert _boundary_length(cm.p, cm.t) == pytest.approx(8e-2 + 2 * crack.length, rel=1e-12)
    assert set(cm.tip_nodes) == {0, 1}
    assert not set(cm.tip_nodes.values()) & set(cm.pairs.ravel().tolist())


def test_path_leaving_the_body_refused() -> None:
    crack = CrackPath(points=((0.0, 0.0), (0.5e-2, 0.0), (0.5e-2, 1.5e-2)))
    with pytest.raises(InputError, match="leaves the body") as err:
        mesh_cracked_polygon(SQUARE, crack, h=0.4e-2, h_tip=0.05e-2)
    assert "\n" not in str(err.value)


def test_bad_crack_and_sizes_refused() -> None:
    with pytest.raises(InputError, match="crack.points"):
        CrackPath(points=((0.0, 0.0), (0.0, 0.0)))
    with pytest.raises(InputError, match="mouth"):
        mesh_cracked_polygon(SQUARE, CrackPath(points=((0.0, 0.3e-2), (0.5e-2, 0.3e-2))),
                             h=0.4e-2, h_tip=0.05e-2)
    with pytest.raises(InputError, match="mesh.h_tip"):
        mesh_cracked_polygon(SQUARE, CrackPath(points=((0.0, 0.0), (0.5e-2, 0.0))),
                             h=0.4e-2, h_tip=1.0)
