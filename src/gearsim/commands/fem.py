"""CLI verbs ``fe-check`` (FE versus PE tooth compliance) and ``fe-pair`` (FE gear pair)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from gearsim.commands._options import as_options, with_torque

__all__ = ["fe_check_command", "fe_pair_command", "register"]


def _gearbox(config: str, purpose: str):
    """The gearbox of ``config``, refused without a gear chain (beside a planetary stage:
    the gears driving it, then those it drives, :attr:`gearsim.model.Gearbox.chains`)."""
    from gearsim.errors import require
    from gearsim.model import load

    gb = load(config)
    require(bool(gb.chains), "config", config, f"has a planetary stage and no gear chain; "
            f"{purpose}")
    return gb


def _figure_file(name: str) -> bool:
    """A figure ``fe-check`` writes (the other ones are kept when the folder is replaced)."""
    return name.startswith("fe_check_") and name.endswith(".png")


def fe_check_command(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    gear: Annotated[str | None, typer.Option(help="gear to check (default: the cracked "
                                                  "gear, else the first)")] = None,
    crack: Annotated[str, typer.Option(help="none, working or non-working")] = "none",
    closure: Annotated[str | None, typer.Option(help="open or contact (default: "
                                                     "config)")] = None,
    level: Annotated[int, typer.Option(help="mesh level N: element size m_n/(4 2^N) on the "
                                            "loaded tooth")] = 2,
    points: Annotated[int, typer.Option(help="contact positions on the path (3 to 201)")]
    = 11,
    plot: Annotated[str | None, typer.Option(
        help="folder for the PNG figures (fe_check_*.png only; replaced as a whole, "
             "keeping the other fe_check_*.png)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON report")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="run even above the cost bound (5e5 FE unknowns); or set "
                        "GEARSIM_FORCE=1")] = False,
) -> None:
    """FE and potential-energy tooth compliance along the path of contact, with the
    max / min / mean differences (the seed's Figure 3) and the mesh level used.
    \f

    The first paragraph is the command help: Typer and Click cut the help at the form
    feed ``\\f`` above, and list the first paragraph; the rest documents the function
    (it calls :func:`gearsim.fem.check.fe_check`).

    Parameters
    ----------
    config : str
        TOML file or built-in example name.
    gear : str, optional
        Gear to check, of the external gears (beside a planetary stage, those driving or
        driven by it; a config without any is refused); default the first cracked gear,
        else the first gear.
    crack : str
        ``"none"``, ``"working"`` or ``"non-working"``; depth and angle from the
        config's crack on that gear.
    closure : str, optional
        ``"open"`` or ``"contact"``; default the config's ``stiffness.closure``.
    level : int
        FE mesh level N: element size m_n / (4 2^N) on the loaded tooth.
    points : int
        Contact positions along the path of contact (3 to
        :data:`gearsim.fem.check.MAX_POINTS`).
    plot : str, optional
        Folder for the PNG figure ``fe_check_<gear>_<crack>_<closure>.png``. Checked
        before any work; an existing folder may hold only ``fe_check_*.png`` figures,
        which are kept. The folder is written as a whole (temporary folder, then
        swapped in).
    json_ : bool
        Print the JSON report instead of the table (option ``--json``).
    force : bool
        Lift the cost bound (:data:`gearsim.fem.check.MAX_DOFS` estimated unknowns;
        option ``--force``, or ``GEARSIM_FORCE=1``).

    Raises
    ------
    InputError
        An unknown gear, crack or closure, too many points, a level whose mesh is
        estimated above the cost bound, a bad config or an unwritable ``--plot`` folder
        (exit status 2 in the CLI).
    """
    from gearsim.errors import InputError
    from gearsim.fem.check import fe_check
    from gearsim.io.targets import atomic_folder, check_output_folder
    from gearsim.viz import save

    folder = None
    if plot is not None:  # every output target is checked before any work
        folder = check_output_folder(plot, "--plot", owned=_figure_file)
    chains = _gearbox(config, "fe-check takes a gear of external gears").chains
    names = [g.name for t in chains for g in t.gears]
    if gear is not None and gear not in names:
        raise InputError("--gear", gear, f"must be one of the external gears {names}")
    train = next((t for t in chains if gear in [g.name for g in t.gears]
                  or gear is None and t.cracks), chains[0])
    with as_options({"fem.level": "--level", "points": "--points"}):
        result = fe_check(train, gear, crack=crack, closure=closure, level=level,
                          points=points, force=True if force else None)
    if folder is not None:
        name = f"fe_check_{result.gear.name}_{result.crack}_{result.closure}.png"
        with atomic_folder(folder, keep=_figure_file) as tmp:
            save(result.plot(), Path(tmp) / name, parameter="--plot")
    if json_:
        typer.echo(json.dumps(result.to_dict(), indent=2))
        return
    r = result.fe_result
    b = result.gear.face_width
    typer.echo(f"gear {result.gear.name}: crack {result.crack}, closure {result.closure}, "
               f"plane {result.plane}; FE mesh level {r.level} (element size "
               f"{r.h * 1e3:.4g} mm, {r.elements} P2 triangles, {r.dofs} dofs)")
    typer.echo(f"{'radius mm':>10} {'roll deg':>9} {'k_FE GN/m':>10} {'k_PE GN/m':>10} "
               f"{'PE/FE':>7}")
    for i in range(result.radii.size):
        kf, kp = result.k_fe[i] * b, result.k_pe[i] * b
        typer.echo(f"{result.radii[i] * 1e3:10.4f} {result.roll_angle[i] * 57.29578:9.3f} "
                   f"{kf / 1e9:10.4f} {kp / 1e9:10.4f} {kp / kf:7.4f}")
    d = result.differences()
    typer.echo(f"difference (k_PE - k_FE)/k_FE: max {d['max']:+.2f} %, min {d['min']:+.2f} %, "
               f"mean {d['mean']:+.2f} % (seed Fig. 3b: 6.7 / 5.6 / 6.3 %)")


def _positions(text: str) -> list[float]:
    """``N`` (N positions u = (i + 1/2) / N) or a comma list of mesh-cycle fractions."""
    from gearsim.errors import InputError

    text = text.strip()
    try:
        n = int(text) if "," not in text and "." not in text else None
        values = [float(v) for v in text.split(",") if v.strip()] if n is None else []
    except ValueError:
        raise InputError("--positions", text, "must be a count or a comma list of mesh-cycle "
                         "fractions in [0, 1)") from None
    if n is not None:  # outside the try: an InputError is a ValueError too
        if not 1 <= n <= 200:
            raise InputError("--positions", text, "a count must be in [1, 200]")
        return [(i + 0.5) / n for i in range(n)]
    if not values or len(values) > 200:
        raise InputError("--positions", text, "must give 1 to 200 positions")
    for v in values:
        if not (math.isfinite(v) and 0.0 <= v < 1.0):
            raise InputError("--positions", v, "a position must be a mesh-cycle fraction "
                             "in [0, 1)")
    return values


def fe_pair_command(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    mesh: Annotated[int, typer.Option(help="mesh index (0 = mesh I), as gearsim layout "
                                           "names the meshes")] = 0,
    positions: Annotated[str, typer.Option(
        help="N positions u = (i + 1/2)/N, or a comma list of mesh-cycle fractions in [0, 1)")]
    = "8",
    torque: Annotated[str | None, typer.Option(
        help="input torque, e.g. '2000 N*m' (default the configuration's)")] = None,
    level: Annotated[int, typer.Option(help="mesh level N: element size m_n/(4 2^N) on the "
                                            "teeth, 8 times finer on the flanks")] = 2,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON report")] = False,
) -> None:
    """FE gear pair in contact on the transverse section of one mesh: loaded
    transmission error, mesh stiffness, load sharing, contact widths and root stresses at
    mesh positions, beside the potential-energy mesh stiffness (seed Figure 3a).
    \f

    Both gears whole, hubs rigid, frictionless contact solved exactly
    (:class:`gearsim.fem.pair.FEPairModel`; docs/fem.md, "Gear pair in contact"). The
    PE curves are those of :func:`gearsim.studies.fe_pair_check.section_tvms`: the
    seed's options and the FE tooth with the 2D line contact and body coupling.

    Parameters
    ----------
    config : str
        TOML file or built-in example name (its cracks are ignored: healthy gears).
    mesh : int
        Mesh index of the external gears as ``gearsim layout`` names them (beside a
        planetary stage the gears driving it first, :meth:`gearsim.model.Gearbox.gear_mesh`).
    positions : str
        A count N or a comma list of mesh-cycle fractions in [0, 1).
    torque : str, optional
        Input torque with its unit; default the configuration's.
    level : int
        FE mesh level.
    json_ : bool
        Print the JSON report (option ``--json``).

    Raises
    ------
    InputError
        A mesh index, position, torque or level out of range, or a mesh too coarse for
        the contact (exit status 2 in the CLI), before the FE model is built.
    """
    import dataclasses

    import numpy as np

    from gearsim.fem.pair import FEPairModel
    from gearsim.stiffness.settings import MODELS
    from gearsim.studies.fe_pair_check import section_tvms

    u = _positions(positions)
    gb = with_torque(_gearbox(config, "fe-pair takes a mesh of external gears"), torque)
    train, mesh, mesh_name = gb.gear_mesh(mesh, "--mesh")
    train = train.with_cracks(())
    pair, own = train.pairs[mesh], train.settings_of(mesh)
    with as_options({"fem.level": "--level", "level": "--level", "torque": "--torque"}):
        model = FEPairModel(pair, torque=train.mesh_torque(mesh), level=level,
                            plane=own.plane)
    results = [model.solve(v) for v in u]
    seed = dataclasses.replace(own, **MODELS["seed"])
    curves = {}
    for name, st in (("pe", seed), ("fe_tooth_line_coupling", dataclasses.replace(
            seed, source="fe", contact="line", coupling="fe")),
                     ("config", own)):
        x, k = section_tvms(train, mesh, st, 400)
        curves[name] = np.interp(u, x, k, period=float(pair.driver.teeth))
    rows = []
    for i, r in enumerate(results):
        rows.append({
            "position": u[i], "stiffness_N_per_m": r.stiffness,
            "transmission_error_m": r.transmission_error,
            "pair_teeth": [int(k) for k in r.pair_teeth],
            "load_share": [float(v) for v in r.load_share],
            "contact_half_width_m": [float(v) for v in r.contact_half_width],
            "root_stress_driver_Pa": [float(v) for v in r.root_stress_driver],
            "root_stress_driven_Pa": [float(v) for v in r.root_stress_driven],
            **{f"k_{c}_N_per_m": float(v[i]) for c, v in curves.items()}})
    if json_:
        typer.echo(json.dumps({"mesh": mesh_name, "torque_N_m": train.mesh_torque(mesh),
                               "level": model.level, "h_contact_m": model.h_contact,
                               "positions": rows}, indent=2))
        return
    typer.echo(f"mesh {mesh_name} ({pair.driver.name} -> {pair.driven.name}), transverse "
               f"section; driver torque {train.mesh_torque(mesh):.6g} N m; FE level {model.level} "
               f"(contact elements {model.h_contact * 1e6:.3g} um)")
    typer.echo(f"{'u':>6} {'k_FE GN/m':>10} {'TE um':>8} {'shares':>14} {'b um':>12} "
               f"{'root MPa':>9} {'PE/FE':>6} {'FE+line/FE':>10} {'model/FE':>8}")
    for row in rows:
        k = row["stiffness_N_per_m"]
        shares = "/".join(f"{v:.2f}" for v in row["load_share"])
        widths = "/".join(f"{v * 1e6:.0f}" for v in row["contact_half_width_m"])
        root = max(row["root_stress_driver_Pa"] + [0.0]) / 1e6
        typer.echo(f"{row['position']:6.3f} {k / 1e9:10.4f} "
                   f"{row['transmission_error_m'] * 1e6:8.3f} {shares:>14} {widths:>12} "
                   f"{root:9.1f} {row['k_pe_N_per_m'] / k:6.3f} "
                   f"{row['k_fe_tooth_line_coupling_N_per_m'] / k:10.3f} "
                   f"{row['k_config_N_per_m'] / k:8.3f}")
    typer.echo("PE: the seed's method; FE+line: FE tooth, line contact, body coupling; "
               f"model: the configuration's stiffness ({own.source}, "
               f"{own.contact}, {own.coupling})")


def register(app: typer.Typer) -> None:
    """Add ``fe-check`` and ``fe-pair`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`); :func:`fe_check_command` and
        :func:`fe_pair_command` are registered as ``fe-check`` and ``fe-pair``.
    """
    app.command("fe-check")(fe_check_command)
    app.command("fe-pair")(fe_pair_command)
