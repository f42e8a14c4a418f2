"""CLI verbs: ``example``, ``layout``, ``stiffness`` and ``contact``."""

from __future__ import annotations

import dataclasses
import json
from typing import Annotated

import typer

from gearsim.commands._options import as_options, with_torque

__all__ = ["register"]


def example(name: Annotated[str, typer.Argument(
        help="idler-table1, spur-19-48, two-stage-reducer, lin-parker-1999, nrel-grc or "
             "wind-turbine-grc")]) -> None:
    """Print a built-in example configuration (TOML)."""
    from gearsim.data import example_text  # the file, without the model's imports

    typer.echo(example_text(name), nl=False)


def layout(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    plot: Annotated[str | None, typer.Option(help="figure of the layout (.png, .pdf, .svg)")]
    = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
) -> None:
    """The gearbox as a graph: shafts (speed, torque), gears, meshes (driver -> driven,
    mesh frequency, static force) and the planetary stage, with a figure in plan and side
    view."""
    from gearsim.model import load
    from gearsim.viz import check_plot_file, save

    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    out = load(config).layout()
    drawing = out.pop("plan")
    if plot is not None:
        from gearsim.viz.layout import plot_layout

        save(plot_layout(drawing["shafts"], drawing["gears"], drawing["links"],
                         title=out["name"], stage=drawing["stage"],
                         upstream=drawing["upstream"]), plot, parameter="--plot")
    if json_:
        typer.echo(json.dumps(out, indent=2))
        return
    typer.echo(out["name"])
    for k, s_ in enumerate([out["stage"], *out.get("next_stages", [])] if "stage" in out
                           else []):
        typer.echo(f"stage{f' {k + 1}' if 'next_stages' in out else ''} "
                   f"{s_['teeth'][0]}/{s_['teeth'][1]}/{s_['teeth'][2]} x "
                   f"{s_['planets']}: {s_['input']} in, {s_['fixed']} held; f_m "
                   f"{s_['mesh_frequency_hz']:.6g} Hz"
                   + ("; " + ", ".join(f"{m} on {sh}" for m, sh in s_["member_shafts"].items())
                      if "member_shafts" in s_ else ""))
    for sh in out["shafts"]:
        typer.echo(f"shaft {sh['name']}: {', '.join(sh['gears'] + sh.get('members', []))}; "
                   f"{sh['speed_rpm']:.6g} rpm, "
                   f"{sh['torque_Nm']:.6g} N m")
    for m in out["meshes"]:
        typer.echo(f"mesh {m['mesh']}: {m['driver']} -> {m['driven']}; f_m "
                   f"{m['mesh_frequency_hz']:.6g} Hz, static force {m['static_force_N']:.6g} N")


def stiffness(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    out: Annotated[str | None, typer.Option(help="TVMS table, .csv or .nc")] = None,
    plot: Annotated[str | None, typer.Option(help="figure of the TVMS (.png, .pdf, .svg)")]
    = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
    crack: Annotated[str | None, typer.Option(help="none, working or non-working")] = None,
    closure: Annotated[str | None, typer.Option(help="open or contact")] = None,
) -> None:
    """Time-varying mesh stiffness of every mesh over one revolution of each gear."""
    from gearsim.io.targets import check_output_file
    from gearsim.model import load
    from gearsim.viz import check_plot_file, save

    # every output target is checked before any work
    if out is not None:
        out = check_output_file(out, "--out", (".csv", ".nc"))
    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)  # the file's own values are named as written in it
    with as_options({"crack": "--crack", "stiffness.closure": "--closure"}):
        gb = gb.with_crack(crack, closure=closure)
    ts = gb.tvms()
    if out is not None:
        ts.write(out)
    if plot is not None:
        save(ts.figure(), plot, parameter="--plot")
    summary = ts.summary
    if json_:
        typer.echo(json.dumps(summary, indent=2))
        return
    nexts = summary.get("next_stages", [])  # stages in series, each with its meshes
    stages = [("", summary)] if not nexts else [
        (f"stage{k}-", st) for k, st in enumerate([summary, *nexts], 1)]

    def show(pre: str, m: dict) -> None:
        gears = f" ({m['gears'][0]} -> {m['gears'][1]})" if "gears" in m else ""
        extra = (f"period {m['period_cycles']} cycles, phase {m['phase_cycles']:+.4f}"
                 if "period_cycles" in m else
                 f"eps_alpha {m['eps_alpha']:.3f}, eps_beta {m['eps_beta']:.3f}")
        typer.echo(f"{pre}{gears}: k mean {m['k_mean'] / 1e9:.4f} GN/m, min "
                   f"{m['k_min'] / 1e9:.4f}, max {m['k_max'] / 1e9:.4f}; {extra}; mean / "
                   f"ISO 6336 c_ga b = {m['ratio_to_iso6336']:.3f}")

    for pre, st in stages:
        for m in st.get("input_chain", {}).get("meshes", []):  # the gears driving it
            show(f"{'input ' if st is summary else ''}chain mesh {m['mesh']}", m)
        if "phasing" in st:
            title = f"{pre[:-1]} ({st['name']})" if pre else st["name"]
            typer.echo(f"{title}: f_m {st['mesh_frequency']:.6g} Hz, "
                       f"{st['phasing']} planets; eps_alpha sun-planet "
                       f"{st['eps_alpha_sun']:.3f}, ring-planet "
                       f"{st['eps_alpha_ring']:.3f}, eps_beta {st['eps_beta']:.3f}")
        for m in st["meshes"]:
            show(f"mesh {pre}{m['mesh']}", m)
    for m in summary.get("chain", {}).get("meshes", []):
        show(f"chain mesh {m['mesh']}", m)


def contact(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    mesh: Annotated[int, typer.Option(help="mesh index (0 = mesh I)")] = 0,
    torque: Annotated[str | None, typer.Option(
        help="input torque, e.g. '2000 N*m' (default the configuration's)")] = None,
    out: Annotated[str | None, typer.Option(help="results, .nc")] = None,
    plot: Annotated[str | None, typer.Option(help="figure (.png, .pdf, .svg)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
) -> None:
    """Loaded tooth contact analysis of one mesh with its faults and modifications:
    loaded transmission error, load sharing and contact pattern over a period."""
    from gearsim.errors import InputError
    from gearsim.io.targets import check_output_file
    from gearsim.model import load
    from gearsim.stiffness.ltca import loaded_contact
    from gearsim.viz import check_plot_file, save

    if out is not None:
        out = check_output_file(out, "--out", (".nc",))
    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)
    if not gb.chains:
        raise InputError("config", config, "has no external gear mesh (a planetary stage "
                         "alone): the loaded contact analysis needs [[gears]]")
    train, i, name = with_torque(gb, torque).gear_mesh(mesh, "--mesh")
    grid = dataclasses.replace(train.mesh_contacts(i), name=name)  # the gearbox's name
    lc = loaded_contact(grid, train.static_mesh_force(i))
    if out is not None:
        from gearsim.io.results import write_results

        write_results(lc.to_dataset(), out)
    if plot is not None:
        save(lc.plot(), plot, parameter="--plot")
    s = lc.summary()
    if json_:
        typer.echo(json.dumps(s, indent=2))
        return
    ptp = s["loaded_te_ptp_m"]
    typer.echo(f"mesh {s['mesh']}: F = {s['force_N'] / 1e3:.4g} kN over {s['period_cycles']} "
               f"mesh cycles; loaded TE peak-to-peak {ptp * 1e6:.4g} um, mean stiffness "
               f"{(s['stiffness_mean_N_per_m'] or 0) / 1e9:.4f} GN/m, largest line load "
               f"{s['max_line_load_N_per_m'] / 1e3:.4g} N/mm; positions without contact: "
               f"{s['positions_without_contact']} of {s['positions']}")


def register(app: typer.Typer) -> None:
    """Add the verbs of this module to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`); ``example``, ``layout``,
        ``stiffness`` and ``contact`` are registered on it.
    """
    app.command("example")(example)
    app.command("layout")(layout)
    app.command("stiffness")(stiffness)
    app.command("contact")(contact)

