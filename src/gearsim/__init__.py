"""gearsim: mesh stiffness, tooth-root cracks and vibration of spur and helical gear trains.

The public API, for scripts and notebooks (``import gearsim as gs``):

===================  ==========================================================
``gs.load``          a TOML configuration (or built-in example) -> :class:`Gearbox`
``gs.loads``         the same from TOML text
``gs.example``       a built-in example (``"idler-table1"``, ``"spur-19-48"``)
``gs.simulate``      vibration of a gearbox -> :class:`xarray.Dataset`
``gs.read_signal``   one channel of a measured or simulated record
``gs.analyze``       time, frequency, time-frequency and TSA analysis of a record
``gs.reproduce``     the source paper's study (report, figures, claims)
``gs.sweep``         a parameter study on Dask -> labelled store
===================  ==========================================================

A :class:`Gearbox` holds the train (``gb.train``: gears, operating point, stiffness
options, cracks; ``gb.train.mesh_stiffness(0)``) and its ``dynamics`` and ``analysis``
settings; see ``docs/api.md``. Names are imported on first use, so ``import gearsim``
stays light.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from gearsim.api import analyze, read_signal, reproduce, simulate, sweep
    from gearsim.errors import InputError, SimulationError
    from gearsim.model import Gearbox, example, load, loads
    from gearsim.stiffness.crack import Crack
    from gearsim.system import GearTrain

#: Public name -> module that defines it (imported on first access, PEP 562).
_LAZY = {
    "Gearbox": "gearsim.model", "load": "gearsim.model", "loads": "gearsim.model",
    "example": "gearsim.model",
    "simulate": "gearsim.api", "read_signal": "gearsim.api", "analyze": "gearsim.api",
    "reproduce": "gearsim.api", "sweep": "gearsim.api",
    "GearTrain": "gearsim.system", "Crack": "gearsim.stiffness.crack",
    "InputError": "gearsim.errors", "SimulationError": "gearsim.errors",
    # the installed version (importlib.metadata, ~45 ms): on first use, not at start-up
    "__version__": "gearsim._version",
}

__all__ = ["Crack", "GearTrain", "Gearbox", "InputError", "SimulationError", "__version__",
           "analyze", "example", "load", "loads", "read_signal", "reproduce", "simulate",
           "sweep"]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'gearsim' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
