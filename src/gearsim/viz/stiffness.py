"""Figures of the time-varying mesh stiffness."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gearsim.viz import pyplot

__all__ = ["plot_train_stiffness", "plot_healthy_vs_cracked"]


def plot_train_stiffness(ts, path: str | Path) -> Path:
    """TVMS of every mesh over one revolution of its driver, with load sharing.

    Parameters
    ----------
    ts : gearsim.stiffness.report.TrainStiffness
    path : output PNG
    """
    plt = pyplot()
    n = len(ts.train.pairs)
    fig, axes = plt.subplots(n, 2, figsize=(12, 3.6 * n), squeeze=False)
    for i, pair in enumerate(ts.train.pairs):
        r = ts.results[(i, 1)]
        ax = axes[i, 0]
        ax.plot(np.degrees(r.theta1), r.k / 1e9, lw=1.0, label="total")
        ax.set_xlabel(f"rotation of {pair.driver.name} [deg]")
        ax.set_ylabel("mesh stiffness [GN/m]")
        ax.set_title(f"mesh {pair.name}: {pair.driver.name} -> {pair.driven.name}")
        ax.legend(loc="lower right")
        ax = axes[i, 1]
        npc = r.attrs["positions_per_cycle"]
        sel = slice(0, 3 * npc)
        for m in range(r.pair_k.shape[1]):
            ax.plot(r.cycles[sel], r.load_share[sel, m], lw=1.0, label=f"pair {m}")
        ax.set_xlabel("mesh cycles [-]")
        ax.set_ylabel("load share [-]")
        ax.set_title(f"mesh {pair.name}: load sharing (3 cycles)")
        ax.legend(loc="upper right", fontsize=8, ncol=2)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def plot_healthy_vs_cracked(curves: dict[str, tuple[np.ndarray, np.ndarray]], path: str | Path,
                            *, title: str, xlabel: str) -> Path:
    """Overlay several stiffness curves ``label -> (x, k [N/m])``."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(10, 4))
    for label, (x, k) in curves.items():
        ax.plot(x, k / 1e9, lw=1.1, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("mesh stiffness [GN/m]")
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path
