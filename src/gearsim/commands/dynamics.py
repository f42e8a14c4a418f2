"""CLI verb ``simulate``: train dynamics to a NetCDF file, with a JSON summary."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Annotated

import typer

from gearsim.errors import InputError

__all__ = ["DEFAULT_CRACK", "register", "with_crack_choice"]

#: Crack used by ``--crack working|non-working`` when the config has none: the crack of
#: the built-in Table-1 example (input gear, tooth 0, 2 mm deep, 45 deg).
DEFAULT_CRACK = {"tooth": 0, "depth": 2e-3, "angle": math.radians(45.0)}


def with_crack_choice(train, crack: str | None):
    """``none``: no crack; ``working`` / ``non-working``: the config's cracks (or the
    default crack on the input gear) on that flank; ``None``: the config as it is."""
    from gearsim.stiffness.crack import Crack

    if crack is None:
        return train
    if crack == "none":
        return train.with_cracks(())
    if crack not in ("working", "non-working"):
        raise InputError("--crack", crack, 'must be "none", "working" or "non-working"')
    cracks = train.cracks or (Crack(gear=train.gears[0].name, **DEFAULT_CRACK),)
    return train.with_cracks(tuple(dataclasses.replace(c, flank=crack) for c in cracks))


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
    from gearsim.dynamics import DynamicsSettings, summary
    from gearsim.dynamics import simulate as run
    from gearsim.io.config import load
    from gearsim.io.results import write_results

    train = with_crack_choice(load(config), crack)
    settings = train.extra.get("dynamics") or DynamicsSettings()
    changes = {k: v for k, v in {"duration": duration, "fs": fs, "step": step,
                                 "transient": transient, "model": model}.items()
               if v is not None}
    for key, value in changes.items():
        if key == "model" and value not in ("lta", "seed"):
            raise InputError("--model", value, 'must be "lta" or "seed"')
        if key != "model" and not (isinstance(value, float) and value > 0
                                   or key == "transient" and value == 0):
            raise InputError(f"--{key}", value, "must be > 0")
    settings = dataclasses.replace(settings, **changes)
    ds = run(train, settings)
    path = write_results(ds, out)
    if plot:
        from gearsim.viz.dynamics import plot_run

        plot_run(ds, path.with_suffix(".png"))
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
    """Add ``simulate`` to ``app``."""
    app.command("simulate")(simulate)
