"""The plotting convention of :mod:`gearsim.viz`.

Every plot function returns a Figure, draws into a caller's ``ax=`` (single panel) or
``fig=`` (several panels), draws in the house style without touching the global
``matplotlib.rcParams``, and writes nothing; :func:`gearsim.viz.save` is the only writer.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

import gearsim
from gearsim.errors import InputError
from gearsim.viz import DPI, STYLE, save, save_all

VIZ_MODULES = ("contacts", "dynamics", "fem", "planetary", "reproduce", "signals", "stiffness",
               "sweep", "toolbox")
VIZ_DIR = Path(gearsim.__file__).parent / "viz"

# name -> (fixture, extra kwargs, "ax" or "fig": the keyword of the target)
CALLS: dict[str, tuple[str, dict, str]] = {
    "contacts.plot_loaded_contact": ("loaded_contact_result", {}, "fig"),
    "dynamics.plot_run": ("dynamics_run", {}, "fig"),
    "fem.plot_fe_check": ("fe_result", {}, "fig"),
    "planetary.plot_stage_meshes": ("stage_train", {"cycles": 2.0}, "fig"),
    "planetary.plot_gearbox_meshes": ("gears_and_stage", {"names": ("II",)}, "fig"),
    "reproduce.plot_stiffness": ("reproduction", {}, "fig"),
    "reproduce.plot_time": ("reproduction", {}, "fig"),
    "reproduce.plot_spectrum": ("reproduction", {}, "ax"),
    "reproduce.plot_zooms": ("reproduction", {}, "fig"),
    "reproduce.plot_stft": ("reproduction", {}, "fig"),
    "reproduce.plot_sensitivity": ("reproduction", {}, "fig"),
    "reproduce.plot_fault_magnitudes": ("reproduction", {}, "fig"),
    "signals.plot_time": ("analysis", {"units": "N"}, "fig"),
    "signals.plot_spectrum": ("analysis", {"units": "N"}, "ax"),
    "signals.plot_zooms": ("analysis", {}, "fig"),
    "signals.plot_spectrogram": ("analysis", {}, "fig"),
    "signals.plot_tsa": ("analysis", {}, "fig"),
    "signals.plot_comparison": ("comparison", {}, "fig"),
    "stiffness.plot_train_stiffness": ("spur_stiffness", {}, "fig"),
    "stiffness.plot_mesh_tvms": ("spur_stiffness", {}, "ax"),
    "sweep.plot_separability": ("separability_rows", {"title": "test"}, "fig"),
    "sweep.plot_confusion": ("separability_rows",
                             {"classes": ("none", "working", "non-working")}, "fig"),
    "sweep.plot_diagnostic": ("separability_rows",
                              {"classes": ("none", "working", "non-working")}, "fig"),
    "toolbox.plot_envelope_spectrum": ("envelope_result", {}, "ax"),
    "toolbox.plot_kurtogram": ("kurtogram_result", {}, "ax"),
}
# Tested by hand below (not one result object in, or a collection of figures out).
OTHER = {"fem.plot_mesh", "stiffness.plot_healthy_vs_cracked", "reproduce.plot_all",
         "toolbox.plot_cepstrum"}


def _function(name: str):
    mod, func = name.split(".")
    return getattr(importlib.import_module(f"gearsim.viz.{mod}"), func)


def _public_plot_functions() -> set[str]:
    out = set()
    for mod in VIZ_MODULES:
        m = importlib.import_module(f"gearsim.viz.{mod}")
        out |= {f"{mod}.{n}" for n in m.__all__ if n.startswith("plot_")
                and inspect.isfunction(getattr(m, n))}
    return out


def _call(name: str, request, **target) -> Figure:
    fixture, kwargs, _ = CALLS[name]
    return _function(name)(request.getfixturevalue(fixture), **kwargs, **target)


def test_every_plot_function_is_covered():
    assert _public_plot_functions() == set(CALLS) | OTHER


@pytest.mark.parametrize("name", sorted(CALLS))
def test_returns_figure_keyword_target_and_no_global_state(name, request, tmp_path,
                                                           monkeypatch):
    monkeypatch.chdir(tmp_path)
    func = _function(name)
    kind = CALLS[name][2]
    param = inspect.signature(func).parameters[kind]
    assert param.kind is inspect.Parameter.KEYWORD_ONLY and param.default is None
    before = dict(matplotlib.rcParams)
    caller = {"font.size": 5.0, "ytick.labelsize": 5.0, "axes.labelsize": 5.0,
              "axes.grid": False}
    with matplotlib.rc_context(caller):
        fig = _call(name, request)
    assert isinstance(fig, Figure)
    assert dict(matplotlib.rcParams) == before
    assert fig.dpi == DPI
    assert not list(tmp_path.iterdir()), "a plot function wrote a file"
    # renders with its Agg canvas (no pyplot, no GUI), in the house style although the
    # caller's settings differ both when drawing and when rendering
    with matplotlib.rc_context(caller):
        fig.canvas.draw()
    assert np.asarray(fig.canvas.buffer_rgba()).shape[2] == 4
    ax = fig.axes[0]
    assert {t.get_fontsize() for t in ax.yaxis.get_ticklabels()} == {STYLE["ytick.labelsize"]}
    assert ax.yaxis.label.get_fontsize() == STYLE["axes.labelsize"]
    if not name.endswith(("plot_stft", "plot_mesh", "plot_kurtogram",
                          "plot_confusion")):  # images: no grid
        assert any(line.get_visible() for line in ax.get_xgridlines())
    assert dict(matplotlib.rcParams) == before


@pytest.mark.parametrize("name", sorted(CALLS))
def test_draws_into_the_callers_axes_or_figure(name, request):
    kind = CALLS[name][2]
    target = Figure(figsize=(8, 6))
    if kind == "ax":
        ax = target.add_subplot(2, 1, 2)
        fig = _call(name, request, ax=ax)
        image = name.endswith("plot_kurtogram")  # an image map with its colour bar axes
        assert fig is target and len(target.axes) == (2 if image else 1)
        assert ax.collections if image else ax.lines
    else:
        fig = _call(name, request, fig=target)
        assert fig is target and len(target.axes) >= 2
        assert tuple(target.get_size_inches()) == (8, 6)


def test_single_panel_functions_without_a_result_object(tmp_path):
    from gearsim.viz.fem import plot_mesh
    from gearsim.viz.stiffness import plot_healthy_vs_cracked

    before = dict(matplotlib.rcParams)
    p = np.array([[0.0, 1e-3, 0.0, 1e-3], [0.0, 0.0, 1e-3, 1e-3]])
    t = np.array([[0, 1], [1, 3], [2, 2]])
    crack = type("C", (), {"start": (0.0, 0.0), "tip": (5e-4, 5e-4)})()
    fig = plot_mesh(p, t, crack=crack, window=(0, 1e-3, 0, 1e-3))
    assert isinstance(fig, Figure) and len(fig.axes[0].lines) == 3  # triplot: 2 lines + crack
    x = np.linspace(0, 10, 20)
    ax = Figure().add_subplot()
    assert plot_healthy_vs_cracked({"a": (x, x * 1e9)}, ax=ax) is ax.figure
    assert plot_mesh(p, t, ax=ax) is ax.figure
    assert dict(matplotlib.rcParams) == before
    assert not list(tmp_path.iterdir())


def test_result_objects_hand_off_in_one_line(analysis, spur_stiffness, fe_result):
    figs = analysis.figures(units="N")
    assert list(figs) == ["time", "spectrum", "zoom_mesh_harmonics", "spectrogram", "tsa"]
    assert all(isinstance(f, Figure) for f in figs.values())
    ax = Figure().add_subplot()
    assert analysis.plot("spectrum", ax=ax) is ax.figure
    assert isinstance(analysis.plot("tsa"), Figure)
    with pytest.raises(InputError, match="kind"):
        analysis.plot("bode")
    with pytest.raises(InputError, match="pass fig="):
        analysis.plot("time", ax=ax)
    assert len(spur_stiffness.plot().axes) == 2 * len(spur_stiffness.train.pairs)
    ax = Figure().add_subplot()
    assert spur_stiffness.plot(0, ax=ax) is ax.figure
    with pytest.raises(InputError, match="mesh"):
        spur_stiffness.plot(7)
    assert len(fe_result.plot().axes) == 2


def test_reproduce_figures_names_and_captions(reproduction):
    from gearsim.viz.reproduce import CAPTIONS, plot_all

    figs = plot_all(reproduction)
    names = ["fig3_stiffness", "fig5_time", "fig6_spectrum", "fig7_zooms", "fig8_stft",
             "fig_sensitivity", "fig_fault_magnitudes"]
    drawn = names if reproduction.fault_magnitudes else names[:-1]
    assert list(figs) == drawn and list(CAPTIONS) == names
    assert all(isinstance(f, Figure) for f in figs.values())
    assert all(len(c) > 40 for c in CAPTIONS.values())
    # the seed's values come from the result, drawn as dotted reference lines
    ax_rms = figs["fig_sensitivity"].axes[2]
    ys = [line.get_ydata()[0] for line in ax_rms.lines if line.get_linestyle() == ":"]
    assert pytest.approx(sorted(ys)) == [97.3, 132.4]


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


def _small_figure() -> Figure:
    from gearsim.viz.style import new_figure

    fig = new_figure(4, 3)
    fig.add_subplot().plot([0, 1], [0, 1])
    return fig


def test_save_formats_dpi_and_folder(tmp_path):
    fig = _small_figure()
    out = save(fig, tmp_path / "a" / "b" / "f.png")
    assert out == tmp_path / "a" / "b" / "f.png"
    assert _png_size(out) == (4 * DPI, 3 * DPI)
    assert _png_size(save(fig, tmp_path / "g.png", dpi=50)) == (200, 150)
    assert save(fig, tmp_path / "f.pdf").read_bytes()[:5] == b"%PDF-"
    assert b"<svg" in save(fig, tmp_path / "f.SVG").read_bytes()[:1000]
    before = dict(matplotlib.rcParams)
    paths = save_all({"one": fig, "two": _small_figure()}, tmp_path / "all", "svg")
    assert [p.name for p in paths] == ["one.svg", "two.svg"]
    assert all(p.is_file() for p in paths)
    assert dict(matplotlib.rcParams) == before


@pytest.mark.parametrize("parameter", ["path", "--plot"])
def test_save_refuses_unknown_suffix(tmp_path, parameter):
    with pytest.raises(InputError) as exc:
        save(_small_figure(), tmp_path / "sub" / "out.xyz",
             **({} if parameter == "path" else {"parameter": parameter}))
    assert exc.value.parameter == parameter
    assert str(exc.value) == f"{parameter} = {tmp_path / 'sub' / 'out.xyz'}: " \
                             "must end in .png, .pdf or .svg"
    assert not (tmp_path / "sub").exists()
    with pytest.raises(InputError, match="fmt"):
        save_all({"a": _small_figure()}, tmp_path, "jpg")
    assert not list(tmp_path.iterdir())


def test_save_is_atomic(tmp_path, monkeypatch):
    target = tmp_path / "f.png"
    target.write_bytes(b"old result")
    fig = _small_figure()

    def broken(path, **kwargs):
        Path(path).write_bytes(b"half a PNG")
        raise RuntimeError("disk full")

    monkeypatch.setattr(fig, "savefig", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        save(fig, target)
    assert target.read_bytes() == b"old result"
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]  # no temporary file left


def test_cli_refuses_unknown_plot_suffix(tmp_path, monkeypatch, capsys):
    import sys

    from gearsim import cli

    monkeypatch.setattr(sys, "argv", ["gearsim", "stiffness", "spur-19-48", "--plot",
                                      str(tmp_path / "s.xyz")])
    with pytest.raises(SystemExit) as exc:
        cli.main()
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2
    assert err == [f"gearsim: error: --plot = {tmp_path / 's.xyz'}: must end in .png, .pdf "
                   "or .svg"]


_GLOBAL_STATE = re.compile(r"rcParams\s*(\.update|\[)|\bmatplotlib\.rc\(|\bmpl\.rc\(|"
                           r"style\.use\(|matplotlib\.use\(|import matplotlib\.pyplot")


def test_no_module_changes_global_matplotlib_state():
    src = Path(gearsim.__file__).parent
    bad = [f"{p.relative_to(src)}:{i}: {line.strip()}"
           for p in sorted(src.rglob("*.py"))
           for i, line in enumerate(p.read_text().splitlines(), 1)
           if _GLOBAL_STATE.search(line)]
    assert not bad, "\n".join(bad)


def _runtime_imports(path: Path) -> list[str]:
    """Modules imported by ``path`` outside ``if TYPE_CHECKING:`` blocks."""
    tree = ast.parse(path.read_text())
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip |= {id(n) for b in node.body for n in ast.walk(b)}
    out = []
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            out.append(node.module)
    return out


ALLOWED = ("__future__", "collections", "functools", "math", "pathlib", "typing",
           "matplotlib", "numpy", "xarray", "gearsim.errors", "gearsim.io.atomic",
           "gearsim.io.targets", "gearsim.viz")


@pytest.mark.parametrize("path", sorted(VIZ_DIR.glob("*.py")), ids=lambda p: p.name)
def test_viz_is_the_bottom_layer(path):
    bad = [m for m in _runtime_imports(path)
           if not any(m == a or m.startswith(a + ".") for a in ALLOWED)]
    assert not bad, f"{path.name} imports {bad} at run time"


def test_core_imports_viz_only_lazily():
    """Computation modules import the plotting layer (and matplotlib) only on demand.

    The study drivers (``gearsim.studies``) and the CLI verbs (``gearsim.commands``),
    whose job includes writing figures, may import it at module level.
    """
    src = Path(gearsim.__file__).parent
    bad = []
    for p in sorted(src.rglob("*.py")):
        if p.parent.name in ("viz", "studies", "commands"):
            continue
        tree = ast.parse(p.read_text())
        for node in tree.body:  # module level only
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
                    "gearsim.viz") or isinstance(node, ast.Import) and any(
                    a.name.startswith("gearsim.viz") for a in node.names):
                bad.append(f"{p.relative_to(src)}:{node.lineno}")
    assert not bad, bad
