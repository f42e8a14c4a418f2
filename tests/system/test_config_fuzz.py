"""Property test: a gearbox file with one value replaced by a bad one is read, or refused
with an InputError that names a section of the file as written.

Starting points: two gearboxes of shafts and planetary stages in the graph form
(gears-stage-stage-gears, and wind-turbine-grc), the stage form they are translated into
(the same gears-stage-stage-gears box, nrel-grc, lin-parker-1999), a gear-train graph
(two-stage-reducer), two whose power branches (tests/system/test_branching.py) and the
chains of gears (idler-table1, spur-19-48): every example.
Hypothesis picks one value of the file (any table, any key) and
one bad value (non-finite, zero, negative, absurd, tiny, of the wrong type or unit, a
name that does not exist). The loader (:func:`gearsim.loads`) may accept it (a value that
happens to be valid) or refuse it; a refusal must be :class:`gearsim.InputError` (no other
exception: no traceback), one line, whose parameter starts with a section of the file;
of a graph of stages, never one of the stage form the graph is translated into
(``chain.``, ``input_chain.``, ``stage.``, ``members.``, ``stages[k]`` beyond the file's
stages). Every (value, bad value) pair of idler-table1, spur-19-48 and lin-parker-1999, and
1500 examples of each other file, were run once (all held); the suite runs 300 a file.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib

import pytest
from branching_boxes import GEAR_SPLIT, SHAFT_SPLIT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from two_stage_boxes import TOML_CHAINS, TOML_CHAINS_GRAPH

from gearsim.errors import InputError
from gearsim.model import example_text, loads

#: Gears, stage, stage, gears; and a stage driving gears (the example), as graphs; and
#: the stage form the graphs are translated into (the same checks run there).
BASES = {"gears-stages-gears": tomllib.loads(TOML_CHAINS_GRAPH),
         "wind-turbine-grc": tomllib.loads(example_text("wind-turbine-grc")),
         "stage-form": tomllib.loads(TOML_CHAINS),
         "nrel-grc": tomllib.loads(example_text("nrel-grc")),
         "two-stage-reducer": tomllib.loads(example_text("two-stage-reducer")),
         "idler-table1": tomllib.loads(example_text("idler-table1")),
         "spur-19-48": tomllib.loads(example_text("spur-19-48")),
         "lin-parker-1999": tomllib.loads(example_text("lin-parker-1999")),
         "gear-split": tomllib.loads(GEAR_SPLIT), "shaft-split": tomllib.loads(SHAFT_SPLIT)}
BAD = ["nan mm", "inf N*m/rad", "-inf deg", 0, -1, -3.5, 1e300, "1e300 mm", "1e-300 rpm",
       "1e-300 N*m", "1e-300 mm", "12 kg", "x", "", [1, 2], True, "housing", "nowhere",
       "-5 mm", "0 deg", "90 deg"]
#: The stage form's own table names, which a refusal of the graph form must not show.
FOREIGN = ("chain.", "chain =", "input_chain", "stage.", "members.")


def _lit(v) -> str:
    """TOML text of a value; tables and arrays of tables inline (the same document)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_lit(x) for x in v) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {_lit(x)}" for k, x in v.items()) + "}"


def _leaves(doc, path=()):
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _leaves(v, (*path, k))
    elif isinstance(doc, list) and doc and all(isinstance(t, dict) for t in doc):
        for i, t in enumerate(doc):
            yield from _leaves(t, (*path, i))
    else:
        yield path


LEAVES = {k: sorted(_leaves(doc), key=str) for k, doc in BASES.items()}


def _set(doc, path, value):
    out = copy.deepcopy(doc)
    node = out
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return out


@pytest.mark.parametrize("base", sorted(BASES))
@settings(derandomize=True, database=None, deadline=None, max_examples=300,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_one_bad_value_is_read_or_refused_as_written(base, data):
    path = data.draw(st.sampled_from(LEAVES[base]), label="path")
    value = data.draw(st.sampled_from(BAD), label="value")
    doc = _set(BASES[base], path, value)
    text = "\n".join(f"{json.dumps(k)} = {_lit(v)}" for k, v in doc.items())
    assert tomllib.loads(text) == doc
    try:
        loads(text)
    except InputError as exc:
        line = str(exc)
        assert "\n" not in line, line
        # a section of the file as written
        assert exc.parameter.split(".")[0].split("[")[0] in doc, (path, value, line)
        if "shafts" in doc and "stages" in doc:  # a graph of stages: not the stage form
            beyond = f"stages[{len(doc['stages'])}]"
            assert not any(line.startswith(f) for f in (*FOREIGN, beyond)), (path, value, line)
