"""Command-line interface: a thin typer layer over the Python API.

Each verb lives in a module of :mod:`gearsim.commands` that defines ``register(app)``;
this module only collects them. Bad input (:class:`gearsim.errors.InputError`) is printed
as one line on standard error with exit status 2.
"""

from __future__ import annotations

import sys

import typer

from gearsim.commands import analysis, basic, dynamics, fem, studies, sweep
from gearsim.errors import InputError, SimulationError

app = typer.Typer(
    name="gearsim",
    help="Mesh stiffness, tooth-root cracks and vibration of spur and helical gear trains.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

# One module per verb group; each defines register(app).
for _verbs in (basic, analysis, dynamics, fem, studies, sweep):
    _verbs.register(app)


def main() -> None:
    """Entry point of the ``gearsim`` script."""
    try:
        app(standalone_mode=False)
    except InputError as exc:
        print(f"gearsim: error: {exc}", file=sys.stderr)
        sys.exit(2)
    except SimulationError as exc:
        print(f"gearsim: failed: {exc}", file=sys.stderr)
        sys.exit(1)
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except (typer.Abort, KeyboardInterrupt):
        print("gearsim: aborted", file=sys.stderr)
        sys.exit(130)
    except Exception as exc:  # click usage errors
        import click

        if isinstance(exc, click.exceptions.ClickException):
            exc.show()
            sys.exit(2)
        raise


if __name__ == "__main__":  # pragma: no cover
    main()
