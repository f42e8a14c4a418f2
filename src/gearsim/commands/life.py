"""CLI verb ``life``: crack growth life of a gear and a run-to-failure NetCDF store.

Everything the user gives is checked before any work, each refusal one line (exit 2):
the output targets, the fractions (numbers in [0, 1]), the seeds (>= 1), the Paris
constants (:class:`gearsim.fracture.paris.ParisLaw` ranges), the increment, the torque,
the records' loads and speeds (the model's operating bounds and the simulation's checks
at each speed), the workers and the scheduler (its address, and that it answers) and a
gear without a crack. A load that never reaches the threshold is an answer: ``end: no
growth`` with its dK and the threshold, exit 0, and no store is written.

The crack grows at the config's operating point (``--torque``): that one life is the
crack's history. The records are simulated at each of its crack states at every
``--loads`` x ``--speeds`` (default: that operating point), on Dask with ``--workers``
> 1 or ``--scheduler`` (more workers than simulations: refused; than CPU cores: reduced,
with a note, as ``gearsim sweep``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from typing import Annotated

import typer

from gearsim.commands._options import as_options, with_torque
from gearsim.errors import InputError, require

__all__ = ["register"]

DEFAULT_FRACTIONS = "0,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9"


def _fractions(text: str) -> list[float]:
    parts = [p.strip() for p in text.split(",")]
    try:
        vals = [float(p) for p in parts]
    except ValueError:
        raise InputError("--fractions", text, "must be comma-separated numbers in [0, 1]"
                         ) from None
    if not vals or not all(math.isfinite(v) and 0.0 <= v <= 1.0 for v in vals):
        raise InputError("--fractions", text, "must be comma-separated numbers in [0, 1]")
    if len(set(vals)) != len(vals):
        raise InputError("--fractions", text, "must not repeat a fraction")
    return sorted(vals)


def _quantities(text: str, kind: str, option: str) -> list[tuple[str, float]]:
    """Comma-separated quantities, a unit after the last applying to the bare numbers
    before it (``"100,200 N*m"``, ``"1500,1900 rpm"``): (item as read, SI value)."""
    from gearsim.commands._options import MIN_TORQUE
    from gearsim.units import to_si

    parts = [p.strip() for p in text.split(",")]
    if not all(parts):
        raise InputError(option, text, "must list values without empty items, e.g. "
                         + ("'2000,4000 N*m'" if kind == "torque" else "'1500,1900 rpm'"))

    def bare(p: str) -> bool:
        try:
            float(p)
        except ValueError:
            return False
        return True

    m = re.fullmatch(r"[+-]?(?:\d+\.?\d*(?:e[+-]?\d+)?|\.\d+(?:e[+-]?\d+)?|inf(?:inity)?|nan)"
                     r"\s*(.*)", parts[-1], flags=re.IGNORECASE)
    unit = m.group(1).strip() if m is not None else ""
    out = []
    for p in parts:
        if bare(p) and not unit:  # to_si's hint of a bare TOML number does not hold here
            raise InputError(option, text, f"{p}: give a unit after the last value, e.g. "
                             f"'{text} {'N*m' if kind == 'torque' else 'rpm'}'")
        item = f"{p} {unit}" if bare(p) and unit else p
        try:
            v = to_si(item, kind, option)
        except InputError as exc:
            raise InputError(option, text, f"{item}: {exc.limit}") from None
        if kind == "torque" and 0 < v < MIN_TORQUE:
            raise InputError(option, text, f"{item}: must be >= {MIN_TORQUE:g} N*m (a smaller "
                             "torque can only be a slip of unit or exponent)")
        out.append((item, v))
    return out


def _conditions(gb, loads: str | None, speeds: str | None, duration: float | None):
    """The records' loads [N m] and speeds [rad/s] of ``--loads``/``--speeds``, checked
    item by item (:func:`gearsim.studies.life.operating_conditions`), and ``--duration``
    against the records at every speed (default the config's)."""
    from gearsim.studies.life import operating_conditions

    out = []
    for option, text, kind, name in (("--loads", loads, "torque", "loads"),
                                     ("--speeds", speeds, "speed", "speeds")):
        if text is None:
            out.append(None)
            continue
        items = _quantities(text, kind, option)
        for item, v in items:
            try:
                operating_conditions(gb, **{name: [v]}, duration=duration)
            except InputError as exc:
                if exc.parameter == "duration":
                    raise InputError("--duration", duration, f"{exc.limit} at {item}") from None
                raise InputError(option, text, f"{item}: {exc.limit}") from None
        vals = [v for _, v in items]
        if len(set(vals)) != len(vals):
            raise InputError(option, text, "must not repeat a value")
        out.append(vals)
    if speeds is None:  # the records at the config's speed
        with as_options({"duration": "--duration"}):
            operating_conditions(gb, duration=duration)
    return out[0], out[1]


def life(
    config: Annotated[str, typer.Argument(help="TOML file or built-in example name")],
    out: Annotated[str, typer.Option(help="run-to-failure store (NetCDF, .nc)")] = "life.nc",
    gear: Annotated[str | None, typer.Option(
        help="cracked gear (default: the gear of the first crack)")] = None,
    fractions: Annotated[str, typer.Option(
        help="life fractions of the records, comma-separated, in [0, 1]")] = DEFAULT_FRACTIONS,
    seeds: Annotated[int, typer.Option(help="noise seeds per fraction (>= 1)")] = 10,
    torque: Annotated[str | None, typer.Option(
        help="input torque with unit, e.g. '19504 N*m' (default: the config's)")] = None,
    increment: Annotated[float | None, typer.Option(
        help="crack increment in mm (default m_n / 12; from m_n / 1000 to half the distance "
             "from the initial crack's tip to the outline ahead)")] = None,
    steps: Annotated[int, typer.Option(help="largest number of increments (1 to 500)")] = 20,
    steel: Annotated[str, typer.Option(
        help="Paris C, m of a steel class: martensitic, ferrite-pearlite, austenitic "
             "(Barsom & Rolfe 1999)")] = "martensitic",
    threshold: Annotated[float, typer.Option(
        help="dK_th in MPa sqrt(m) (default 6.0, Barsom & Rolfe, R < 0.1)")] = 6.0,
    toughness: Annotated[float, typer.Option(
        help="K_IC in MPa sqrt(m) (default 80, an assumed value: give the grade's)")] = 80.0,
    noise: Annotated[float, typer.Option(
        help="noise RMS / record standard deviation (0 to 100; 0.1 = SNR 20 dB)")] = 0.1,
    duration: Annotated[float | None, typer.Option(
        help="record duration in s (default 4.2 revolutions of the slowest shaft)")] = None,
    loads: Annotated[str | None, typer.Option(
        help="input torques of the records, comma-separated, a unit after the last, e.g. "
             "'10000,19504 N*m' (default: the life's torque); the crack grows at the "
             "life's")] = None,
    speeds: Annotated[str | None, typer.Option(
        help="input shaft speeds of the records, e.g. '1500,1900 rpm' (default: the "
             "config's)")] = None,
    workers: Annotated[int, typer.Option(
        help="local Dask worker processes for the records' simulations (1 thread each; "
             "more than the simulations refused, more than the CPU cores reduced; 1: in "
             "this process)")] = 1,
    scheduler: Annotated[str | None, typer.Option(
        help="address of a running Dask scheduler for the records' simulations, e.g. "
             "tcp://host:8786")] = None,
    plot: Annotated[str | None, typer.Option(
        help="figure of the indicators over the life and their alarm fractions (.png)")] = None,
    json_: Annotated[bool, typer.Option("--json", help="print a JSON summary")] = False,
) -> None:
    """Grow the gear's crack to the end of life; write records at life fractions."""
    from gearsim.fracture.paris import (
        MPA_SQRT_M,
        STEEL_CLASSES,
        THRESHOLD_RANGE,
        TOUGHNESS_RANGE,
        steel_class_law,
    )
    from gearsim.io.targets import check_output_file
    from gearsim.model import load
    from gearsim.studies import life as lf
    from gearsim.studies.sweep_run import (
        check_scheduler,
        check_workers,
        cluster_client,
        plan_workers,
    )
    from gearsim.viz import check_plot_file

    # every input is checked before any work
    target = check_output_file(out, "--out", (".nc",))
    if plot is not None:
        check_plot_file(plot, "--plot")
    fr = _fractions(fractions)
    require(seeds >= 1, "--seeds", seeds, "must be an integer >= 1")
    require(1 <= steps <= 500, "--steps", steps, "must be an integer in [1, 500]")
    require(math.isfinite(noise) and 0.0 <= noise <= lf.MAX_NOISE, "--noise", noise,
            f"must be in [0, {lf.MAX_NOISE:g}] (noise RMS / record standard deviation; "
            f"{lf.MAX_NOISE:g}: SNR {-20 * math.log10(lf.MAX_NOISE):g} dB, past which every "
            "record is its noise)")
    require(duration is None or (math.isfinite(duration) and duration > 0.0), "--duration",
            duration, "must be > 0 s")
    plan_workers(workers, 1)  # --workers: an integer >= 1
    if scheduler is not None:
        scheduler = check_scheduler(scheduler)
    require(steel in STEEL_CLASSES, "--steel", steel, f"must be one of {', '.join(STEEL_CLASSES)}")
    for name, value, (lo, hi) in (("--threshold", threshold, THRESHOLD_RANGE),
                                  ("--toughness", toughness, TOUGHNESS_RANGE)):
        require(math.isfinite(value) and lo / MPA_SQRT_M <= value <= hi / MPA_SQRT_M, name,
                value, f"must be in [{lo / MPA_SQRT_M:g}, {hi / MPA_SQRT_M:g}] MPa sqrt(m)")
    require(toughness > threshold, "--toughness", toughness,
            f"must exceed the threshold {threshold:g} MPa sqrt(m)")
    law = steel_class_law(steel, threshold=threshold * MPA_SQRT_M,
                          toughness=toughness * MPA_SQRT_M)
    gb = load(config)
    gb = dataclasses.replace(gb, train=with_torque(gb.gears_only("config", config,
                                                                 "crack growth"), torque))
    with as_options({"gear": "--gear"}):
        lf._crack_of(gb, gear)  # a gear without a crack: refused here, before the FE
        lo, hi = lf.increment_range(gb, gear)
    require(increment is None or (math.isfinite(increment)
                                  and lo * 1e3 <= increment <= hi * 1e3), "--increment",
            increment, f"must be in [{lo * 1e3:.4g}, {hi * 1e3:.4g}] mm: at least m_n / "
            f"{1 / lf.MIN_INCREMENT:.0f} (the FE's tip elements, da / 75, against its m_n / 4 "
            "elements) and at most half the distance from the initial crack's tip to the "
            "outline ahead of it")
    record_loads, record_speeds = _conditions(gb, loads, speeds, duration)
    # the records' simulations: each fraction (and the broken tooth after a fracture) at
    # each load and speed; more workers than that would have nothing to do
    check_workers(workers, (len(fr) + 1) * len(record_loads or [0])
                  * len(record_speeds or [0]), "simulation")
    if scheduler is not None:  # a scheduler that does not answer: refused before the FE
        with cluster_client(1, scheduler):
            pass
    da = None if increment is None else increment * 1e-3
    with as_options({"crack.increment": "--increment", "increment": "--increment"}):
        res = lf.gear_life(gb, gear, increment=da, steps=steps, law=law)
    summary = res.to_dict()
    if not math.isfinite(res.cycles_end):
        dk = float(res.path.keq[0]) * res.dynamic_load_factor / MPA_SQRT_M
        summary["store"] = None
        if json_:
            typer.echo(json.dumps(summary, indent=2))
            return
        a0, th = res.path.lengths[0] * 1e3, law.threshold / MPA_SQRT_M
        if res.end == "arrest":  # dK fell to the threshold along the path
            typer.echo(f"end: arrest: dK falls from {dk:.4g} MPa sqrt(m) at the initial "
                       f"crack ({a0:.4g} mm) to the threshold {th:.4g} MPa sqrt(m) at "
                       f"{res.life.a_end * 1e3:.4g} mm (DLF {res.dynamic_load_factor:.4f}); "
                       "the crack stops growing, no store written")
            return
        typer.echo(f"end: {res.end}: dK = {dk:.4g} MPa sqrt(m) at the initial crack "
                   f"({a0:.4g} mm) is below the threshold {th:.4g} MPa sqrt(m) (DLF "
                   f"{res.dynamic_load_factor:.4f}); the crack does not grow, no store written")
        return
    ds = lf.life_records(gb, res, fr, seeds, duration=duration, noise=noise,
                         loads=record_loads, speeds=record_speeds, workers=workers,
                         scheduler=scheduler, note=lambda line: typer.echo(line, err=True))
    path = lf.write_store(ds, target)
    # the alarms at the life's operating point if recorded, else at the first condition
    own_speed, own_torque = gb.operating()
    lv, sv = ds["load"].values, ds["speed"].values
    at_load = (own_torque if any(math.isclose(x, own_torque, rel_tol=1e-9) for x in lv)
               else float(lv[0]))
    at_speed = (own_speed if any(math.isclose(x, own_speed, rel_tol=1e-9) for x in sv)
                else float(sv[0]))
    cross = lf.alarm_fractions(ds, load=at_load, speed=at_speed)
    summary["store"] = str(path)
    summary["loads_n_m"] = lv.tolist()
    summary["speeds_rad_s"] = sv.tolist()
    summary["alarm_condition"] = {"load_n_m": at_load, "speed_rad_s": at_speed}
    summary["alarm_fractions"] = cross
    if lv.size * sv.size > 1:
        summary["alarm_fractions_by_condition"] = [
            {"load_n_m": float(t), "speed_rad_s": float(w),
             "alarm_fractions": lf.alarm_fractions(ds, load=float(t), speed=float(w))}
            for t in lv for w in sv]
    summary["alarm_levels"] = {k: {"level": v[0], "source": v[1]}
                               for k, v in lf.ALARM_LEVELS.items()}
    if plot is not None:
        from gearsim.viz import save
        from gearsim.viz.life import plot_life_alarms

        trends = lf.indicator_trends(ds, load=at_load, speed=at_speed)
        levels = {n: lf.ALARM_LEVELS[n][0] * (trends[n][0] if n == "sideband_energy" else 1)
                  for n in trends}
        save(plot_life_alarms(ds["fraction"].values, trends, levels, cross,
                              title=f"{gb.name}: {res.gear}, end {res.end}"), plot)
        summary["plot"] = plot
    if json_:
        typer.echo(json.dumps(summary, indent=2))
        return
    typer.echo(f"gear {res.gear}: crack {res.path.lengths[0] * 1e3:.4g} mm -> "
               f"{res.life.a_end * 1e3:.4g} mm along the path, end: {res.end}")
    typer.echo(f"life {res.cycles_end:.6g} cycles = {res.hours_end:.6g} h at "
               f"{res.shaft_frequency:.6g} Hz; static {res.static_force:.6g} N/m, DLF "
               f"{res.dynamic_load_factor:.4f}; {res.path.lengths.size} increments, "
               f"{float(res.path.seconds_per_step.mean()):.3g} s FE each")
    typer.echo(f"alarm fractions at {at_load:.6g} N*m, {at_speed * 30 / math.pi:.6g} rpm: "
               + ", ".join(
        f"{k} {'not crossed' if v is None else f'{v:.3g}'}" for k, v in cross.items()))
    n_broken = int(ds["broken"].sum())
    tail = ", the last the broken tooth" if n_broken else ""
    typer.echo(f"gearsim: store written to {path} ({ds.sizes['fraction']} records x "
               f"{ds.sizes['load']} loads x {ds.sizes['speed']} speeds x "
               f"{ds.sizes['seed']} seeds{tail})")


def register(app: typer.Typer) -> None:
    """Add ``life`` to ``app``.

    Parameters
    ----------
    app : typer.Typer
        The ``gearsim`` application (:mod:`gearsim.cli`).
    """
    app.command("life")(life)
