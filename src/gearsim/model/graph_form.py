"""One TOML form for every gearbox: shafts, gears, meshes and planetary stages.

A gearbox with planetary stages is written as a gear train's graph is (``[[shafts]]``,
``[[gears]]`` with ``shaft = ...``, ``[[meshes]]``), with ``[[stages]]`` whose members
sit on the shafts::

    [[shafts]]
    name = "rotor"                 # the first shaft is the input
    [[shafts]]
    name = "low-speed"
    torsional_stiffness = "2e7 N*m/rad"   # between what it carries (a member, a gear)
    [[stages]]
    carrier = "rotor"              # each member names its shaft; the held one "housing"
    sun = "low-speed"
    ring = "housing"
    sun_teeth = 21                 # and the keys of [stage] (docs/planetary.md)
    [[stages.cracks]]              # its own damage and [stages.members]
    [[gears]]
    name = "low-speed-gear"
    shaft = "low-speed"
    [[meshes]]
    [operating]                    # speed and torque of the first shaft
    [[cracks]]                     # damage of the gears, by gear name

The power flow is read from the graph: from the input shaft through gears (meshes) or a
stage (the member on the shaft is its input, the other turning member its output) to the
next shaft, until nothing is left. A stage's held, input and output members follow from
where its members sit; a shaft's ``torsional_stiffness`` is the shaft between what it
carries (between two stages' members, or a member and a gear; default as
:mod:`gearsim.dynamics.compose`), its ``bearing_stiffness`` the bearing of its gears and
members (as :meth:`~gearsim.model.Gearbox.with_bearing`; a member's own in
``[stages.members]`` wins); the other keys of a shaft of members only are refused (their
mass and inertia are ``[stages.members]`` keys). The gears before the first stage, the stages in series,
the gears between two stages and the gears after the last stage are then built as the
``[input_chain]``, ``[[stages]]`` (a later stage's ``input_chain``: the gears driving it)
and ``[chain]`` of :mod:`gearsim.model.planetary` (the same
:class:`~gearsim.model.Gearbox`, the same numbers); a refusal names the element as it is
written here (``gears[3].shaft``, ``stages[2].sun``, ``shafts[1].torsional_stiffness``).

The gears after the last stage may branch the power (each output shaft names its
``power_share``, as in a gearbox of parallel shafts). Not read (one line naming the
element): a shaft driving two parts, a shaft of gears that drive a stage meshing with
two more (branching power ahead of a stage), a
shaft carrying a member that meshes with two shafts, an element off the power path, a
stage without exactly one member on the housing.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, NamedTuple

from gearsim.dynamics.compose import stage_prefix
from gearsim.errors import InputError
from gearsim.geometry.gear import Material
from gearsim.model.damage import array_of_tables
from gearsim.model.gearbox import Gearbox
from gearsim.model.graph_toml import HOUSING, MEMBERS
from gearsim.model.planetary import parse_planetary
from gearsim.sections import as_written, convert, written_name
from gearsim.system.graph import Shaft

__all__ = ["GRAPH_TOP_KEYS", "HOUSING", "is_graph_with_stages", "parse_graph_stages"]

GRAPH_TOP_KEYS = ("name", "material", "common", "shafts", "gears", "meshes", "stages",
                  "operating", "stiffness", "cracks", "faults", "modifications", "sensor",
                  "dynamics", "analysis")
#: The keys of a ``[[shafts]]`` table (of every gearbox of shafts) and their kinds.
SHAFT_KEYS = {"name": "str", "mass": "mass", "inertia": "inertia",
              "torsional_stiffness": "torsional_stiffness", "bearing_stiffness": "stiffness",
              "axial_stiffness": "stiffness", "power_share": "dimensionless"}
#: Sections a stage-form file has and this one does not (where they go here).
MOVED = {"stage": "[[stages]] with each member's shaft", "members": "[stages.members]",
         "chain": "[[gears]] and [[meshes]]", "input_chain": "[[gears]] and [[meshes]]"}


def is_graph_with_stages(doc: dict[str, Any]) -> bool:
    """True for a document of shafts with planetary stages (this module's form).

    Parameters
    ----------
    doc : dict
        A parsed TOML document.

    Returns
    -------
    bool
    """
    return "shafts" in doc and "stages" in doc


def parse_graph_stages(doc: dict[str, Any], material: Material,
                       parse_train: Callable[[dict[str, Any]], Any]) -> Gearbox:
    """Build the :class:`~gearsim.model.Gearbox` of a document of shafts, gears, meshes
    and planetary stages.

    Parameters
    ----------
    doc : dict
        The document (:func:`is_graph_with_stages`).
    material : Material
        The parsed ``[material]``.
    parse_train : callable
        The gear-train parser (:func:`gearsim.model.config.parse`).

    Returns
    -------
    Gearbox

    Raises
    ------
    InputError
        The first problem, named as written in ``doc``.
    """
    staged, back, placed = _translate(doc)
    try:
        gb = parse_planetary(staged, material, parse_train)
    except InputError as exc:
        raise InputError(written_name(exc.parameter, back), exc.value, exc.limit) from None
    return dataclasses.replace(gb, member_shafts=placed, written=tuple(back.items()))


def _names(tables: list[dict[str, Any]], key: str, kind: str) -> list[str]:
    """The names of the elements of ``[[key]]`` (default ``<kind><i + 1>``), each a string
    and unique."""
    names: list[str] = []
    for i, t in enumerate(tables):
        n = t.get("name", f"{kind}{i + 1}")
        if not isinstance(n, str) or not n:
            raise InputError(f"{key}[{i}].name", n, "must be a non-empty string")
        if n in names:
            raise InputError(f"{key}[{i}].name", n, f"is already the name of "
                             f"{key}[{names.index(n)}]: names must be unique")
        names.append(n)
    return names


def _tables(doc: dict[str, Any], key: str) -> list[dict[str, Any]]:
    return array_of_tables(doc.get(key, []), key) if key in doc else []


def _translate(doc: dict[str, Any]
               ) -> tuple[dict[str, Any], dict[str, str], tuple[tuple[str, str], ...]]:
    """The stage form of ``doc``, the renaming of its parameters back to ``doc``'s
    (:func:`written_name`), and
    the shaft of each turning stage member (``(member as the results name it, shaft)``,
    :attr:`gearsim.model.Gearbox.member_shafts`)."""
    for key in doc:
        if key not in GRAPH_TOP_KEYS:
            hint = f" (here: {MOVED[key]})" if key in MOVED else ""
            raise InputError(key, "...", "unknown section for a gearbox of shafts and "
                             f"stages{hint}; allowed: " + ", ".join(GRAPH_TOP_KEYS))
    shafts = _tables(doc, "shafts")
    gears, meshes, stages = _tables(doc, "gears"), _tables(doc, "meshes"), _tables(doc, "stages")
    names = _names(shafts, "shafts", "shaft")
    index = {n: i for i, n in enumerate(names)}
    gear_names = _names(gears, "gears", "gear")
    on: dict[str, list[int]] = {n: [] for n in names}  # the gears on each shaft
    for i, t in enumerate(gears):
        if not isinstance(t.get("shaft"), str) or t["shaft"] not in index:
            raise InputError(f"gears[{i}].shaft", t.get("shaft", "missing"),
                             "no such shaft; shafts: " + ", ".join(names))
        on[t["shaft"]].append(i)
    # shafts joined by meshes: the gear graph's parts (each with its meshes)
    part_of = {n: n for n in names}

    def root(n: str) -> str:
        while part_of[n] != n:
            n = part_of[n]
        return n

    mesh_shafts = []
    for j, t in enumerate(meshes):
        pair = t.get("gears")
        if not (isinstance(pair, list) and len(pair) == 2
                and all(isinstance(g, str) and g in gear_names for g in pair)):
            raise InputError(f"meshes[{j}].gears", pair if pair is not None else "missing",
                             "must name two gears; gears: " + ", ".join(gear_names))
        a, b = (gears[gear_names.index(g)]["shaft"] for g in pair)
        mesh_shafts.append((a, b))
        part_of[root(a)] = root(b)
    # where each stage's members sit
    members: dict[str, list[tuple[int, str]]] = {n: [] for n in names}
    held = []
    for k, st in enumerate(stages):
        for key in ("fixed", "input", "shaft_stiffness"):
            if key in st:
                raise InputError(f"stages[{k}].{key}", st[key], "follows from the shafts "
                                 "the members sit on (here: sun, ring, carrier = a shaft or "
                                 f"\"{HOUSING}\"; a shaft's torsional_stiffness)")
        for m in MEMBERS:
            v = st.get(m, "missing")
            if not isinstance(v, str) or (v != HOUSING and v not in index):
                raise InputError(f"stages[{k}].{m}", v, "no such shaft; shafts: "
                                 + ", ".join(names) + f" (or \"{HOUSING}\": held)")
        fixed = [m for m in MEMBERS if st[m] == HOUSING]
        if len(fixed) != 1:
            raise InputError(f"stages[{k}]", ", ".join(f"{m} = {st[m]}" for m in MEMBERS),
                             f"exactly one member must be on the \"{HOUSING}\" (held)")
        turning = [m for m in MEMBERS if m != fixed[0]]
        if st[turning[0]] == st[turning[1]]:
            raise InputError(f"stages[{k}].{turning[1]}", st[turning[1]], f"is also the "
                             f"{turning[0]}'s shaft: the two turning members need two shafts")
        held.append(fixed[0])
        for m in turning:
            members[st[m]].append((k, m))
    for i, n in enumerate(names):
        if not on[n] and not members[n]:
            raise InputError(f"shafts[{i}]", n, "carries no gear and no stage member")
        if members[n]:
            _member_shaft(shafts[i], i, n, members[n], bool(on[n]))
    # the power path from the input shaft
    path: list[tuple] = []
    used_parts, used_stages = set(), set()
    cur = names[0]
    while True:
        ahead = ([("gears", root(cur))] if on[cur] and root(cur) not in used_parts else [])
        ahead += [("stage", k, m) for k, m in members[cur] if k not in used_stages]
        if not ahead:
            break
        if len(ahead) > 1:
            raise InputError(f"shafts[{index[cur]}]", cur, "drives two parts ("
                             + " and ".join("gears" if a[0] == "gears" else f"stages[{a[1]}]"
                                            for a in ahead)
                             + "): branching power is not read")
        step = ahead[0]
        if step[0] == "stage":
            _, k, m = step
            out = next(x for x in MEMBERS if x not in (m, held[k]))
            path.append(("stage", k, m, cur))
            used_stages.add(k)
            cur = stages[k][out]
            continue
        used_parts.add(step[1])
        part = [n for n in names if root(n) == step[1]]
        exits = [(n, k, m) for n in part if n != cur for k, m in members[n]
                 if k not in used_stages]
        if len(exits) > 1:
            raise InputError("gears", ", ".join(f"stages[{k}].{m} = {n}" for n, k, m in exits),
                             "the gears drive two stages: branching power is not read")
        path.append(("gears", step[1], cur, exits[0][0] if exits else None))
        if not exits:
            break
        cur = exits[0][0]
    for k in range(len(stages)):
        if k not in used_stages:
            raise InputError(f"stages[{k}]", "...", f"is not on the power path from the "
                             f"input shaft {names[0]!r}")
    for i, t in enumerate(gears):
        if root(t["shaft"]) not in used_parts:
            raise InputError(f"gears[{i}]", gear_names[i], f"is not on the power path from "
                             f"the input shaft {names[0]!r}")
    for key in ("cracks", "faults", "modifications"):  # the gears' damage, by name
        for i, t in enumerate(_tables(doc, key)):
            if t.get("gear") not in gear_names:
                raise InputError(f"{key}[{i}].gear", t.get("gear", "missing"), "no such "
                                 "gear; gears: " + ", ".join(gear_names) + " (a stage's is "
                                 f"[[stages.{key}]])")
    near = {n: {b if a == n else a for a, b in mesh_shafts if n in (a, b)} for n in names}
    for i, p in enumerate(path):  # gears driving a stage pass the power on in one path
        # (the shafts it enters and leaves by mesh with one gear's shaft); those the last
        # stage drives may branch (their outputs' power_share)
        if p[0] == "gears" and not (i == len(path) - 1 and i > 0):
            for n in (n for n in names if root(n) == p[1]):
                if len(near[n]) > (1 if n in p[2:] else 2):
                    raise InputError(f"shafts[{index[n]}]", n, "meshes with "
                                     + ", ".join(sorted(near[n])) + ": branching power "
                                     "beside a planetary stage is read in the gears after "
                                     "the last stage only (not in gears driving a stage)")
    order = [p[1] for p in path if p[0] == "stage"]
    placed = tuple((stage_prefix(n, len(order)) + m, stages[k][m])
                   for n, k in enumerate(order) for m in MEMBERS
                   if stages[k][m] != HOUSING)
    g = _Graph(doc, shafts, names, index, gears, gear_names, on, meshes, mesh_shafts,
               stages, held)
    return (*_stage_form(g, path), placed)


def _member_shaft(t: dict[str, Any], i: int, name: str, held: list[tuple[int, str]],
                  gears: bool) -> None:
    """Check shaft ``i``, which carries the stage members ``held`` (``(stage, member)``)
    and, with ``gears``, gears: its keys as any shaft's (:data:`SHAFT_KEYS`, the bounds
    of :class:`~gearsim.system.graph.Shaft`); of members only, refuse the keys that have
    no meaning there (the members' own are ``[stages.members]``)."""
    kw = {k: v for k, v in convert(t, SHAFT_KEYS, f"shafts[{i}]").items() if k != "name"}
    with as_written(t, f"shafts.{name}", SHAFT_KEYS, sources=[(f"shafts[{i}]", t)]):
        Shaft(name=name, gears=(name, f"{name}'"), **kw)  # two bodies: a member and more
    if gears:  # the gears' shaft, with them; its bearing also its member's
        return
    what = " and ".join(f"the {m} of stages[{k}]" for k, m in held)
    for key in kw:
        if key == "torsional_stiffness" and len(held) == 1:
            raise InputError(f"shafts[{i}].{key}", t[key], f"the shaft carries {what} "
                             "only: nothing for it to twist between (it joins two stages' "
                             "members, or a member and gears)")
        if key not in ("torsional_stiffness", "bearing_stiffness"):
            m = held[0][1]
            raise InputError(f"shafts[{i}].{key}", t[key], f"is not read on a shaft of "
                             f"stage members only ({what}): a member's mass, inertia and "
                             f"bearing are [stages.members] keys ({m}_mass, {m}_inertia, "
                             f"{m}_bearing); it has no axial bearing or power share")


class _Graph(NamedTuple):
    """A gearbox file of shafts and stages as read: its tables, the names of its shafts
    and gears, the gears on each shaft, the shafts each mesh joins and the member each
    stage holds."""

    doc: dict[str, Any]
    shafts: list[dict[str, Any]]
    names: list[str]
    index: dict[str, int]
    gears: list[dict[str, Any]]
    gear_names: list[str]
    on: dict[str, list[int]]
    meshes: list[dict[str, Any]]
    mesh_shafts: list[tuple[str, str]]
    stages: list[dict[str, Any]]
    held: list[str]


def _stage_form(g: _Graph, path: list[tuple]
                ) -> tuple[dict[str, Any], Callable[[str], str]]:
    """The ``[input_chain]``, ``[[stages]]`` (with the gears between two stages as the
    later one's ``input_chain``) and ``[chain]`` document of the power path, and the
    renaming of its parameters."""
    doc, index, stages, held = g.doc, g.index, g.stages, g.held
    out: dict[str, Any] = {k: doc[k] for k in ("name", "material", "sensor", "dynamics",
                                                "analysis", "stiffness") if k in doc}
    back: dict[str, str] = {}  # prefix in the stage form -> as written here
    stage_tabs = []
    for i, step in enumerate(path):
        if step[0] != "stage":
            continue
        _, k, m, shaft = step
        n = len(stage_tabs)
        raw = {key: v for key, v in stages[k].items() if key not in MEMBERS}
        own = {f"{x}_bearing": g.shafts[index[s]]["bearing_stiffness"] for x in MEMBERS
               if (s := stages[k][x]) != HOUSING
               and "bearing_stiffness" in g.shafts[index[s]]}
        if own and isinstance(raw.get("members", {}), dict):  # a shaft's bearing is its
            raw["members"] = {**own, **raw.get("members", {})}  # members' (their own wins)
        where = f"stages[{n}]"
        back[where] = f"stages[{k}]"
        if n == 0:  # the first stage's own tables are the document's
            for key in ("fixed", "input"):
                if key in doc.get("operating", {}):
                    raise InputError(f"operating.{key}", doc["operating"][key], "follows "
                                     "from the shafts the stages' members sit on")
            for key in ("members", "cracks", "faults"):
                if key in raw:
                    out[key] = raw.pop(key)
                    back[key] = f"stages[{k}].{key}"
            out["operating"] = {**doc.get("operating", {}), "fixed": held[k], "input": m}
            back["operating.fixed"] = f"stages[{k}].{held[k]}"
            back["operating.input"] = f"stages[{k}].{m}"
        else:  # its shaft from the previous stage's output member: the one its input
            raw |= {"fixed": held[k], "input": m}  # member sits on, or the gears' first
            src = path[i - 1][2] if path[i - 1][0] == "gears" else shaft
            t = g.shafts[index[src]]
            if "torsional_stiffness" in t:
                raw["shaft_stiffness"] = t["torsional_stiffness"]
                back[f"{where}.shaft_stiffness"] = f"shafts[{index[src]}].torsional_stiffness"
        stage_tabs.append(raw)
    out["stages"] = stage_tabs
    for i, (_, _, entry, leave) in ((i, x) for i, x in enumerate(path) if x[0] == "gears"):
        n = sum(x[0] == "stage" for x in path[:i])  # the stages before the gears
        table = ("input_chain" if n == 0 else "chain" if i == len(path) - 1
                 else f"stages[{n}].input_chain")
        chain, ren = _chain(g, entry)
        chain["name"] = ("input gears" if n == 0 else "output gears" if table == "chain"
                         else f"gears before stage {n + 1}")
        joins = [x for x in (entry if n else None, leave if table != "chain" else None) if x]
        for join in joins:  # the shafts from and to a member: their stiffnesses the
            t = g.shafts[index[join]]  # stages' (read above) or the chain's own
            if "torsional_stiffness" in t and (join == leave or table == "chain"):
                chain["shaft_stiffness"] = t["torsional_stiffness"]
                ren["shaft_stiffness"] = f"shafts[{index[join]}].torsional_stiffness"
            chain["shafts"] = [{k: v for k, v in sh.items() if k != "torsional_stiffness"}
                               if sh is t else sh for sh in chain["shafts"]]
        if n and table != "chain":
            stage_tabs[n]["input_chain"] = chain
        else:
            out[table] = chain
        back |= {f"{table}.{a}": b for a, b in ren.items()}
        if table == "input_chain":
            for key in ("speed", "torque"):
                back[f"input_chain.operating.{key}"] = f"operating.{key}"
    return out, back



def _chain(g: _Graph, entry: str) -> tuple[dict[str, Any], dict[str, str]]:
    """The ``[chain]`` table of the gears the power reaches from shaft ``entry`` (the
    part of the graph holding it), its shafts in the order of the power flow (gear 1 on
    ``entry``), and the renaming of its elements' indices (``gears[0]`` of the chain ->
    ``gears[i]`` as written)."""
    doc, index, on, mesh_shafts = g.doc, g.index, g.on, g.mesh_shafts
    order, queue = [], [entry]
    while queue:  # breadth first from the shaft the power enters by
        n = queue.pop(0)
        if n in order:
            continue
        order.append(n)
        queue += [b if a == n else a for a, b in mesh_shafts if n in (a, b)]
    gear_ids = [i for n in order for i in on[n]]
    members = {g.gear_names[i] for i in gear_ids}
    mesh_ids = [j for j, (a, _) in enumerate(mesh_shafts) if a in order]
    ren = {"gears": "gears"}
    chain: dict[str, Any] = {"shafts": [g.shafts[index[n]] for n in order],
                             "gears": [g.gears[i] for i in gear_ids],
                             "meshes": [g.meshes[j] for j in mesh_ids]}
    for key, ids in (("shafts", [index[n] for n in order]), ("gears", gear_ids),
                     ("meshes", mesh_ids)):
        ren |= {f"{key}[{a}]": f"{key}[{b}]" for a, b in enumerate(ids)}
    ren |= {f"shafts.{n}.": f"shafts[{index[n]}]." for n in order}  # a shaft by its name
    for key in ("cracks", "faults", "modifications"):
        tabs = _tables(doc, key)
        ids = [i for i, t in enumerate(tabs) if t.get("gear") in members]
        if ids:
            chain[key] = [tabs[i] for i in ids]
            ren |= {f"{key}[{a}]": f"{key}[{b}]" for a, b in enumerate(ids)}
    for key in ("common", "stiffness"):
        if key in doc:
            chain[key] = doc[key]
            ren[key] = key
    return chain, ren
