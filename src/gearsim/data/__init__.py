"""Built-in example configurations (TOML files of this package) and their names.

Kept free of the model's imports so that ``gearsim example NAME`` prints a file without
loading numpy and the physics (:func:`gearsim.model.example` parses one).
"""

from __future__ import annotations

from importlib import resources

from gearsim.errors import InputError

__all__ = ["EXAMPLES", "example_text"]

#: Names of the built-in examples (``gearsim example NAME``).
EXAMPLES = ("idler-table1", "spur-19-48", "two-stage-reducer", "lin-parker-1999",
            "nrel-grc", "wind-turbine-grc")


def example_text(name: str) -> str:
    """TOML text of a built-in example.

    Parameters
    ----------
    name : str
        One of :data:`EXAMPLES`.

    Returns
    -------
    str

    Raises
    ------
    InputError
        An unknown name (the examples are listed).

    Examples
    --------
    >>> example_text("spur-19-48").splitlines()[0].startswith("#")
    True
    """
    if name not in EXAMPLES:
        raise InputError("example", name, "unknown; built-in examples: " + ", ".join(EXAMPLES))
    return resources.files("gearsim.data").joinpath(f"{name}.toml").read_text(encoding="utf-8")
