"""The typed gearbox model and its configuration files.

:func:`load` / :func:`loads` / :func:`example` return a :class:`Gearbox`; see
:mod:`gearsim.model.config` for the file layout and :mod:`gearsim.model.gearbox` for
the object.
"""

from gearsim.model.config import EXAMPLES, example, example_text, load, loads, parse
from gearsim.model.gearbox import Gearbox

__all__ = ["EXAMPLES", "Gearbox", "example", "example_text", "load", "loads", "parse"]
