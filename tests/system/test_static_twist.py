"""A shaft twisted past the kernel's bound by its static torque is refused before the run.

A run starts from the static equilibrium, where a shaft of torsional stiffness k_t carrying
T is twisted by T / k_t; past Q_LIMIT = 1 rad the kernel would stop at its first step as
"diverged ... reduce dynamics.step", which no step cures (probe-b #10). The torques are
by hand: SHAFT_SPLIT's intermediate shaft takes 100 N m x 48/24 = 200 N m and passes
0.4 / 0.6 of it to its two outputs (segments p2-g1 80 N m, g1-p3 120 N m);
TOML_CHAINS_GRAPH: 200 N m x 60/20 = 600 N m into the sun of 24/24/72 (ring held), its
carrier 600 (1 + 72/24) = 2400 N m into the sun of 20/40/100, its carrier 2400 x 6 =
14400 N m into the gears.
"""

from __future__ import annotations

import pytest
from branching_boxes import SHAFT_SPLIT
from two_stage_boxes import TOML_CHAINS_GRAPH, refused_in_one_line

from gearsim.dynamics.simulate import check_twists
from gearsim.model import loads

TAIL = ", beyond the 1 rad at which a run stops as diverged: give at least "


@pytest.mark.parametrize("kt,twist,torque", [("50", "1.6", "80"), ("100", "1.2", "120")])
def test_soft_shaft_of_a_train_refused(kt, twist, torque, tmp_path, capsys):
    text = SHAFT_SPLIT.replace('"2e5 N*m/rad"', f'"{kt} N*m/rad"')
    line = refused_in_one_line(text, tmp_path, capsys, "shafts.mid.torsional_stiffness")
    assert line == (f"gearsim: error: shafts.mid.torsional_stiffness = {kt} N*m/rad: twists "
                    f"shaft mid by {twist} rad under its static torque of {torque} N*m"
                    f"{TAIL}{torque} N*m/rad")
    check_twists(loads(SHAFT_SPLIT.replace('"2e5 N*m/rad"', '"121 N*m/rad"')).train)


@pytest.mark.parametrize("old,new,parameter,shaft,twist,torque", [
    # named as the graph writes them (before: input_chain.shaft_stiffness,
    # stages[1].shaft_stiffness and shaft shaft-stage1-carrier-stage2-sun, and
    # chain.shaft_stiffness: the translated form's; probe round 8 #6)
    ('"2e6 N*m/rad"', "500", "shafts[1].torsional_stiffness", "sun-shaft", "1.2", "600"),
    ('"3e6 N*m/rad"', "2000", "shafts[2].torsional_stiffness", "between", "1.2", "2400"),
    ('"5e7 N*m/rad"', "10000", "shafts[3].torsional_stiffness", "out", "1.44", "14400"),
])
def test_soft_shaft_of_a_stage_box_refused(old, new, parameter, shaft, twist, torque, tmp_path,
                                           capsys):
    text = TOML_CHAINS_GRAPH.replace(old, f'"{new} N*m/rad"')
    line = refused_in_one_line(text, tmp_path, capsys, parameter)
    assert line == (f"gearsim: error: {parameter} = {new} N*m/rad: twists shaft {shaft} by "
                    f"{twist} rad under its static torque of {torque} N*m{TAIL}{torque} N*m/rad")
