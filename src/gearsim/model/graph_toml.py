"""A gearbox with planetary stages written back as the graph form that
:mod:`gearsim.model.graph_form` reads (SI numbers, floats by ``repr``: read back bit for
bit).

Every part becomes what the reader builds it from: the shafts in power-flow order (the
input chain's, those between the stages or the shafts of the gears between them, the
output chain's; a shaft carrying a member and a gear is the chain's shaft, its
``torsional_stiffness`` the stage's shaft), one
``[[stages]]`` a stage (members on their shafts, its ``[stages.members]`` and damage),
the gears, meshes and damage of the chains (:mod:`gearsim.system.toml`), ``[operating]``
of the input, one ``[stiffness]``, ``[sensor]``, ``[dynamics]``, ``[analysis]``. A
member's shaft is named as :attr:`~gearsim.model.Gearbox.member_shafts` names it, else
after the member as the results name it (``carrier``, ``stage1-sun``) or the chain's
shaft it shares.

Refused (one line), as the graph form cannot say it: stiffness options that differ
between the parts or a ``corner_contact`` / ``fe_pair_positions`` off its default (a stage
reads neither), stages of different materials, a sensor on a later stage, a chain's own
torsional stiffness on the shaft it shares with a member, a stage's meshes of contacts
without a fault (a study's variant). Not written: the names of the gear chains (the
graph calls them ``input gears``, ``gears before stage <k>`` and ``output gears``).
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

from gearsim.dynamics.compose import stage_prefix
from gearsim.errors import require
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.toml import EFFECTIVE_HEADER, damage_tables, gear_tables, table, toml_value

if TYPE_CHECKING:
    from gearsim.model.gearbox import Gearbox

__all__ = ["HOUSING", "MEMBERS", "stages_to_toml"]

#: The held member's place.
HOUSING = "housing"
MEMBERS = ("sun", "ring", "carrier")
#: The ``[stiffness]`` keys a stage reads (:func:`gearsim.model.planetary.parse_planetary`).
STAGE_STIFFNESS = ("closure", "slices", "positions_per_cycle", "gauss_points", "plane",
                   "source", "contact", "coupling")


def stages_to_toml(gb: Gearbox) -> str:
    """The configuration of a gearbox with planetary stages as graph-form TOML.

    Parameters
    ----------
    gb : Gearbox
        With ``stage`` (and any of ``next_stages``, ``input_train``, ``train``).

    Returns
    -------
    str
        TOML text that :func:`gearsim.loads` reads back to the same stages, chains,
        shafts, members, damage and settings.

    Raises
    ------
    InputError
        What the graph form cannot say (the module docstring).
    """
    stages, inp, out = gb.stages, gb.input_train, gb.train
    n, s = len(stages), gb.stage.settings
    one = StiffnessSettings(**{k: getattr(s, k) for k in STAGE_STIFFNESS})
    require(all(p == one for p in [t.settings for t in stages] + [t.stiffness for t in gb.chains]),
            "stiffness", gb.name, "cannot be written as one [stiffness] (the stages and gears "
            "differ, or corner_contact / fe_pair_positions are off their defaults)")
    material = gb.stage.stage.material
    require(all(t.stage.material == material for t in stages), "material", gb.name,
            "the stages differ in material: the graph form has one for all stages")
    require(not any(t.contacts and not t.faults for t in stages), "stage.contacts", True,
            "a healthy stage's meshes of contacts are not written in a file")
    require(all((ns.members.sensor_angle, ns.members.sensor_width) == (0.0, math.pi)
                for ns in gb.next_stages), "sensor", gb.name, "only the first stage has one")

    def output(t) -> str:
        return next(m for m in MEMBERS if m not in (t.operating.fixed, t.operating.input))

    lines = [EFFECTIVE_HEADER, f"name = {toml_value(gb.name)}"]
    table(lines, "[material]", dataclasses.asdict(material))
    ends = []  # at junction k (before stage k; k = n after the last): the shafts of stage
    for k in range(n + 1):  # k - 1's output member and of stage k's input member
        nxt = gb.next_stages[k - 1] if 0 < k < n else None
        chain = inp if k == 0 else out if k == n else nxt.input_train
        if chain is None:
            name = gb.shaft_label(stage_prefix(k - 1, n) + output(stages[k - 1]) if k
                                  else stage_prefix(0, n) + stages[0].operating.input)
            table(lines, "[[shafts]]", {"name": name, "torsional_stiffness": nxt and
                                        nxt.shaft_stiffness})
            ends.append((name, name))
            continue
        fl = chain.flow  # the shafts of its ends that carry a member, their stiffnesses
        kts = ({0: gb.shaft_stiffness if k == n else nxt.shaft_stiffness} if k else {}) | (
            {fl.outputs[0]: gb.input_shaft_stiffness if k == 0 else nxt.input_shaft_stiffness}
            if k < n else {})
        for j in kts:
            require(fl.shafts[j].torsional_stiffness is None, "shafts", fl.shafts[j].name,
                    "has a torsional stiffness between its gears and one to the stage "
                    "member it carries: the graph form has one")
        for i, sh in enumerate(fl.shafts):
            table(lines, "[[shafts]]", {**{a: v for a, v in dataclasses.asdict(sh).items()
                                           if a != "gears"},
                                        **({"torsional_stiffness": kts[i]} if i in kts else {})})
        ends.append((fl.shafts[0].name, fl.shafts[fl.outputs[0]].name))
    for k, t in enumerate(stages):
        op, st = t.operating, t.stage
        table(lines, "[[stages]]", {
            **{m: HOUSING if m == op.fixed else ends[k][1] if m == op.input else ends[k + 1][0]
               for m in MEMBERS},
            "name": t.name if k else None,
            **{f.name: getattr(st, f.name) for f in dataclasses.fields(st)
               if f.name != "material"},
            "sun_mesh_stiffness": t.sun_mesh_stiffness,
            "ring_mesh_stiffness": t.ring_mesh_stiffness, "ring_foundation": t.ring_foundation})
        mem = gb.next_stages[k - 1].members if k else gb.members
        own = {f"{m}_{q}": v for group, q in (("masses", "mass"), ("inertias", "inertia"),
                                              ("bearings", "bearing"))
               for m, v in getattr(mem, group).items()}
        if own or mem.held_torsional is not None:
            table(lines, "[stages.members]", {**own, "held_torsional": mem.held_torsional})
        damage_tables(lines, t, "stages.")
    for chain in gb.chains:
        gear_tables(lines, chain, graph=True)
    for chain in gb.chains:
        damage_tables(lines, chain)
    op = (inp or gb.stage).operating
    table(lines, "[operating]", {"speed": f"{op.speed!r} rad/s", "torque": op.torque})
    table(lines, "[stiffness]", {k: getattr(s, k) for k in STAGE_STIFFNESS})
    table(lines, "[sensor]", {"angle": gb.members.sensor_angle,
                              "width": gb.members.sensor_width})
    table(lines, "[dynamics]", gb.dynamics.to_dict())
    table(lines, "[analysis]", gb.analysis.to_dict())
    return "\n".join(lines) + "\n"
