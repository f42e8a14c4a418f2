"""CLI verbs: ``example`` and ``stiffness``."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from gearsim.commands._options import as_options
from gearsim.io.targets import check_output_file
from gearsim.model import example_text, load
from gearsim.system import train_stiffness
from gearsim.viz import check_plot_file, save

__all__ = ["register"]


def example(name: Annotated[str, typer.Argument(help="idler-table1 or spur-19-48")]) -> None:
    """Print a built-in example configuration (TOML)."""
    typer.echo(example_text(name), nl=False)


def stiffness(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    out: Annotated[str | None, typer.Option(help="TVMS table, .csv or .nc")] = None,
    plot: Annotated[str | None, typer.Option(help="figure of the TVMS (.png, .pdf, .svg)")]
    = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
    crack: Annotated[str | None, typer.Option(help="none, working or non-working")] = None,
    closure: Annotated[str | None, typer.Option(help="open or contact")] = None,
) -> None:
    """Time-varying mesh stiffness of every mesh over one revolution of each gear."""
    # every output target is checked before any work
    if out is not None:
        out = check_output_file(out, "--out", (".csv", ".nc"))
    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)
    with as_options({"crack": "--crack", "stiffness.closure": "--closure"}):
        train = gb.train.with_crack(crack, closure=closure)
    ts = train_stiffness(train)
    if out is not None:
        ts.write(out)
    if plot is not None:
        save(ts.plot(), plot, parameter="--plot")
    summary = ts.summary()
    if json_:
        typer.echo(json.dumps(summary, indent=2))
    else:
        for m in summary["meshes"]:
            typer.echo(f"mesh {m['mesh']} ({m['gears'][0]} -> {m['gears'][1]}): "
                       f"k mean {m['k_mean'] / 1e9:.4f} GN/m, min {m['k_min'] / 1e9:.4f}, "
                       f"max {m['k_max'] / 1e9:.4f}; eps_alpha {m['eps_alpha']:.3f}, "
                       f"eps_beta {m['eps_beta']:.3f}; mean / ISO 6336 c_ga b = "
                       f"{m['ratio_to_iso6336']:.3f}")


def register(app: typer.Typer) -> None:
    """Add the verbs of this module to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`); ``example`` and ``stiffness``
        are registered on it.
    """
    app.command("example")(example)
    app.command("stiffness")(stiffness)

