"""CLI verb ``fe-check``: finite-element versus potential-energy tooth compliance."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from gearsim.commands._options import as_options
from gearsim.fem.check import fe_check
from gearsim.io.targets import atomic_folder, check_output_folder
from gearsim.model import load
from gearsim.viz import save

__all__ = ["fe_check_command", "register"]


def _figure_file(name: str) -> bool:
    """A figure ``fe-check`` writes (the other ones are kept when the folder is replaced)."""
    return name.startswith("fe_check_") and name.endswith(".png")


def fe_check_command(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    gear: Annotated[str | None, typer.Option(help="gear to check (default: the cracked "
                                                  "gear, else the first)")] = None,
    crack: Annotated[str, typer.Option(help="none, working or non-working")] = "none",
    closure: Annotated[str | None, typer.Option(help="open or contact (default: "
                                                     "config)")] = None,
    level: Annotated[int, typer.Option(help="mesh level N: element size m_n/(4 2^N) on the "
                                            "loaded tooth")] = 2,
    points: Annotated[int, typer.Option(help="contact positions on the path (3 to 201)")]
    = 11,
    plot: Annotated[str | None, typer.Option(
        help="folder for the PNG figures (fe_check_*.png only; replaced as a whole, "
             "keeping the other fe_check_*.png)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON report")] = False,
) -> None:
    """FE and potential-energy tooth compliance along the path of contact, with the
    max / min / mean differences (the seed's Figure 3) and the mesh level used.
    \f

    The first paragraph is the command help: Typer and Click cut the help at the form
    feed ``\\f`` above, and list the first paragraph; the rest documents the function
    (it calls :func:`gearsim.fem.check.fe_check`).

    Parameters
    ----------
    config : str
        TOML file or built-in example name.
    gear : str, optional
        Gear to check; default the first cracked gear, else the first gear.
    crack : str
        ``"none"``, ``"working"`` or ``"non-working"``; depth and angle from the
        config's crack on that gear.
    closure : str, optional
        ``"open"`` or ``"contact"``; default the config's ``stiffness.closure``.
    level : int
        FE mesh level N: element size m_n / (4 2^N) on the loaded tooth.
    points : int
        Contact positions along the path of contact (3 to
        :data:`gearsim.fem.check.MAX_POINTS`).
    plot : str, optional
        Folder for the PNG figure ``fe_check_<gear>_<crack>_<closure>.png``. Checked
        before any work; an existing folder may hold only ``fe_check_*.png`` figures,
        which are kept. The folder is written as a whole (temporary folder, then
        swapped in).
    json_ : bool
        Print the JSON report instead of the table (option ``--json``).

    Raises
    ------
    InputError
        An unknown gear, crack or closure, too many points, a bad config or an
        unwritable ``--plot`` folder (exit status 2 in the CLI).
    """
    folder = None
    if plot is not None:  # every output target is checked before any work
        folder = check_output_folder(plot, "--plot", owned=_figure_file)
    train = load(config).train
    with as_options({"fem.level": "--level", "points": "--points"}):
        result = fe_check(train, gear, crack=crack, closure=closure, level=level,
                          points=points)
    if folder is not None:
        name = f"fe_check_{result.gear.name}_{result.crack}_{result.closure}.png"
        with atomic_folder(folder, keep=_figure_file) as tmp:
            save(result.plot(), Path(tmp) / name, parameter="--plot")
    if json_:
        typer.echo(json.dumps(result.to_dict(), indent=2))
        return
    r = result.fe_result
    b = result.gear.face_width
    typer.echo(f"gear {result.gear.name}: crack {result.crack}, closure {result.closure}, "
               f"plane {result.plane}; FE mesh level {r.level} (element size "
               f"{r.h * 1e3:.4g} mm, {r.elements} P2 triangles, {r.dofs} dofs)")
    typer.echo(f"{'radius mm':>10} {'roll deg':>9} {'k_FE GN/m':>10} {'k_PE GN/m':>10} "
               f"{'PE/FE':>7}")
    for i in range(result.radii.size):
        kf, kp = result.k_fe[i] * b, result.k_pe[i] * b
        typer.echo(f"{result.radii[i] * 1e3:10.4f} {result.roll_angle[i] * 57.29578:9.3f} "
                   f"{kf / 1e9:10.4f} {kp / 1e9:10.4f} {kp / kf:7.4f}")
    d = result.differences()
    typer.echo(f"difference (k_PE - k_FE)/k_FE: max {d['max']:+.2f} %, min {d['min']:+.2f} %, "
               f"mean {d['mean']:+.2f} % (seed Fig. 3b: 6.7 / 5.6 / 6.3 %)")


def register(app: typer.Typer) -> None:
    """Add ``fe-check`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`); :func:`fe_check_command` is
        registered under the name ``fe-check``.
    """
    app.command("fe-check")(fe_check_command)
