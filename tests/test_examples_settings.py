"""Every built-in example runs through ``gearsim simulate`` with its own settings.

``gearsim simulate`` checks the output rate against the highest mesh harmonic the
analysis looks at (``[analysis] orders``, default 4) before any work. The wind-turbine
example's 5 kHz was below twice the fourth harmonic of its high-speed mesh (4 x 660 Hz):
``gearsim simulate wind-turbine-grc`` was refused with its own file. The independent
number here is the Nyquist rule on the fastest mesh of each example, computed from its
tooth counts and speeds.
"""

from __future__ import annotations

import pytest

import gearsim as gs
from gearsim.data import EXAMPLES


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_settings_resolve_the_analysed_harmonics(name):
    gb = gs.example(name)
    harmonics = max(gb.analysis.orders)
    fastest = 0.0
    if gb.stage is not None:
        fastest = gb.stage.mesh_frequency
    if gb.train is not None:
        fastest = max(fastest, *gb.train.mesh_frequencies)
    assert gb.dynamics.fs > 2 * harmonics * fastest, (gb.dynamics.fs, fastest)
    gb.check_run(harmonics)  # what gearsim simulate asks before any work: no refusal
