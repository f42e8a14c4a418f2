"""Command-line interface: a thin typer layer over the Python API, with one error path.

Each verb lives in a module of :mod:`gearsim.commands` that defines ``register(app)``;
this module collects them (on first use, so that ``import gearsim.cli`` is light and an
interrupt during start-up is handled like any other) and turns every way a run can end
into one line on standard error and an exit status:

========================================  ==========================================  ====
what happened                             standard error                              exit
========================================  ==========================================  ====
bad input (:class:`InputError`)           ``gearsim: error: PARAM = VALUE: LIMIT``    2
usage error (unknown option or verb,      ``gearsim: error: MESSAGE (see gearsim       2
missing argument, ``--fs abc``)           VERB --help)``
failed computation (``SimulationError``)  ``gearsim: failed: MESSAGE``                1
Ctrl-C (``KeyboardInterrupt``, abort)     ``gearsim: interrupted``                    130
anything else (a bug)                     ``gearsim: internal error: TYPE: MESSAGE    1
                                          (rerun with --debug for the traceback)``
========================================  ==========================================  ====

``--debug`` (anywhere on the command line) or ``GEARSIM_DEBUG=1`` prints the Python
traceback before that line. A model used outside the range it was fitted on
(:class:`~gearsim.errors.ModelRangeWarning`) does not stop the run: it is printed once
as ``gearsim: warning: MESSAGE`` when the run ends (not after a refusal of bad input,
which stays one line).

Typer bundles its own copy of click (``typer._click``); usage errors are recognised by
class name along the exception's MRO, so those of either click package are caught.
"""

from __future__ import annotations

import atexit
import importlib
import os
import re
import sys
import traceback
import warnings
from functools import partial
from typing import Any

import typer

from gearsim.errors import InputError, ModelRangeWarning, SimulationError

__all__ = ["console", "main", "run"]

HELP = ("Mesh stiffness, tooth-root cracks, vibration and its analysis of gearboxes: gear "
        "trains, graphs of shafts and planetary stages.")
DEBUG_FLAG = "--debug"
DEBUG_ENV = "GEARSIM_DEBUG"
EXIT_INTERRUPTED = 130

_APP: typer.Typer | None = None


def _global_options(
    debug: bool = typer.Option(False, DEBUG_FLAG, help="on an error, also print the Python "
                               "traceback (or set GEARSIM_DEBUG=1); allowed anywhere"),
) -> None:
    """Mesh stiffness, tooth-root cracks and vibration of spur and helical gear trains."""


#: Verb -> the module of gearsim.commands that defines it. A call imports only its verb's
#: module (a small call starts fast); help and unknown verbs build the whole app.
VERB_MODULES = {
    "example": "basic", "layout": "basic", "stiffness": "basic", "contact": "basic",
    "analyze": "analysis", "compare": "analysis",
    "simulate": "dynamics", "fe-check": "fem", "fe-pair": "fem", "reproduce": "studies", "sweep": "sweep",
    "sweep-report": "sweep",
    "life": "life",
}


def _new_app() -> typer.Typer:
    new = typer.Typer(name="gearsim", help=HELP, no_args_is_help=True,
                      add_completion=False, pretty_exceptions_enable=False,
                      rich_markup_mode=None)  # plain help: no rich import at start-up
    new.callback()(_global_options)
    return new


def _build_app() -> typer.Typer:
    """The typer application with every verb (imported here, on first use)."""
    global _APP
    if _APP is None:
        from gearsim.commands import analysis, basic, dynamics, fem, life, studies, sweep

        new = _new_app()
        # One module per verb group; each defines register(app).
        for verbs in (basic, analysis, dynamics, fem, studies, sweep, life):
            verbs.register(new)
        _APP = new
    return _APP


def _app_for(args: list[str]) -> typer.Typer:
    """The app for this call: only the verb's own module when the verb is known."""
    verb = next((a for a in args if not a.startswith("-")), None)
    name = VERB_MODULES.get(verb or "")
    if name is None or _APP is not None:
        return _build_app()
    new = _new_app()
    importlib.import_module(f"gearsim.commands.{name}").register(new)
    return new


#: click commands built from the apps, by verb module ("" for the whole app): typer
#: converts an app to click on every call (~10 ms), a process calling :func:`run` many
#: times (tests, notebooks) converts each once; a click command is reusable (each call
#: makes its own context).
_COMMANDS: dict[str, Any] = {}


def _command_for(args: list[str]) -> Any:
    """The click command that runs ``args`` (built once per verb module and process)."""
    verb = next((a for a in args if not a.startswith("-")), None)
    key = VERB_MODULES.get(verb or "") or ""
    if key not in _COMMANDS:
        _COMMANDS[key] = typer.main.get_command(_app_for(args))
    return _COMMANDS[key]


def __getattr__(name: str) -> Any:
    if name == "app":
        return _build_app()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _one_line(text: object) -> str:
    return re.sub(r"\s*\n\s*", " ", str(text)).strip()


def _is_a(exc: BaseException, *names: str) -> bool:
    """Whether a class of ``exc``'s MRO has one of ``names`` (click, typer._click, typer)."""
    return any(c.__name__ in names for c in type(exc).__mro__)


def _strip_debug(args: list[str]) -> tuple[list[str], bool]:
    """Remove ``--debug`` (before a ``--`` separator) from the arguments."""
    if "--" in args:
        cut = args.index("--")
        head, tail = args[:cut], args[cut:]
    else:
        head, tail = args, []
    kept = [a for a in head if a != DEBUG_FLAG]
    return kept + tail, len(kept) < len(head)


def _say(line: str) -> None:
    try:
        print(line, file=sys.stderr, flush=True)
    except (OSError, ValueError):  # closed or broken standard error: nothing to tell
        pass


def _verb(args: list[str]) -> str | None:
    """The verb of the command line, if it names one."""
    first = next((a for a in args if not a.startswith("-")), None)
    return first if first in VERB_MODULES else None


def _interrupted() -> int:
    """Report an interrupt; the exit status 130.

    CPython remembers a ``KeyboardInterrupt`` that passed through ``exec`` of a string
    (as some imports do) and, under ``python -m``, then ends the process by SIGINT at exit
    whatever the exit status; running any string clears that flag.
    """
    exec("pass")  # noqa: S102  (clears CPython's unhandled-interrupt flag; see above)
    _say("gearsim: interrupted")
    return EXIT_INTERRUPTED


def _usage_line(exc: BaseException, args: list[str]) -> str:
    fmt = getattr(exc, "format_message", None)
    msg = _one_line(fmt() if callable(fmt) else exc)
    ctx = getattr(exc, "ctx", None)
    path = getattr(ctx, "command_path", None) if ctx is not None else None
    if not path:  # some parser errors carry no context
        verb = _verb(args)
        path = f"gearsim {verb}" if verb else "gearsim"
    return f"gearsim: error: {msg} (see {path} --help)"


def _exit_code(code: object) -> int:
    if code is None:
        return 0
    if isinstance(code, bool):
        return int(code)
    if isinstance(code, int):
        return code
    _say(f"gearsim: {_one_line(code)}")  # sys.exit("message")
    return 1


def _interrupt_inside(exc: BaseException) -> bool:
    """A Ctrl-C that surfaced as another exception.

    A ``KeyboardInterrupt`` raised while a compiled (numba) function runs comes back as
    ``SystemError: ... returned a result with an exception set`` whose context is the
    interrupt; the chain of causes and contexts is searched for it.
    """
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or (None if e.__suppress_context__ else e.__context__)
    return False


def _as_written(exc: InputError, args: list[str]) -> str:
    """The refusal's line with an option's number as the user wrote it.

    Typer hands a verb ``--fs 1e300`` as the float 1e+300 and ``--shaft-rpm 0`` as 0.0;
    when the refused parameter is an option whose last text on the command line reads as
    that same number, that text is shown. A value the verb converted (a unit, mm to m)
    differs from the text and is kept.
    """
    p, line = exc.parameter, _one_line(exc)
    if not (p.startswith("--") and isinstance(exc.value, (int, float))
            and not isinstance(exc.value, bool)):
        return line
    texts = [b if a == p else a[len(p) + 1:] for a, b in zip(args, [*args[1:], ""], strict=True)
             if a == p or a.startswith(p + "=")]
    if not texts:  # the option's value came from elsewhere (a config, a default)
        return line
    text = texts[-1]
    try:
        same = float(text) == float(exc.value) or text.strip().lower() == str(exc.value)
    except ValueError:
        return line
    return _one_line(InputError(p, text, exc.limit)) if same else line


def _finish(exc: BaseException, debug: bool, args: list[str]) -> int:
    """Print the one line for ``exc`` (with the traceback if ``debug``); the exit status."""
    if debug and not isinstance(exc, SystemExit) and not _is_a(exc, "Exit"):
        traceback.print_exception(exc, file=sys.stderr)
    if isinstance(exc, KeyboardInterrupt) or _is_a(exc, "Abort") or _interrupt_inside(exc):
        return _interrupted()
    if isinstance(exc, InputError):
        _say(f"gearsim: error: {_as_written(exc, args)}")
        return 2
    if isinstance(exc, SimulationError):
        _say(f"gearsim: failed: {_one_line(exc)}")
        return 1
    if isinstance(exc, SystemExit):
        return _exit_code(exc.code)
    if _is_a(exc, "Exit"):  # typer.Exit / click Exit raised past typer
        code = _exit_code(getattr(exc, "exit_code", 0))
        return _interrupted() if code == EXIT_INTERRUPTED else code
    if _is_a(exc, "NoArgsIsHelpError"):  # bare `gearsim`: the help, as click does
        try:
            exc.show()  # type: ignore[attr-defined]
        except Exception:
            _say(_usage_line(exc, args))
        return 2
    if _is_a(exc, "ClickException"):  # usage errors of typer's click or of click
        _say(_usage_line(exc, args))
        code = getattr(exc, "exit_code", 2)
        return code if isinstance(code, int) and code else 2
    if isinstance(exc, BrokenPipeError):  # `gearsim ... | head`
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115  (silence the final flush)
        except OSError:
            pass
        return 1
    _say(f"gearsim: internal error: {type(exc).__name__}: {_one_line(exc)}"
         + ("" if debug else f" (rerun with {DEBUG_FLAG} for the traceback)"))
    return 1


def _keep_warning(seen: list[str], message, category, filename, lineno, file=None,
                  line=None) -> None:
    """Collect a warning's text once, folded to one line (printed when the run ends, see
    :func:`run`)."""
    text = " ".join(str(message).split())
    if text not in seen:
        seen.append(text)


def _show_warnings(seen: list[str]) -> None:
    """Print each collected warning as one line ``gearsim: warning: MESSAGE``."""
    for text in seen:
        _say(f"gearsim: warning: {text}")


def run(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``) and return the exit status.

    Never raises (but for ``SystemExit`` of the interpreter itself): every error is
    reported as one line on standard error (see the module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Arguments after the program name, e.g. ``["simulate", "idler-table1"]``.

    Returns
    -------
    int
        0 on success, 2 for bad input or usage, 1 for a failed computation or an
        unexpected error, 130 when interrupted.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    args, debug = _strip_debug([str(a) for a in args])
    debug = debug or os.environ.get(DEBUG_ENV, "").strip().lower() not in ("", "0", "false",
                                                                           "no")
    seen: list[str] = []
    with warnings.catch_warnings():
        warnings.simplefilter("always", ModelRangeWarning)
        warnings.showwarning = partial(_keep_warning, seen)
        try:
            rv = _command_for(args).main(args=args, prog_name="gearsim",
                                         standalone_mode=False)
        except BaseException as exc:  # noqa: BLE001  (the one error path of the CLI)
            code = _finish(exc, debug, args)
            if code != 2:  # a refusal is one line; the warnings of its checks are moot
                _show_warnings(seen)
            return code
    _show_warnings(seen)
    # non-standalone typer returns the code of typer.Exit, and 130 for a Ctrl-C it caught
    code = rv if isinstance(rv, int) and not isinstance(rv, bool) else 0
    return _interrupted() if code == EXIT_INTERRUPTED else code


def main() -> None:
    """Run the command line and exit with its status: ``sys.exit(run())``.

    For callers in a Python process (tests, scripts); the ``gearsim`` script is
    :func:`console`.
    """
    sys.exit(run())


def console() -> None:
    """Entry point of the ``gearsim`` script: :func:`run`, then a quick exit.

    The interpreter's own exit tears down every module it imported, about 0.4 s after
    a run that loaded numba, xarray and pint (1,700 modules; measured 1.94 s against
    1.45 s for ``gearsim simulate idler-table1 --duration 1``). Nothing of it is needed
    once the run is over: every file gearsim writes is closed and renamed into place
    before :func:`run` returns. So the exit handlers run (``atexit``: logging, temporary
    folders, child processes), the standard streams are flushed and the process ends
    with :func:`os._exit`. While other threads still run (a Dask cluster being shut
    down) the interpreter's normal exit waits for them instead.
    """
    import threading

    code = run()
    if threading.active_count() > 1:
        sys.exit(code)
    try:
        atexit._run_exitfuncs()
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed pipe: nothing more can be said
                pass
        os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    console()
