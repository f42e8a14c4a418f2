"""CLI verbs ``sweep`` (parameter study on Dask) and ``sweep-report`` (diagnostic table)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from gearsim.errors import InputError

__all__ = ["register"]


def sweep(
    study: Annotated[str, typer.Argument(help="study TOML file or built-in study name "
                                         "(diagnostic, faults)")],
    out: Annotated[Path, typer.Option(help="results store (NetCDF, .nc); parts go to "
                                      "OUT.parts/")] = Path("sweep.nc"),
    scheduler: Annotated[str | None, typer.Option(
        help="address of a running Dask scheduler, e.g. tcp://host:8786 "
             "(default: a local cluster)")] = None,
    workers: Annotated[int | None, typer.Option(
        help="local worker processes (1 thread each; default one per CPU core and "
             "simulation; more than the study's simulations is refused, more than the "
             "cores reduced)")] = None,
    batch: Annotated[int | None, typer.Option(
        help="simulations per Dask task (one part file each; default: about 10 tasks "
             "per worker, at most 32 simulations each)")] = None,
    show: Annotated[bool, typer.Option("--show", help="print the study TOML and stop")] = False,
    progress: Annotated[bool, typer.Option(help="progress bar on stderr")] = True,
    report: Annotated[Path | None, typer.Option(
        help="also write the diagnostic report (CSV, JSON, PNG) to this folder")] = None,
) -> None:
    """Run a parameter study (crack depth and flank or fault class and severity, closure,
    speed, torque, bearing stiffness, noise) on Dask; resumes from OUT.parts/ after an
    interruption."""
    from gearsim.io.targets import check_output_file, check_output_folder
    from gearsim.studies.diagnostic import (
        CLASSES,
        FAULT_CLASSES,
        REPORT_NAMES,
        require_simulations,
    )
    from gearsim.studies.sweep import expand, load_study
    from gearsim.studies.sweep_run import (
        check_batch,
        check_scheduler,
        check_workers,
        groups,
        run_study,
    )

    st = load_study(study)  # every study-wide setting is checked here, once
    if show:
        typer.echo(st.text, nl=False)
        return
    workers = check_workers(workers, len(groups(st)), "simulation")
    check_batch(batch)
    if scheduler is not None:
        check_scheduler(scheduler)
    check_output_file(out, "--out", (".nc",))
    if report is not None:
        check_output_folder(report, "--report", owned=REPORT_NAMES.__contains__)
        what, order = ("fault", FAULT_CLASSES) if "fault" in st.parameters else ("flank",
                                                                                CLASSES)
        cases = expand(st)
        labels = [getattr(c, what) for c in cases]
        classes = sorted(set(labels), key=order.index)
        if len(classes) < 2:
            raise InputError("--report", str(report), f"the study has {len(classes)} {what} "
                             f"class ({', '.join(classes)}); the diagnostic report compares "
                             "at least two of " + ", ".join(order))
        require_simulations(labels, [c.noise for c in cases],  # folds grouped by simulation
                            [st.simulation_key(c) for c in cases], classes, "--report",
                            str(report), "the study is ")
    res = run_study(st, out, scheduler=scheduler, workers=workers, progress=progress,
                    note=lambda line: typer.echo(line, err=True), batch=batch)
    typer.echo(f"gearsim: {res.n_cases} cases ({res.computed} computed, {res.skipped} resumed,"
               f" {res.failed} failed) written to {res.store}")
    if report is not None:
        _report(res.store, report)


def _report(store: Path, out: Path) -> None:

    from gearsim.studies.diagnostic import diagnostic_report

    paths = diagnostic_report(store, out, out_parameter="--report")
    typer.echo(_folds_line(json.loads(paths[1].read_text())))
    for p in paths:
        typer.echo(f"gearsim: report written to {p}")


def _folds_line(doc: dict) -> str:
    """One line on the report's cross-validation: grouped by simulation, the simulations
    of each class, the folds used and the rows left unscored."""
    folds = sorted({r["folds"] for r in doc["rows"]})
    n_na = sum(1 for r in doc["rows"] if r["folds"] < 2)
    return ("gearsim: folds grouped by simulation ("
            + ", ".join(f"{c} {n}" for c, n in doc["simulations"].items()) + " simulations); "
            + "/".join(map(str, folds)) + " folds"
            + (f"; {n_na} of {len(doc['rows'])} rows n/a (< 2 simulations of a class)"
               if n_na else ""))


def sweep_report(
    store: Annotated[Path, typer.Argument(help="store written by gearsim sweep (.nc)")],
    out: Annotated[Path, typer.Option(help="output folder")] = Path("sweep-report"),
    json_: Annotated[bool, typer.Option("--json", help="print the summary as JSON")] = False,
) -> None:
    """Separability of the fault classes (healthy / working-flank / non-working-flank crack,
    or the fault coordinate of a fault study) per feature group (cross-validated logistic
    regression): table (CSV, JSON with confusion matrices) and figure (PNG)."""
    from gearsim.studies.diagnostic import diagnostic_report


    paths = diagnostic_report(store, out)
    doc = json.loads(paths[1].read_text())
    typer.echo(json.dumps(doc, indent=2) if json_ else _folds_line(doc))
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
