"""CLI verbs ``sweep`` (parameter study on Dask) and ``sweep-report`` (diagnostic table)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from gearsim.studies.diagnostic import diagnostic_report
from gearsim.studies.sweep import load_study
from gearsim.studies.sweep_run import run_study

__all__ = ["register"]


def sweep(
    study: Annotated[str, typer.Argument(help="study TOML file or built-in study name "
                                         "(diagnostic)")],
    out: Annotated[Path, typer.Option(help="results store (NetCDF, .nc); parts go to "
                                      "OUT.parts/")] = Path("sweep.nc"),
    scheduler: Annotated[str | None, typer.Option(
        help="address of a running Dask scheduler, e.g. tcp://host:8786 "
             "(default: a local cluster)")] = None,
    workers: Annotated[int, typer.Option(help="local worker processes (1 thread each)")] = 2,
    show: Annotated[bool, typer.Option("--show", help="print the study TOML and stop")] = False,
    progress: Annotated[bool, typer.Option(help="progress bar on stderr")] = True,
    report: Annotated[Path | None, typer.Option(
        help="also write the diagnostic report (CSV, JSON, PNG) to this folder")] = None,
) -> None:
    """Run a parameter study (crack depth, flank, closure, speed, torque, bearing stiffness,
    noise) on Dask; resumes from OUT.parts/ after an interruption."""

    st = load_study(study)
    if show:
        typer.echo(st.text, nl=False)
        return
    res = run_study(st, out, scheduler=scheduler, workers=workers, progress=progress)
    typer.echo(f"gearsim: {res.n_cases} cases ({res.computed} computed, {res.skipped} resumed,"
               f" {res.failed} failed) written to {res.store}")
    if report is not None:
        _report(res.store, report)


def _report(store: Path, out: Path) -> None:

    paths = diagnostic_report(store, out)
    for p in paths:
        typer.echo(f"gearsim: report written to {p}")


def sweep_report(
    store: Annotated[Path, typer.Argument(help="store written by gearsim sweep (.nc)")],
    out: Annotated[Path, typer.Option(help="output folder")] = Path("sweep-report"),
    json_: Annotated[bool, typer.Option("--json", help="print the summary as JSON")] = False,
) -> None:
    """Separability of healthy / working-flank / non-working-flank cracks per feature group
    (cross-validated logistic regression): table (CSV, JSON) and figure (PNG)."""

    paths = diagnostic_report(store, out)
    if json_:
        typer.echo(json.dumps(json.loads(paths[1].read_text()), indent=2))
    for p in paths:
        typer.echo(f"gearsim: report written to {p}")


def register(app: typer.Typer) -> None:
    """Add ``sweep`` and ``sweep-report`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("sweep")(sweep)
    app.command("sweep-report")(sweep_report)
