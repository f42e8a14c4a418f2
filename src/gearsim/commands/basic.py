"""CLI verbs: ``example``, ``layout``, ``stiffness`` and ``contact``."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from gearsim.commands._options import as_options, with_torque
from gearsim.io.targets import check_output_file
from gearsim.model import example_text, load
from gearsim.system import train_stiffness
from gearsim.viz import check_plot_file, save

__all__ = ["register"]


def example(name: Annotated[str, typer.Argument(
        help="idler-table1, spur-19-48, two-stage-reducer, lin-parker-1999, nrel-grc or "
             "wind-turbine-grc")]) -> None:
    """Print a built-in example configuration (TOML)."""
    typer.echo(example_text(name), nl=False)


def layout(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    plot: Annotated[str | None, typer.Option(help="figure of the layout (.png, .pdf, .svg)")]
    = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
) -> None:
    """The gearbox as a graph: shafts (speed, torque), gears, meshes (driver -> driven,
    mesh frequency, static force) and the planetary stage, with a plan-view figure."""
    import math

    from gearsim.dynamics.layout import idlers
    from gearsim.dynamics.layout import layout as plan

    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)
    stage = getattr(gb.train, "stage", None)
    train = gb.chain if stage is not None else gb.train
    out: dict = {"name": train.name if stage is None else gb.train.name, "shafts": [],
                 "meshes": []}
    if stage is not None:
        tr = gb.train
        out["stage"] = {"teeth": [stage.sun_teeth, stage.planet_teeth, stage.ring_teeth],
                        "planets": stage.planets, "fixed": tr.operating.fixed,
                        "input": tr.operating.input, "mesh_frequency_hz": tr.mesh_frequency,
                        "speeds_rpm": {m: w * 30 / math.pi for m, w in tr.speeds.items()}}
    if train is not None:
        fl = train.flow
        for sh in fl.shafts:
            i = train.gear_index(sh.gears[0])
            out["shafts"].append({"name": sh.name, "gears": list(sh.gears),
                                  "speed_rpm": train.speed(i) * 30 / math.pi,
                                  "torque_Nm": train.torque(i)})
        for m, p in enumerate(train.pairs):
            out["meshes"].append({"mesh": p.name, "driver": p.driver.name,
                                  "driven": p.driven.name,
                                  "mesh_frequency_hz": train.mesh_frequencies[m],
                                  "static_force_N": train.static_mesh_force(m)})
    if plot is not None:
        from gearsim.viz.layout import plot_layout

        shafts, gears, links, st = [], [], [], None
        if train is not None:
            n_id = len(idlers(train))
            lay = plan(train, gb.dynamics.per_item("idler_angle", n_id, "idler"))
            shafts = [(sh.name, tuple(c)) for sh, c in zip(fl.shafts, lay.centres, strict=True)]
            gears = [(g.name, fl.shaft_of[g.name], g.pitch_radius, g.teeth) for g in train.gears]
            links = [(p.driver.name, p.driven.name, p.name) for p in train.pairs]
        if stage is not None:
            st = {"sun": stage.sun.pitch_radius, "ring": stage.ring.pitch_radius,
                  "planet": stage.planet.pitch_radius, "centre": stage.centre_distance,
                  "angles": list(stage.planet_angles_value),
                  "teeth": (stage.sun_teeth, stage.planet_teeth, stage.ring_teeth)}
        save(plot_layout(shafts, gears, links, title=out["name"], stage=st), plot,
             parameter="--plot")
    if json_:
        typer.echo(json.dumps(out, indent=2))
        return
    typer.echo(out["name"])
    if "stage" in out:
        s_ = out["stage"]
        typer.echo(f"stage {s_['teeth'][0]}/{s_['teeth'][1]}/{s_['teeth'][2]} x "
                   f"{s_['planets']}: {s_['input']} in, {s_['fixed']} held; f_m "
                   f"{s_['mesh_frequency_hz']:.6g} Hz")
    for sh in out["shafts"]:
        typer.echo(f"shaft {sh['name']}: {', '.join(sh['gears'])}; {sh['speed_rpm']:.6g} rpm, "
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
    # every output target is checked before any work
    if out is not None:
        out = check_output_file(out, "--out", (".csv", ".nc"))
    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)
    if getattr(gb, "kind", "") == "planetary":
        _stage_stiffness(gb, out, plot, json_, crack, closure)
        return
    with as_options({"crack": "--crack", "stiffness.closure": "--closure"}):
        train = gb.train.with_crack(crack, closure=closure)
    ts = train_stiffness(train)
    if out is not None:
        ts.write(out)
    if plot is not None:
        save(ts.plot(), plot, parameter="--plot")
    summary = ts.summary()
    if json_:
        typer.echo(json.dumps(summary, indent=2))
    else:
        for m in summary["meshes"]:
            typer.echo(f"mesh {m['mesh']} ({m['gears'][0]} -> {m['gears'][1]}): "
                       f"k mean {m['k_mean'] / 1e9:.4f} GN/m, min {m['k_min'] / 1e9:.4f}, "
                       f"max {m['k_max'] / 1e9:.4f}; eps_alpha {m['eps_alpha']:.3f}, "
                       f"eps_beta {m['eps_beta']:.3f}; mean / ISO 6336 c_ga b = "
                       f"{m['ratio_to_iso6336']:.3f}")


def _stage_stiffness(box, out, plot, json_: bool, crack: str | None, closure: str | None
                     ) -> None:
    """The ``stiffness`` verb for a planetary stage (every sun and ring mesh)."""
    import dataclasses

    from gearsim.system.planetary import stage_stiffness

    with as_options({"crack": "--crack"}):
        box = box.with_crack(crack)
    train = box.train
    if closure is not None:
        with as_options({"stiffness.closure": "--closure"}):
            train = dataclasses.replace(train, settings=dataclasses.replace(
                train.settings, closure=closure))
    summary, ds = stage_stiffness(train)
    if box.chain is not None:  # the parallel gears on the output shaft
        chain = box.chain.with_crack("none") if crack == "none" else box.chain
        summary["chain"] = train_stiffness(chain).summary()
    if out is not None:
        if str(out).endswith(".nc"):
            from gearsim.io.results import write_results

            write_results(ds, out)
        else:
            from gearsim.io.atomic import atomic_write

            def write(tmp) -> None:
                with open(tmp, "w", encoding="utf-8") as f:
                    f.write(f"# gearsim TVMS of '{train.name}'; stiffness in N/m along the "
                            "transverse line of action, cycles counted from each table's "
                            "start (forward sense)\nmesh,cycles,k\n")
                    for name in ds.data_vars:
                        mesh = name[2:]
                        for c, k in zip(ds[f"cycles_{mesh}"].values, ds[name].values,
                                        strict=True):
                            f.write(f"{mesh},{c:.10g},{k:.10g}\n")
            atomic_write(out, write)
    if plot is not None:
        from gearsim.viz.planetary import plot_stage_meshes

        save(plot_stage_meshes(train), plot, parameter="--plot")
    if json_:
        typer.echo(json.dumps(summary, indent=2))
        return
    typer.echo(f"{summary['name']}: f_m {summary['mesh_frequency']:.6g} Hz, "
               f"{summary['phasing']} planets; eps_alpha sun-planet "
               f"{summary['eps_alpha_sun']:.3f}, ring-planet {summary['eps_alpha_ring']:.3f}, "
               f"eps_beta {summary['eps_beta']:.3f}")
    for m in summary["meshes"]:
        typer.echo(f"mesh {m['mesh']}: k mean {m['k_mean'] / 1e9:.4f} GN/m, min "
                   f"{m['k_min'] / 1e9:.4f}, max {m['k_max'] / 1e9:.4f}; period "
                   f"{m['period_cycles']} cycles, phase {m['phase_cycles']:+.4f}; mean / "
                   f"ISO 6336 c_ga b = {m['ratio_to_iso6336']:.3f}")
    for m in summary.get("chain", {}).get("meshes", []):
        typer.echo(f"chain mesh {m['mesh']} ({m['gears'][0]} -> {m['gears'][1]}): k mean "
                   f"{m['k_mean'] / 1e9:.4f} GN/m, min {m['k_min'] / 1e9:.4f}, max "
                   f"{m['k_max'] / 1e9:.4f}; mean / ISO 6336 c_ga b = "
                   f"{m['ratio_to_iso6336']:.3f}")


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
    from gearsim.stiffness.ltca import loaded_contact

    if out is not None:
        out = check_output_file(out, "--out", (".nc",))
    if plot is not None:
        plot = check_plot_file(plot, "--plot")
    gb = load(config)
    train = gb.train
    n = len(train.pairs)
    if not 0 <= mesh < n:
        raise InputError("--mesh", mesh, f"must be in 0 .. {n - 1} ({n} meshes)")
    train = with_torque(train, torque)
    lc = loaded_contact(train.mesh_contacts(mesh), train.static_mesh_force(mesh))
    if out is not None:
        from gearsim.io.atomic import atomic_write

        ds = lc.to_dataset()
        atomic_write(out, lambda p: ds.to_netcdf(p, engine="h5netcdf"))
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

