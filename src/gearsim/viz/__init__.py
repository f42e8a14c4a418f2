"""Figures. Every module here imports matplotlib lazily (Agg backend, no screen)."""


def pyplot():
    """Return matplotlib.pyplot with the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 11, "axes.grid": True, "grid.alpha": 0.3,
                         "figure.dpi": 110, "savefig.dpi": 130})
    return plt
