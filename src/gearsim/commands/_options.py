"""Shared pieces of the CLI verbs: naming the option a refused value came from."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from gearsim.errors import InputError

__all__ = ["MIN_TORQUE", "as_options", "with_torque"]

#: Smallest ``--torque`` [N m] (5e-324 gave a zero mesh force: infinite stiffness, / 0).
MIN_TORQUE = 1e-9


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


def with_torque(train, torque: str | None):
    """``train`` with the input torque of a ``--torque`` option (with its unit), if given.

    Parameters
    ----------
    train : GearTrain or Gearbox
        The train, or a gearbox (then at that input torque: :meth:`Gearbox.at`).
    torque : str or None
        The option's text, e.g. ``"2000 N*m"``; ``None`` keeps the train's torque.

    Returns
    -------
    GearTrain or Gearbox
        The train at that torque (refusals name ``--torque``; below
        :data:`MIN_TORQUE` refused).
    """
    if torque is None:
        return train
    import dataclasses

    from gearsim.system import Operating
    from gearsim.units import to_si

    t = to_si(torque, "torque", "--torque")
    if 0 < t < MIN_TORQUE:
        raise InputError("--torque", torque, f"must be >= {MIN_TORQUE:g} N*m (a smaller torque can "
                         "only be a slip of unit or exponent)")
    with as_options({"operating.torque": "--torque"}):
        if hasattr(train, "at"):  # a gearbox: every part at its input's torque
            return train.at(speed=train.operating()[0], torque=t)
        return dataclasses.replace(train, operating=Operating(speed=train.operating.speed,
                                                              torque=t))
