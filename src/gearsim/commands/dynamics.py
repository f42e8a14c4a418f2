"""CLI verb ``simulate``: train dynamics to a NetCDF file, with a JSON summary.

The output files are checked before any work, and the run's cost before the model is
built (:func:`gearsim.dynamics.simulate.check_cost`): more than 1e9 integration steps or
an estimated memory above half of the machine's are refused unless ``--force`` (or
``GEARSIM_FORCE=1``) is given; an output rate that would alias the mesh harmonics of the
config's ``[analysis] orders`` is always refused.
"""

from __future__ import annotations

import json
from typing import Annotated

import typer

from gearsim.commands._options import as_options

__all__ = ["register"]


def simulate(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    out: Annotated[str, typer.Option(help="results file (NetCDF, .nc)")] = "run.nc",
    crack: Annotated[str | None, typer.Option(
        help="none, working or non-working (default: as in the config)")] = None,
    duration: Annotated[float | None, typer.Option(help="recorded duration in s (> 0, <= 1e4)")] = None,
    fs: Annotated[float | None, typer.Option(help="output sampling rate in Hz (> 0, <= 1e7)")] = None,
    step: Annotated[float | None, typer.Option(help="largest integration step in s (1e-9 to 1)")] = None,
    transient: Annotated[float | None, typer.Option(
        help="dropped transient in s (>= 0, 0: none; default: from the damping)")] = None,
    model: Annotated[str | None, typer.Option(help="lta, torsional or seed")] = None,
    plot: Annotated[bool, typer.Option("--plot", help="also write a PNG beside --out")] = False,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="run even above the cost bounds (1e9 steps, half the memory); "
                        "or set GEARSIM_FORCE=1")] = False,
) -> None:
    """Simulate the gearbox; write mesh forces, DTE, bearing forces, accelerations.

    The summary gives each mesh force's mean, its RMS about the mean (the fluctuation)
    and its peak, for every kind of gearbox."""
    from gearsim.io.results import write_results
    from gearsim.io.targets import check_output_file
    from gearsim.model import load

    # every output target is checked before any work
    target = check_output_file(out, "--out", (".nc",))
    if plot:  # matplotlib only when a figure is asked for (~0.4 s of imports)
        from gearsim.viz import check_plot_file, save
        from gearsim.viz.dynamics import plot_run

        check_plot_file(target.with_suffix(".png"), "--plot")
    changes = {k: v for k, v in {"duration": duration, "fs": fs, "step": step,
                                 "transient": transient, "model": model}.items()
               if v is not None}
    gb = load(config)
    # every value is checked where the settings are made; the message names the option
    names = {"crack": "--crack", **{f"dynamics.{k}": f"--{k}" for k in changes}}
    with as_options(names):
        gb = gb.with_crack(crack).replace(dynamics=changes)
        # cost and aliasing (of the harmonics the analysis looks at) before any work
        ds = gb.simulate(harmonics=max(gb.analysis.orders), force=True if force else None)
    path = write_results(ds, target)
    if plot:
        save(plot_run(ds), path.with_suffix(".png"))
    s = gb.summary(ds)
    s["out"] = str(path)
    if json_:
        typer.echo(json.dumps(s, indent=2))
        return
    for key in ("meshes", "chain_meshes"):
        for m in s.get(key, []):
            err = (f", {100 * m['mean_error']:+.3f} %" if "mean_error" in m else "")
            if m.get("load_factor", 1.0) != 1.0:  # a load profile: its mean over the record
                err = f" x mean load factor {m['load_factor']:.4g}{err}"
            peak = f", peak {m['peak']:.6g} N" if "peak" in m else ""
            typer.echo(f"{'chain ' if key == 'chain_meshes' else ''}mesh {m['mesh']}: mean "
                       f"{m['mean']:.6g} N (static {m['static_force']:.6g} N{err}), RMS about "
                       f"the mean "
                       f"{m['rms']:.6g} N{peak}")
    if "sensor_rms" in s:
        typer.echo(f"sensor (ring, transfer-path window): RMS about the mean "
                   f"{s['sensor_rms']:.6g} N; f_m "
                   f"{s['mesh_frequency']:.6g} Hz")
    if s.get("modes"):
        top = max(m["frequency"] for m in s["modes"])
        groups = "Lin & Parker" in s.get("modes_of", "Lin & Parker")  # classified groups
        modes = ", ".join("0 (rigid body)" if m["frequency"] < 1e-6 * top else
                          f"{m['frequency']:.5g}" + (f" ({m['kind'][0]}{m['multiplicity']})"
                                                     if groups else "")
                          for m in s["modes"])
        legend = (" (r rotational, t translational, p planet, m mixed; multiplicity)"
                  if groups else "")
        what = ("natural frequencies of the stage's mean-stiffness Lin & Parker model"
                if groups else s["modes_of"])  # the result's long name, "natural ... of"
        typer.echo(f"{what} [Hz]{legend}: {modes}")
    for st in s.get("stages", []):  # stages in series: each stage's torques
        shaft = (f"; shaft {st['shaft']}: torque mean {st['shaft_torque_mean']:.6g} N m "
                 f"(static {st['static_shaft_torque']:.6g}), RMS about the mean "
                 f"{st['shaft_torque_rms']:.6g} N m" if "shaft" in st else "")
        typer.echo(f"{st['stage']}: f_m {st['mesh_frequency']:.6g} Hz, sun torque "
                   f"{st['sun_torque']:.6g} N m, carrier torque {st['carrier_torque']:.6g} "
                   f"N m{shaft}")
    if "shaft_torque_mean" in s:
        if "input_shaft_torque_mean" in s:
            typer.echo(f"input shaft ({s['input_member']}): torque mean "
                       f"{s['input_shaft_torque_mean']:.6g} N m, RMS about the mean "
                       f"{s['input_shaft_torque_rms']:.6g} N m")
        side = "output" if s["chain_side"] == "both" else s["chain_side"]
        typer.echo(f"{side} shaft ({s['shaft_member']}): torque mean "
                   f"{s['shaft_torque_mean']:.6g} N m, RMS about the mean "
                   f"{s['shaft_torque_rms']:.6g} N m")
    if s.get("constant_meshes"):
        typer.echo("note: constant mesh stiffnesses: no parametric excitation, the response "
                   "stays at the static load")
    typer.echo(f"gearsim: results written to {path}")


def register(app: typer.Typer) -> None:
    """Add ``simulate`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("simulate")(simulate)
