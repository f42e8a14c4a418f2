"""Shared pieces of the CLI verbs: naming the option a refused value came from."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from gearsim.errors import InputError

__all__ = ["as_options"]


@contextmanager
def as_options(names: dict[str, str]) -> Iterator[None]:
    """Re-raise an :class:`InputError` under the name of the option the user typed.

    The checks live where the values are made (``GearTrain.with_crack``, the settings
    dataclasses) and name config parameters (``stiffness.closure``); a verb passes the
    map from those names to its options (``{"stiffness.closure": "--closure"}``).

    Parameters
    ----------
    names : dict
        Config parameter name -> CLI option.
    """
    try:
        yield
    except InputError as exc:
        if exc.parameter in names:
            raise InputError(names[exc.parameter], exc.value, exc.limit) from None
        raise
