"""CLI verb ``fe-check``: finite-element versus potential-energy tooth compliance."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from gearsim.fem.check import fe_check
from gearsim.model import load
from gearsim.viz import save

__all__ = ["fe_check_command", "register"]


def fe_check_command(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    gear: Annotated[str | None, typer.Option(help="gear to check (default: the cracked "
                                                  "gear, else the first)")] = None,
    crack: Annotated[str, typer.Option(help="none, working or non-working")] = "none",
    closure: Annotated[str | None, typer.Option(help="open or contact (default: "
                                                     "config)")] = None,
    level: Annotated[int, typer.Option(help="mesh level N: element size m_n/(4 2^N) on the "
                                            "loaded tooth")] = 2,
    points: Annotated[int, typer.Option(help="contact positions on the path")] = 11,
    plot: Annotated[Path | None, typer.Option(help="folder for the PNG figures")] = None,
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
        Contact positions along the path of contact.
    plot : Path, optional
        Folder for the PNG figure ``fe_check_<gear>_<crack>_<closure>.png``.
    json_ : bool
        Print the JSON report instead of the table (option ``--json``).

    Raises
    ------
    InputError
        An unknown gear, crack or closure, or a bad config (exit status 2 in the CLI).
    """
    result = fe_check(load(config).train, gear, crack=crack, closure=closure, level=level,
                      points=points)
    if plot is not None:
        name = f"fe_check_{result.gear.name}_{result.crack}_{result.closure}.png"
        save(result.plot(), Path(plot) / name)
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
