"""CLI verb ``simulate``: train dynamics to a NetCDF file, with a JSON summary."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from gearsim.commands._options import as_options
from gearsim.dynamics import simulate as run
from gearsim.dynamics import summary
from gearsim.io.results import write_results
from gearsim.model import load
from gearsim.viz import save
from gearsim.viz.dynamics import plot_run

__all__ = ["register"]

def simulate(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    out: Annotated[Path, typer.Option(help="results file (NetCDF)")] = Path("run.nc"),
    crack: Annotated[str | None, typer.Option(
        help="none, working or non-working (default: as in the config)")] = None,
    duration: Annotated[float | None, typer.Option(help="recorded duration in s")] = None,
    fs: Annotated[float | None, typer.Option(help="output sampling rate in Hz")] = None,
    step: Annotated[float | None, typer.Option(help="largest integration step in s")] = None,
    transient: Annotated[float | None, typer.Option(help="dropped transient in s")] = None,
    model: Annotated[str | None, typer.Option(help="lta or seed")] = None,
    plot: Annotated[bool, typer.Option("--plot", help="also write a PNG beside --out")] = False,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
) -> None:
    """Simulate the gear train; write mesh forces, DTE, bearing forces, accelerations."""
    changes = {k: v for k, v in {"duration": duration, "fs": fs, "step": step,
                                 "transient": transient, "model": model}.items()
               if v is not None}
    gb = load(config)
    # every value is checked where the settings are made; the message names the option
    with as_options({"crack": "--crack", **{f"dynamics.{k}": f"--{k}" for k in changes}}):
        gb = gb.with_crack(crack).replace(dynamics=changes)
    ds = run(gb.train, gb.dynamics)
    path = write_results(ds, out)
    if plot:
        save(plot_run(ds), path.with_suffix(".png"))
    s = summary(ds)
    s["out"] = str(path)
    if json_:
        typer.echo(json.dumps(s, indent=2))
    else:
        for m in s["meshes"]:
            typer.echo(f"mesh {m['mesh']}: mean {m['mean']:.6g} N (static {m['static_force']:.6g}"
                       f" N, {100 * m['mean_error']:+.3f} %), RMS {m['rms']:.6g} N, peak "
                       f"{m['peak']:.6g} N")
        typer.echo(f"gearsim: results written to {path}")


def register(app: typer.Typer) -> None:
    """Add ``simulate`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("simulate")(simulate)
