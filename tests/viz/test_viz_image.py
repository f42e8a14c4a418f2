"""Image-level check of a rendered figure: pixels, not just the Artists.

The TVMS of mesh I of the built-in Table-1 train is drawn healthy (blue) and with the
example root crack on input tooth 0 (red, drawn on top) into one panel with
:func:`gearsim.viz.stiffness.plot_mesh_tvms`. The figure is rendered with its Agg
canvas and the curves are found by colour. Around the cracked tooth the red curve must
lie *below* the blue one on screen (larger row index: a stiffness loss), by as many
pixels as the data say, and elsewhere the two coincide. A figure drawn with swapped
curves, an inverted or wrongly scaled axis, or data shifted along the rotation fails.

Tolerance: a curve "passes through" a data point if a pixel of its colour lies within
3 px of the point's screen position (rows; +-1 column). The lines are 1 pt wide (1.8 px
at 130 dpi) and anti-aliased, so a pure-colour pixel lies within 1 px of the exact line;
rounding the column adds up to 0.5 px horizontally, which on the steepest flanks of the
stiffness steps (about 1 px per px) is 0.5 px vertically. 3 px leaves margin for both and
is far below the stiffness loss the test requires on screen (more than 25 px), so it
cannot hide a missing or misplaced drop. "Below" compares the median rows of the two
colours per column, required in 90 % of the columns (the steep flanks are drawn as
vertical runs whose medians can cross).
"""

from __future__ import annotations

import numpy as np
import pytest


def _mask(img: np.ndarray, colour: str) -> np.ndarray:
    r, g, b = (img[..., i].astype(int) for i in range(3))
    if colour == "red":
        return (r > 180) & (g < 90) & (b < 90)
    return (b > 180) & (r < 90) & (g < 90)


def _hits(mask: np.ndarray, cols: np.ndarray, rows: np.ndarray, tol: int = 3) -> np.ndarray:
    """Whether a pixel of ``mask`` lies within ``tol`` px of each point (col, row)."""
    r = np.round(rows).astype(int)
    return np.array([mask[max(0, y - tol): y + tol + 1, max(0, x - 1): x + 2].any()
                     for x, y in zip(cols, r, strict=True)])


def _median_rows(mask: np.ndarray, cols: np.ndarray) -> np.ndarray:
    out = np.full(cols.size, np.nan)
    for i, c in enumerate(cols):
        rows = np.flatnonzero(mask[:, c])
        if rows.size:
            out[i] = np.median(rows)
    return out


@pytest.fixture(scope="module")
def curves(idler):
    from gearsim.system import train_stiffness

    train = idler
    assert train.cracks, "the example has a crack"
    return train_stiffness(train.with_cracks(())), train_stiffness(train)


def test_cracked_curve_lies_below_the_healthy_one_in_pixels(curves):
    from gearsim.viz.stiffness import plot_mesh_tvms

    healthy, cracked = curves
    fig = plot_mesh_tvms(healthy, 0, color="#0000ff", label="healthy")
    ax = fig.axes[0]
    assert plot_mesh_tvms(cracked, 0, color="#ff0000", label="cracked", ax=ax) is fig
    ax.get_legend().remove()  # its line samples are red and blue too
    rh, rc = healthy.results[(0, 1)], cracked.results[(0, 1)]
    theta = np.degrees(rh.theta1)
    drop = rh.k - rc.k
    centre = theta[np.argmax(drop)]
    ax.set_ylim(0.99 * rc.k.min() / 1e9, 1.01 * rh.k.max() / 1e9)

    def render(lo: float, hi: float):
        """Pixels of the view lo..hi [deg] and the screen position of the data there."""
        ax.set_xlim(lo, hi)
        fig.canvas.draw()
        img = np.asarray(fig.canvas.buffer_rgba())[..., :3]
        sel = (theta > lo + 0.5) & (theta < hi - 0.5)

        def pixels(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            xy = ax.transData.transform(np.column_stack([theta[sel], k[sel] / 1e9]))
            return np.round(xy[:, 0]).astype(int), img.shape[0] - xy[:, 1]

        return _mask(img, "red"), _mask(img, "blue"), sel, pixels

    # around the cracked tooth (three mesh periods): red below blue, where the data say
    red, blue, sel, pixels = render(centre - 14.0, centre + 14.0)
    cols, row_h = pixels(rh.k)
    _, row_c = pixels(rc.k)
    near = drop[sel] > 0.5 * drop.max()
    assert near.sum() > 20
    assert np.max(row_c - row_h) > 25, "the crack must show as a clear drop on screen"
    red_rows, blue_rows = _median_rows(red, cols[near]), _median_rows(blue, cols[near])
    seen = np.isfinite(red_rows) & np.isfinite(blue_rows)
    assert seen.mean() > 0.9
    assert np.all(red_rows[seen] > blue_rows[seen]), "cracked curve not below the healthy one"
    assert _hits(red, cols, row_c).all()
    assert _hits(blue, cols[near], row_h[near]).all()
    assert not _hits(red, cols[near], row_h[near]).any()  # no red where healthy is

    # half a revolution away the crack is out of mesh: the curves coincide and the red
    # one (drawn last) hides the blue one
    red, blue, sel, pixels = render(centre + 166.0, centre + 194.0)
    assert np.all(drop[sel] == 0)
    cols, row_far = pixels(rc.k)
    assert _hits(red, cols, row_far).all()
    assert blue[:, cols.min():cols.max()].sum() < 0.2 * red[:, cols.min():cols.max()].sum()
