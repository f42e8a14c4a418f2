"""Every public function, class, method and property of gearsim has a numpydoc docstring.

In the spirit of python-control's ``control/tests/docstrings_test.py``: walk all modules
of the package, collect the public names each module *defines*, and run
:func:`numpydoc.validate.validate` on them. Only a small set of numpydoc's codes is
enforced, the ones that make a docstring useful to a reader rather than pretty:

* ``GL08`` the object has no docstring;
* ``PR01`` a parameter of the signature is not documented;
* ``PR02`` a documented parameter is not in the signature (stale after a rename).

Style codes (summary punctuation, section order, "Returns" wording, ...) are not
enforced: they would turn the test into a formatter and hide the failures that matter.

Public means: a module whose name has no component starting with ``_`` (and not
``gearsim.cli``, the Typer entry point whose functions document themselves as command
help); in it, the names of ``__all__`` if the module has one, otherwise the names not
starting with ``_`` whose ``__module__`` is that module; in a public class, the methods
and properties the class itself defines (not inherited ones) whose name does not start
with ``_``. Module-level data (dicts, tuples, registries) is skipped: numpydoc would
validate the docstring of its type (``dict``), not of the constant. For dataclasses,
fields documented in the class's ``Parameters`` section count, as numpydoc validates a
class against its ``__init__`` signature.

All failures are collected and reported in one assertion so that one run lists them all.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from functools import cached_property

import numpydoc.validate
import pytest

import gearsim

CHECKED_CODES = ("GL08", "PR01", "PR02")
SKIPPED_MODULES = ("gearsim.cli",)


def _public_modules() -> list[str]:
    names = [gearsim.__name__]
    for info in pkgutil.walk_packages(gearsim.__path__, prefix=gearsim.__name__ + "."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts[1:]):
            continue
        if info.name in SKIPPED_MODULES or info.name.startswith(tuple(s + "." for s in
                                                                       SKIPPED_MODULES)):
            continue
        names.append(info.name)
    return sorted(names)


def _is_documentable(obj: object) -> bool:
    """Functions (also numba dispatchers, which wrap one) and classes; not data."""
    return inspect.isclass(obj) or inspect.isfunction(obj) or callable(getattr(obj, "py_func",
                                                                               None))


def _module_names(module) -> list[str]:
    if hasattr(module, "__all__"):
        names = list(module.__all__)
    else:
        names = [n for n in vars(module) if not n.startswith("_")]
    out = []
    for n in names:
        obj = getattr(module, n, None)
        if obj is None or inspect.ismodule(obj) or not _is_documentable(obj):
            continue
        if not hasattr(module, "__all__") and getattr(obj, "__module__", None) != module.__name__:
            continue  # imported from elsewhere: checked in its own module
        out.append(n)
    return out


def _class_members(cls: type) -> list[str]:
    out = []
    for n, attr in vars(cls).items():
        if n.startswith("_"):
            continue
        if isinstance(attr, (staticmethod, classmethod)):
            attr = attr.__func__
        if inspect.isfunction(attr) or isinstance(attr, (property, cached_property)):
            out.append(n)
    return out


def _targets() -> list[str]:
    targets = []
    for modname in _public_modules():
        module = importlib.import_module(modname)
        for n in _module_names(module):
            obj = getattr(module, n)
            # a name listed in __all__ but defined elsewhere is validated where it lives
            home = getattr(obj, "__module__", modname)
            qual = f"{modname}.{n}"
            if home != modname and home.startswith("gearsim"):
                continue
            targets.append(qual)
            if inspect.isclass(obj):
                targets.extend(f"{qual}.{m}" for m in _class_members(obj))
    return sorted(set(targets))


def _is_protocol(name: str) -> bool:
    """A typing.Protocol class: an interface, its generic ``__init__`` has no parameters."""
    modname, _, attr = name.rpartition(".")
    try:
        obj = getattr(importlib.import_module(modname), attr)
    except (ImportError, AttributeError):
        return False
    return inspect.isclass(obj) and getattr(obj, "_is_protocol", False)


def _failures(name: str) -> list[str]:
    result = numpydoc.validate.validate(name)
    codes = CHECKED_CODES if not _is_protocol(name) else ("GL08",)
    return [f"{name}: {code} {msg}" for code, msg in result["errors"] if code in codes]


def test_walk_finds_the_package():
    """The walk sees the subpackages and known public names (guards an empty walk)."""
    mods = _public_modules()
    for expected in ("gearsim.geometry.gear", "gearsim.stiffness.tooth", "gearsim.fem.solve"):
        assert expected in mods
    assert "gearsim.cli" not in mods
    assert not any("._" in m for m in mods)
    targets = _targets()
    for expected in ("gearsim.geometry.gear.Gear", "gearsim.geometry.gear.Gear.base_radius",
                     "gearsim.stiffness.tooth.hertz_stiffness",
                     "gearsim.errors.InputError"):
        assert expected in targets


def test_validator_catches_a_missing_parameter():
    """The chosen codes fire on a bad docstring (the check itself can fail)."""
    import types

    mod = types.ModuleType("gearsim_docstring_probe")

    def probe(a, b):
        """Summary line.

        Parameters
        ----------
        a
            Documented.
        c
            Not in the signature.
        """

    probe.__module__ = mod.__name__
    mod.probe = probe
    import sys

    sys.modules[mod.__name__] = mod
    try:
        codes = {c for c, _ in numpydoc.validate.validate(f"{mod.__name__}.probe")["errors"]}
    finally:
        del sys.modules[mod.__name__]
    assert {"PR01", "PR02"} <= codes


@pytest.mark.filterwarnings("ignore")
def test_public_docstrings():
    """GL08, PR01, PR02 over the whole public API; one assertion listing every failure."""
    failures = [f for name in _targets() for f in _failures(name)]
    assert not failures, f"{len(failures)} docstring failures:\n" + "\n".join(failures)
