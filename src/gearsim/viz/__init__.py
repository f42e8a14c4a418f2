"""Figures. Every module here imports matplotlib lazily (Agg backend, no screen)."""


def pyplot():
    """Return matplotlib.pyplot with the non-interactive Agg backend."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 11, "axes.grid": True, "grid.alpha": 0.3,
                         "figure.dpi": 110, "savefig.dpi": 130})
    return plt


#: House style of the object-oriented figures (fonts >= 9 pt at the saved size, light grid).
RC = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
}


def figure(width: float, height: float):
    """A ``matplotlib.figure.Figure`` (Agg canvas, no GUI) in the house style."""
    import matplotlib
    from matplotlib.figure import Figure

    matplotlib.rcParams.update(RC)
    return Figure(figsize=(width, height), layout="constrained")
