"""Figures of the finite-element check (matplotlib imported lazily, Agg backend)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gearsim.viz import pyplot

__all__ = ["plot_fe_check", "plot_mesh"]


def plot_fe_check(check, path: str | Path) -> Path:
    """FE and PE tooth stiffness along the path of contact, and their ratio.

    Parameters
    ----------
    check : gearsim.fem.check.FECheck
    path : output PNG
    """
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    roll = np.degrees(check.roll_angle)
    b = check.gear.face_width
    ax = axes[0]
    ax.plot(roll, check.k_fe * b / 1e9, "o-", label=f"FE (level {check.fe_result.level})")
    ax.plot(roll, check.k_pe * b / 1e9, "s--", label="potential energy")
    ax.set_xlabel("roll angle [deg]")
    ax.set_ylabel(f"tooth stiffness, b = {b * 1e3:.4g} mm [GN/m]")
    ax.set_title(f"{check.gear.name}: crack {check.crack}, {check.closure}")
    ax.legend()
    d = check.differences()
    labels = list(d)
    axes[1].bar(labels, [d[k] for k in labels])
    axes[1].axhline(0.0, color="k", lw=0.8)
    axes[1].set_ylabel("(k_PE - k_FE) / k_FE [%]")
    axes[1].set_title("max / min / mean")
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out


def plot_mesh(p: np.ndarray, t: np.ndarray, path: str | Path, *, window=None,
              crack=None) -> Path:
    """The triangulation (optionally zoomed to ``window`` = (x0, x1, y0, y1) [m])."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.triplot(p[0] * 1e3, p[1] * 1e3, t.T, lw=0.3, color="0.3")
    if crack is not None:
        ax.plot([crack.start[0] * 1e3, crack.tip[0] * 1e3],
                [crack.start[1] * 1e3, crack.tip[1] * 1e3], "r-", lw=1.5)
    if window is not None:
        ax.set_xlim(window[0] * 1e3, window[1] * 1e3)
        ax.set_ylim(window[2] * 1e3, window[3] * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.grid(False)
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out
