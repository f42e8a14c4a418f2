"""CLI verb ``reproduce``: the seed's study on the built-in Table-1 idler train."""

from __future__ import annotations

import sys
import time
from typing import Annotated

import typer

from gearsim.commands._options import as_options
from gearsim.errors import InputError

__all__ = ["register"]


def _depth(text: str, option: str) -> float:
    """One crack depth: a length with a unit, or a plain number of millimetres."""
    from gearsim.units import to_si

    s = text.strip()
    try:
        float(s)  # a plain number ("2", "1e-1", "inf", "nan"): millimetres
    except ValueError:
        pass
    else:
        s = f"{s} mm"
    try:  # finite; a non-length unit ("a" is a year) is refused
        d = to_si(s, "length", option)
    except InputError as exc:
        raise InputError(option, text, exc.limit) from None
    if not d > 0:
        raise InputError(option, text, "a crack depth must be > 0 mm")
    return d


def _depths(text: str) -> tuple[float, ...]:
    parts = [p.strip() for p in text.split(",")]
    if not all(parts):
        raise InputError("--depths", text, "must list depths without empty items, e.g. '2 mm, "
                         "6 mm'")
    return tuple(_depth(p, "--depths") for p in parts)


def _severities(text: str) -> tuple[float, ...]:
    """Parse ``--fault-severities`` ("0.25, 0.5, 1" or "none")."""
    if text.strip().lower() == "none":
        return ()
    out = []
    for part in (p.strip() for p in text.split(",") if p.strip()):
        try:
            out.append(float(part))
        except ValueError:
            raise InputError("--fault-severities", part,
                             "must be numbers in (0, 1], comma separated, or 'none'") from None
    if not out:
        raise InputError("--fault-severities", text, "must list at least one severity or 'none'")
    return tuple(out)


def reproduce(
    out: Annotated[str, typer.Option(help="output folder (report.html, claims.json, "
                                          "figures/, dynamic_load.nc): new, empty or an "
                                          "earlier output; replaced as a whole")] = "out",
    config: Annotated[str, typer.Option(help="TOML file or built-in example name")]
    = "idler-table1",
    depth: Annotated[str, typer.Option(help="reference crack depth, e.g. '6 mm' "
                                            "(plain numbers are mm)")] = "6 mm",
    depths: Annotated[str, typer.Option(help="depths of the sensitivity study, comma "
                                             "separated (plain numbers are mm)")]
    = "1, 2, 4, 6, 8, 9",
    revolutions: Annotated[int, typer.Option(help="recorded input revolutions per case")] = 32,
    fe: Annotated[bool, typer.Option("--fe/--no-fe", help="also run the FE-stiffness route "
                                                          "and the FE tooth check")] = True,
    model: Annotated[str, typer.Option(help="dynamic model: lta or seed")] = "lta",
    fault_severities: Annotated[str, typer.Option(
        help="severities in (0, 1] of the fault-magnitude section (every fault class at "
             "each), comma separated; 'none' to skip it")] = "0.25, 0.5, 1",
    quiet: Annotated[bool, typer.Option("--quiet", help="no progress messages")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="run even above the cost bounds (1e9 integration steps over all "
                        "cases, half the memory); or set GEARSIM_FORCE=1")] = False,
) -> None:
    """Reproduce the seed's study (Shi, Li & Zhou 2025): healthy, working- and
    non-working-flank crack; figures like its Figs. 3, 5-8; claims table; report.html."""
    from gearsim.studies.reproduce import ReproduceOptions, check_output, run_reproduction

    names = {"revolutions": "--revolutions", "model": "--model", "depth": "--depth",
             "depths": "--depths", "fault_severities": "--fault-severities", "config": "--config"}
    # every option is checked before any work, and every problem reported (as analyze)
    problems: list[InputError] = []
    given = {"revolutions": revolutions, "model": model}

    def checked(fn, *args):
        try:
            with as_options(names):
                return fn(*args)
        except InputError as exc:
            problems.append(exc)
            return None

    folder = checked(check_output, out, "--out")  # every output target before any work
    given["depth"] = checked(_depth, depth, "--depth")
    given["depths"] = checked(_depths, depths)
    given["fault_severities"] = checked(_severities, fault_severities)
    for field, value in given.items():  # each range alone, the others at their defaults
        if value is not None:
            checked(lambda f=field, v=value: ReproduceOptions(**{f: v}))
    if len(problems) == 1:
        raise problems[0]
    if problems:  # as analyze: input = N problems: first; second
        raise InputError("input", f"{len(problems)} problems", "; ".join(map(str, problems)))
    opt = ReproduceOptions(config=config, fe=fe, **given)
    t0 = time.perf_counter()

    def progress(msg: str) -> None:
        if not quiet:
            print(f"[{time.perf_counter() - t0:6.1f} s] {msg}", file=sys.stderr, flush=True)

    with as_options(names):
        rep = run_reproduction(folder, opt, progress=progress, force=True if force else None)
    n_ok = sum(1 for f in rep.findings["PE"] if f["holds"])
    typer.echo(f"gearsim: {n_ok} of {len(rep.findings['PE'])} qualitative findings of the seed "
               f"hold (PE route); claims table in {folder / 'claims.json'}")
    typer.echo(f"gearsim: report written to {(folder / 'report.html').resolve()}")


def register(app: typer.Typer) -> None:
    """Add ``reproduce`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("reproduce")(reproduce)
