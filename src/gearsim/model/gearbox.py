"""The typed model of a gearbox: its parts and the settings of everything done with it.

:func:`gearsim.load` returns a :class:`Gearbox`, whatever the file describes: a chain of
gears, a graph of shafts, gears and meshes (:class:`~gearsim.system.GearTrain`), a
planetary stage (:class:`~gearsim.system.planetary.PlanetaryTrain`) or a stage driving
such a graph, with the ``[dynamics]`` and ``[analysis]`` settings, each a frozen,
validated dataclass. Variants are made with :meth:`Gearbox.with_crack` and
:meth:`Gearbox.replace`, which check the new value once, where it is made.

Everything done with a gearbox goes through its methods (:meth:`Gearbox.simulate`,
:meth:`Gearbox.tvms`, :meth:`Gearbox.layout`, :meth:`Gearbox.summary`, and for studies
:meth:`Gearbox.at`, :meth:`Gearbox.signals`, :meth:`Gearbox.select`,
:meth:`Gearbox.reference`): the callers above this layer never ask which parts a
gearbox has.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gearsim.dynamics.compose import (
    NextStage,
    chain_of_record,
    chain_operating,
    next_operating,
    output_member,
    stage_of_label,
    stage_operating,
    stage_prefix,
    stage_shaft_names,
)
from gearsim.dynamics.lta import AXES as LTA_AXES
from gearsim.dynamics.lta import dof_map
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.stage import StageDynamics, chain_record_paths, check_stage_settings
from gearsim.errors import InputError, require
from gearsim.model.graph_toml import stages_to_toml
from gearsim.sections import written_name
from gearsim.signals.settings import AnalysisSettings
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.planetary import PlanetaryTrain, StageOperating, planet_name
from gearsim.system.toml import train_to_toml
from gearsim.system.train import GearTrain, Operating

__all__ = ["Gearbox", "GearboxStiffness"]

_BEARING_MEMBERS = ("sun", "planet", "ring", "carrier")
#: A record's name: ``variable`` or ``variable[label]`` / ``variable[label,axis]``; a
#: label is any name a configuration may give (letters, digits, ``_ - . :`` and inner
#: spaces: a shaft ``"in shaft"``, a spring ``m:c-d``).
_SIGNAL = re.compile(r"\s*(\w+)\s*(?:\[\s*([\w.:-]+(?: +[\w.:-]+)*)\s*(?:,\s*(\w+)\s*)?\])?\s*")


@dataclass(frozen=True)
class GearboxStiffness:
    """The stiffness tables of every mesh of a gearbox (:meth:`Gearbox.tvms`).

    Parameters
    ----------
    summary : dict
        ``name`` and ``meshes`` (per mesh ``k_mean``, ``k_min``, ``k_max`` [N/m] and the
        mesh's own quantities), with a stage also its phasing and contact ratios.
    write : callable
        ``write(path)``: the tables to ``.csv`` or ``.nc``, atomically.
    figure : callable
        ``figure()``: a matplotlib figure of the tables.
    """

    summary: dict
    write: Callable[[str | Path], Any]
    figure: Callable[[], Any]


@dataclass(frozen=True)
class Gearbox:
    """A gearbox and the settings of everything done with it.

    Parameters
    ----------
    train : GearTrain or None
        The parallel-shaft part: shafts, gears, meshes, operating point, stiffness
        options and faults; with a stage, the part its output shaft drives (at the
        output's speed and torque); ``None``: a stage alone.
    dynamics : DynamicsSettings
        Options of the vibration simulation (``[dynamics]``).
    analysis : AnalysisSettings
        Options of the signal analysis (``[analysis]``).
    stage : PlanetaryTrain, optional
        A planetary stage (``[stage]``), the input of the gearbox.
    members : StageDynamics, optional
        The stage's member masses, inertias, bearings and ring sensor (``[members]``).
    shaft_stiffness : float, optional
        Torsional stiffness [N m/rad] of the shaft between the stage and ``train``
        (``None``: :func:`gearsim.dynamics.compose.build_stage_chain_model`'s default).
    input_train : GearTrain, optional
        Gears driving the stage's input member (``[input_chain]``: a parallel input
        stage ahead of a planetary stage); the gearbox's input is then their first
        shaft, and ``train`` (if any) the gears the stage drives.
    input_shaft_stiffness : float, optional
        Torsional stiffness [N m/rad] of the shaft from ``input_train`` to the stage
        (``None``: the default of :func:`~gearsim.dynamics.compose.build_stage_chain_model`).
    next_stages : tuple of NextStage, optional
        Planetary stages in series after ``stage`` (``[[stages]]``), each driven by the
        previous one's output member through its shaft, or through gears between the two
        (its ``input_train``); ``train`` is then driven by the last.
    member_shafts : tuple of (str, str), optional
        The named shaft each turning stage member sits on, ``(member, shaft)`` with the
        member as the results name it (``"carrier"``, ``"stage2-sun"``): a gearbox
        written as a graph (:mod:`gearsim.model.graph_form`). Its tachos and reference
        shafts then take the shaft's name (one tacho a shaft).
    written : tuple of (str, str), optional
        The graph form's parameter names of the translated ones (prefix pairs,
        :func:`gearsim.sections.written_name`), so that a refusal at run time (a
        shaft twisted by its static torque) names the key as written; not compared.

    Examples
    --------
    >>> import gearsim as gs
    >>> gb = gs.example("idler-table1")
    >>> [g.teeth for g in gb.train.gears], gb.dynamics.model, gb.stiffness.closure
    ([39, 59, 125], 'lta', 'contact')
    >>> round(gb.train.mesh_frequency, 3)
    1235.0
    >>> box = gs.example("wind-turbine-grc")
    >>> box.stage.stage.ring_teeth, [g.teeth for g in box.train.gears]
    (99, [82, 23, 88, 22])
    """

    train: GearTrain | None
    dynamics: DynamicsSettings = field(default_factory=DynamicsSettings)
    analysis: AnalysisSettings = field(default_factory=AnalysisSettings)
    stage: PlanetaryTrain | None = None
    members: StageDynamics = field(default_factory=StageDynamics)
    shaft_stiffness: float | None = None
    input_train: GearTrain | None = None
    input_shaft_stiffness: float | None = None
    next_stages: tuple[NextStage, ...] = ()
    member_shafts: tuple[tuple[str, str], ...] = ()
    written: tuple[tuple[str, str], ...] = field(default=(), compare=False, repr=False)

    def __post_init__(self) -> None:
        require(self.train is not None or self.stage is not None, "gearbox", "empty",
                "needs gears ([[gears]]) or a planetary stage ([stage])")
        require(self.input_train is None or self.stage is not None, "input_chain",
                "given", "gears driving a stage need the stage ([stage])")
        require(not self.next_stages or self.stage is not None, "stages", "given",
                "stages in series need the first stage")
        if self.stage is not None:  # what a stage does not model, refused where it is read
            check_stage_settings(self.dynamics, gears=bool(self.chains))

    @property
    def stages(self) -> tuple[PlanetaryTrain, ...]:
        """The planetary stages in power-flow order (none for gears alone)."""
        return (() if self.stage is None
                else (self.stage, *(s.train for s in self.next_stages)))

    @property
    def chains(self) -> tuple[GearTrain, ...]:
        """The gear trains beside the stages in power-flow order (the gears driving the
        first, those between two stages, those the last drives); the gears alone without
        a stage."""
        return tuple(t for t in (self.input_train, *self._between(), self.train)
                     if t is not None)

    def _between(self) -> tuple[GearTrain | None, ...]:
        """The gears driving each stage after the first (None: its shaft alone)."""
        return tuple(s.input_train for s in self.next_stages)

    def _in_flow(self, chains: list, stages: list) -> list:
        """``chains`` (one item per chain of :attr:`chains`) and ``stages`` (one per
        stage) interleaved in power-flow order."""
        c, s = iter(chains), iter(stages)
        out = [next(c)] if self.input_train is not None else []
        for t in (None, *self._between())[:len(self.stages)]:
            out += ([] if t is None else [next(c)]) + [next(s)]
        return out + list(c)

    @property
    def name(self) -> str:
        """Name of the gearbox (the stage's when it has one)."""
        return (self.stage or self.train).name

    @property
    def cracks(self) -> tuple:
        """The cracks of the input part (the stage's when there is one)."""
        return (self.stage or self.train).cracks

    @property
    def stiffness(self) -> StiffnessSettings:
        """Options of the mesh-stiffness computation (of the input part)."""
        return self.stage.settings if self.stage is not None else self.train.stiffness

    def gears_only(self, parameter: str, value: Any, purpose: str) -> GearTrain:
        """The gear train of a gearbox without a planetary stage, for work that models
        external gear meshes only (the seed's study, crack growth).

        Parameters
        ----------
        parameter, value
            Named in the refusal (e.g. ``"config"`` and the file as written).
        purpose
            What needs the gears, e.g. ``"the seed's study"``.

        Returns
        -------
        GearTrain

        Raises
        ------
        InputError
            For a gearbox with a planetary stage.
        """
        require(self.stage is None and self.train is not None, parameter, value,
                f"has a planetary stage; {purpose} needs a gearbox of external gears")
        return self.train

    def _parts(self, stage: PlanetaryTrain | None, train: GearTrain | None,
               input_train: GearTrain | None = None) -> Gearbox:
        return dataclasses.replace(self, stage=stage, train=train, input_train=input_train)

    def with_crack(self, flank: str | None, *, depth: float | None = None,
                   closure: str | None = None, source: str | None = None) -> Gearbox:
        """The fault variant: see :meth:`gearsim.system.GearTrain.with_crack`.

        Parameters
        ----------
        flank : {"none", "working", "non-working"} or None
            No crack, the cracks (or the default crack) on that flank, or as configured.
            With stages, every configured crack, on a stage member or a gear beside a
            stage, is moved (a gearbox with stages and no crack refuses a flank: the
            member or gear and the tooth are not known); ``"none"`` removes every crack
            of the gearbox.
        depth : float, optional
            Crack depth [m] of every crack.
        closure : {"contact", "open"}, optional
            Crack-face model.
        source : {"pe", "fe"}, optional
            Tooth-compliance model.

        Returns
        -------
        Gearbox
        """
        if self.stage is None:
            return self._parts(None, self.train.with_crack(flank, depth=depth,
                                                           closure=closure, source=source))
        require(source is None, "source", source, "a planetary stage's tooth compliance "
                "is set in its [stiffness] section")
        if flank not in (None, "none"):
            require(any(p.cracks for p in (*self.stages, *self.chains)), "crack", flank,
                    "the gearbox has no crack to vary: give the cracked member or gear, its "
                    "tooth and flank ([[stages.cracks]] or [[cracks]] of a graph; [[cracks]] "
                    "of a [stage] file)")
        gb = self._with_stages(tuple(_stage_crack(st, flank, depth, closure)
                                     for st in self.stages))
        return gb._with_chains(tuple(  # gears without a crack get none
            t.with_crack(flank if t.cracks or flank == "none" else None, depth=depth,
                         closure=closure) for t in self.chains))

    def _with_stages(self, stages: tuple[PlanetaryTrain, ...]) -> Gearbox:
        """The gearbox with its stages (the first, then those in series) replaced."""
        return dataclasses.replace(self, stage=stages[0], next_stages=tuple(
            dataclasses.replace(s, train=t)
            for s, t in zip(self.next_stages, stages[1:], strict=True)))

    def healthy(self) -> Gearbox:
        """The gearbox without cracks and faults (on every stage and chain).

        Returns
        -------
        Gearbox
        """
        gb = self if self.stage is None else self._with_stages(tuple(
            dataclasses.replace(st, cracks=(), faults=()) for st in self.stages))
        return gb._with_chains(tuple(t.with_crack("none").with_faults(()) for t in gb.chains))

    def replace(self, *, dynamics: dict[str, Any] | None = None,
                analysis: dict[str, Any] | None = None,
                stiffness: dict[str, Any] | None = None) -> Gearbox:
        """A copy with some settings changed (SI values; each checked where it is made).

        Parameters
        ----------
        dynamics, analysis, stiffness : dict, optional
            Field name -> new value of :class:`DynamicsSettings`,
            :class:`AnalysisSettings`, :class:`StiffnessSettings` (of every part).

        Returns
        -------
        Gearbox

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("spur-19-48").replace(dynamics={"duration": 0.5}).dynamics.duration
        0.5
        """
        gb = self
        if dynamics:
            # (a stage's refusals: __post_init__, check_stage_settings)
            gb = dataclasses.replace(gb, dynamics=dataclasses.replace(gb.dynamics, **dynamics))
        if analysis:
            gb = dataclasses.replace(gb, analysis=dataclasses.replace(gb.analysis, **analysis))
        if stiffness:
            if gb.stage is not None:
                gb = gb._with_stages(tuple(dataclasses.replace(
                    st, settings=dataclasses.replace(st.settings, **stiffness))
                    for st in gb.stages))
            gb = gb._with_chains(tuple(t.with_stiffness(**stiffness) for t in gb.chains))
        return gb

    def mesh_stiffness(self, mesh: int = 0, *, revolution_of: int = 1):
        """TVMS of mesh ``mesh`` of the gears over one revolution of its gear 1 or 2.

        Parameters
        ----------
        mesh : int, optional
            Mesh index (0 = mesh I).
        revolution_of : {1, 2}, optional
            Over one revolution of the driver (1) or of the driven gear (2).

        Returns
        -------
        xarray.Dataset
            ``k`` [N/m] over ``position`` (coordinate ``cycles``), components, pair
            stiffness and load sharing; units in attributes.
        """
        return self.train.mesh_stiffness(mesh, revolution_of=revolution_of).to_dataset()

    def to_toml(self) -> str:
        """The effective configuration as TOML (SI units) that :func:`gearsim.loads` reads
        back to the same gearbox.

        Gears alone: :func:`gearsim.system.train_to_toml`; with planetary stages the graph
        form (:func:`gearsim.model.graph_toml.stages_to_toml`: shafts, stages, gears,
        meshes), whatever form the gearbox was read from.

        Returns
        -------
        str

        Raises
        ------
        InputError
            For a gearbox with stages the graph form cannot say (e.g. a study's variant
            with meshes of contacts; :mod:`gearsim.model.graph_toml`).
        """
        if self.stage is not None:
            return stages_to_toml(self)
        return train_to_toml(self.train, self.dynamics.to_dict())

    # ---- what is done with a gearbox --------------------------------------------------

    def simulate(self, *, harmonics: int = 1, force: bool | None = None,
                 **dynamics: Any):
        """Time response of the whole gearbox.

        Parameters
        ----------
        harmonics : int, optional
            Highest mesh harmonic the output rate must resolve (checked before the run,
            :meth:`check_run`).
        force : bool, optional
            Run above the cost bounds (:func:`gearsim.dynamics.simulate.check_cost`).
        **dynamics
            Changes to the ``[dynamics]`` settings, SI values.

        Returns
        -------
        xarray.Dataset
            :func:`gearsim.dynamics.simulate` (gears),
            :func:`gearsim.dynamics.stage.simulate_stage` (a stage) or
            :func:`gearsim.dynamics.compose.simulate_stage_chain` (a stage driving gears);
            with stages its attribute ``config`` is :meth:`to_toml` of the run (left out
            where that refuses).
        """
        settings = (dataclasses.replace(self.dynamics, **dynamics) if dynamics
                    else self.dynamics)
        if self.stage is None:
            from gearsim.dynamics.simulate import simulate

            return simulate(self.train, settings, harmonics=harmonics, force=force)
        run = dataclasses.replace(self, dynamics=settings)
        run.check_run(harmonics)
        if not self.chains and not self.next_stages:
            from gearsim.dynamics.stage import simulate_stage

            ds = simulate_stage(self.stage, self.members, settings)
        else:
            from gearsim.dynamics.compose import simulate_stage_chain

            try:
                ds = self._named_shafts(simulate_stage_chain(
                    self.stage, self.train, self.members, settings,
                    shaft_stiffness=self.shaft_stiffness, input_chain=self.input_train,
                    input_shaft_stiffness=self.input_shaft_stiffness, stages=self.next_stages))
            except InputError as exc:  # a shaft twisted by its torque: named as written
                raise InputError(written_name(exc.parameter, dict(self.written)), exc.value,
                                 self._shaft_names(exc.limit)) from None
        with contextlib.suppress(InputError):  # none for what no file says (a study's
            ds.attrs["config"] = run.to_toml()  # meshes of contacts: graph_toml)
        return ds

    def shaft_label(self, member: str) -> str:
        """The name of the shaft a stage member sits on (:attr:`member_shafts`), else the
        member's own name.

        Parameters
        ----------
        member : str
            As the results name it (``"carrier"``, ``"stage2-sun"``).

        Returns
        -------
        str
        """
        return dict(self.member_shafts).get(member, member)

    def _shaft_names(self, text: str) -> str:
        """``text`` with the shafts between stages under the names of the shafts their
        members sit on (:attr:`member_shafts`; ``shaft-stage1-carrier-stage2-sun`` ->
        ``mid``)."""
        n = len(self.stages)
        for k, nxt in enumerate(self.next_stages, 1):
            pre, prev = stage_prefix(k, n), self.stages[k - 1]
            ends = [stage_prefix(k - 1, n) + output_member(prev),
                    pre + nxt.train.operating.input]
            names = stage_shaft_names(stage_prefix(k - 1, n), prev, pre, nxt)
            # one shaft joins both members (named after the later's), two: one each
            for name, member in zip(names, ends[-len(names):], strict=True):
                text = text.replace(name, self.shaft_label(member))
        return text

    def _named_shafts(self, ds):
        """``ds`` with its tachos under the names of the shafts the members sit on; of two
        tachos of one shaft (a member and the gear on its shaft, two stages' members),
        the first."""
        if not self.member_shafts or "tacho" not in ds:
            return ds
        labels = [self.shaft_label(str(n)) for n in ds["shaft"].values]
        keep = [i for i, n in enumerate(labels) if n not in labels[:i]]
        ds = ds.isel(shaft=keep).assign_coords(shaft=[labels[i] for i in keep])
        if "analysis_parts" in ds.attrs:  # each stage's reference tacho, renamed alike
            parts = json.loads(ds.attrs["analysis_parts"])
            for st in parts["stages"]:
                if "tacho" in st:
                    st["tacho"] = self.shaft_label(st["tacho"])
            ds.attrs["analysis_parts"] = json.dumps(parts)
        return ds

    def record(self, spec: str, *, harmonics: int = 1, force: bool | None = None,
               **dynamics: Any) -> np.ndarray:
        """One record of :meth:`simulate`: ``self.select(self.simulate(...), spec)``.

        What a study analyses of each run. Of a gear train, a mesh force, transmission
        error, bearing force or acceleration is formed from the channels it needs only
        (:func:`gearsim.dynamics.simulate.simulate_record`: the same run, no dataset);
        every other record, and every record of a stage, through :meth:`select`.

        Parameters
        ----------
        spec : str
            A name of :meth:`signals`, e.g. ``"acceleration[input,y]"``.
        harmonics : int, optional
            As :meth:`simulate`.
        force : bool, optional
            As :meth:`simulate`.
        **dynamics
            Changes to the ``[dynamics]`` settings, SI values.

        Returns
        -------
        ndarray
            The record (float), equal to the selected variable to round-off (1e-13 of
            its peak: a study forms it after the filter, :meth:`simulate` before).

        Raises
        ------
        InputError
            As :meth:`simulate` and :meth:`select`.

        Examples
        --------
        >>> import numpy as np
        >>> import gearsim as gs
        >>> gb = gs.example("spur-19-48").replace(dynamics={"duration": 0.1, "fs": 2e4})
        >>> a = gb.record("acceleration[pinion,y]")
        >>> b = gb.select(gb.simulate(), "acceleration[pinion,y]")
        >>> bool(np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b)))  # to its peak
        True
        """
        if self.stage is None:
            from gearsim.dynamics.simulate import simulate_record

            settings = (dataclasses.replace(self.dynamics, **dynamics) if dynamics
                        else self.dynamics)
            key = self.signal_key(spec)
            x = None if key is None else simulate_record(
                self.train, key, settings, harmonics=harmonics, force=force)
            if x is not None:
                return x
        return self.select(self.simulate(harmonics=harmonics, force=force, **dynamics), spec)

    def summary(self, ds) -> dict:
        """Summary of a result of :meth:`simulate`: per mesh mean, RMS about the mean (the
        standard deviation, for every kind of gearbox), peak force [N].

        Parameters
        ----------
        ds : xarray.Dataset
            The result.

        Returns
        -------
        dict
            :func:`gearsim.dynamics.summary` or :func:`gearsim.dynamics.stage.stage_summary`.
        """
        if self.stage is None:
            from gearsim.dynamics.simulate import summary

            return summary(ds)
        from gearsim.dynamics.stage import stage_summary

        return stage_summary(ds)

    def tvms(self) -> GearboxStiffness:
        """Stiffness tables of every mesh (stage meshes first, then the gears').

        Returns
        -------
        GearboxStiffness
            Summary, writer and figure.
        """
        from gearsim.system import train_stiffness

        if self.stage is None:
            ts = train_stiffness(self.train)
            return GearboxStiffness(ts.summary(), ts.write, ts.plot)
        import xarray as xr

        from gearsim.system.planetary import stage_stiffness

        stage, n = self.stage, len(self.stages)
        parts = [stage_stiffness(st) for st in self.stages]
        summary = parts[0][0]
        if self.next_stages:  # the stages after the first
            summary["next_stages"] = [p[0] for p in parts[1:]]
        sets = [d.rename({x: x.replace("_", "_" + stage_prefix(k, n), 1)
                          for x in (*d.data_vars, *d.coords)}) if n > 1 else d
                for k, (_, d) in enumerate(parts)]  # named as the results name them
        names = iter(self._chain_mesh_names())
        chains = [train_stiffness(tr) for tr in self.chains]
        # the gears driving a stage under its "input_chain", those the last drives "chain"
        homes = [(p[0], "input_chain") for p, t in zip(
            parts, (self.input_train, *self._between()), strict=True) if t is not None]
        for (home, key), ts in zip([*homes, (summary, "chain")], chains, strict=False):
            home[key] = ts.summary()
            for i, m in enumerate(home[key]["meshes"]):
                m["mesh"] = name = next(names)
                r = ts.results[(i, 1)]  # over one revolution of its driver
                sets.append(xr.Dataset({f"k_{name}": (f"cycles_{name}", r.k, {"units": "N/m"})},
                                       coords={f"cycles_{name}": (f"cycles_{name}", r.cycles,
                                                                  {"units": "1"})}))
        ds = xr.merge(sets, combine_attrs="override")

        def write(path: str | Path) -> Path:
            from gearsim.io.atomic import atomic_write
            from gearsim.io.results import write_results

            if str(path).endswith(".nc"):
                return write_results(ds, path)

            def rows(tmp) -> None:
                with open(tmp, "w", encoding="utf-8") as f:
                    f.write(f"# gearsim TVMS of '{stage.name}'; stiffness in N/m along the "
                            "transverse line of action, cycles counted from each table's "
                            "start (forward sense)\nmesh,cycles,k\n")
                    for name in ds.data_vars:
                        mesh = name[2:]
                        for c, k in zip(ds[f"cycles_{mesh}"].values, ds[name].values,
                                        strict=True):
                            f.write(f"{mesh},{c:.10g},{k:.10g}\n")
            return atomic_write(path, rows)

        def figure():
            from gearsim.viz.planetary import plot_gearbox_meshes

            return plot_gearbox_meshes(self._in_flow(chains, list(self.stages)),
                                       self._chain_mesh_names())

        return GearboxStiffness(summary, write, figure)

    def layout(self) -> dict:
        """The gearbox as a graph: shafts, gears, meshes and the stage, with their numbers.

        Returns
        -------
        dict
            ``name``; ``stage`` (teeth, planets, held and input member, mesh frequency
            [Hz], member speeds [rpm] and torques [N m], and of a graph
            ``member_shafts``, the shaft each turning member sits on; with a stage);
            ``next_stages`` (the same of the stages after it); ``shafts`` in power-flow
            order (name, gears, the stage ``members`` on it as the results name them,
            speed [rpm] and torque [N m]: every shaft of the gears and of the stages'
            input and output members); ``meshes`` (driver -> driven, mesh frequency [Hz],
            static force [N]); ``plan``: the arguments of
            :func:`gearsim.viz.layout.plot_layout` (shaft centres from
            :func:`gearsim.dynamics.layout.layout`; ``stage``: one dict a stage, and the
            drawing of the gears between two stages between them).
        """
        from gearsim.dynamics.layout import idlers
        from gearsim.dynamics.layout import layout as plan

        out: dict = {"name": self.name, "shafts": [], "meshes": []}
        n, sts, at_members = len(self.stages), [], []
        for k, tr in enumerate(self.stages):  # the first as "stage", the others after it
            s, op, pre = tr.stage, tr.operating, stage_prefix(k, n)
            ends = {"input": op.input, "output": next(m for m in ("sun", "ring", "carrier")
                                                      if m not in (op.fixed, op.input))}
            entry = {"teeth": [s.sun_teeth, s.planet_teeth, s.ring_teeth],
                     "planets": s.planets, "fixed": op.fixed,
                     "input": op.input, "mesh_frequency_hz": tr.mesh_frequency,
                     "speeds_rpm": {m: w * 30 / math.pi for m, w in tr.speeds.items()},
                     "torques_Nm": dict(tr.torques)}
            shafts = {m: self.shaft_label(pre + m) for m in ("sun", "ring", "carrier")
                      if m != op.fixed}
            if self.member_shafts:  # a graph: the shaft each turning member sits on
                entry["member_shafts"] = shafts
            if k:
                out.setdefault("next_stages", []).append(entry)
            else:
                out["stage"] = entry
            at_members.append([{"name": shafts[m], "gears": [], "members": [pre + m],
                                "speed_rpm": abs(tr.speeds[m]) * 30 / math.pi,
                                "torque_Nm": abs(tr.torques[m])} for m in ends.values()])
            sts.append({"sun": s.sun.pitch_radius, "ring": s.ring.pitch_radius,
                        "planet": s.planet.pitch_radius, "centre": s.centre_distance,
                        "angles": list(s.planet_angles_value),
                        "teeth": (s.sun_teeth, s.planet_teeth, s.ring_teeth), **ends,
                        "fixed": op.fixed, "shafts": shafts,
                        **({"title": f"planetary stage {k + 1}"} if n > 1 else {})})
        drawings, rows = [], []  # of each chain, in power-flow order: (shafts, gears, links)
        names = self._chain_mesh_names()
        for train in self.chains:
            fl = train.flow
            first = len(out["meshes"])  # the meshes' names run through the chains
            rows.append([{"name": sh.name, "gears": list(sh.gears),
                          "speed_rpm": train.speed(i) * 30 / math.pi,
                          "torque_Nm": train.torque(i)}
                         for sh in fl.shafts for i in [train.gear_index(sh.gears[0])]])
            for m, p in enumerate(train.pairs):
                out["meshes"].append({"mesh": names[len(out["meshes"])],
                                      "driver": p.driver.name, "driven": p.driven.name,
                                      "mesh_frequency_hz": train.mesh_frequencies[m],
                                      "static_force_N": train.static_mesh_force(m)})
            lay = plan(train, self.dynamics.per_item("idler_angle", len(idlers(train)),
                                                     "idler"))
            drawings.append((
                [(sh.name, tuple(c)) for sh, c in zip(fl.shafts, lay.centres, strict=True)],
                [(g.name, fl.shaft_of[g.name], g.pitch_radius, g.teeth) for g in train.gears],
                [(p.driver.name, p.driven.name, names[first + m])
                 for m, p in enumerate(train.pairs)]))
        seen: dict[str, dict] = {}  # every shaft once, in power-flow order
        for row in (r for part in self._in_flow(rows, at_members) for r in part):
            if row["name"] in seen:  # a member's and a gear's, or two stages' members
                for key in ("gears", "members"):
                    seen[row["name"]][key] = seen[row["name"]].get(key, []) + row.get(key, [])
            else:
                seen[row["name"]] = row
        out["shafts"] = list(seen.values())
        panels = self._in_flow(drawings, sts)  # the gears between two stages among them
        downstream = panels.pop() if self.train is not None else ([], [], [])
        upstream = panels.pop(0) if self.input_train is not None else None
        out["plan"] = {"shafts": downstream[0], "gears": downstream[1],
                       "links": downstream[2], "stage": panels or None, "upstream": upstream}
        return out

    def gear_mesh(self, mesh: int, parameter: str = "mesh") -> tuple[GearTrain, int, str]:
        """Mesh ``mesh`` of the external gears, counted as :meth:`layout` and
        :meth:`simulate` name them (with a stage, the gears driving it first).

        Parameters
        ----------
        mesh : int
            From 0 (mesh I).
        parameter : str, optional
            Named in the refusal (``"--mesh"``).

        Returns
        -------
        train : GearTrain
            The gears holding it.
        index : int
            Its index in ``train``.
        name : str
            Its name (``"I"``, ...).

        Raises
        ------
        InputError
            No such mesh.
        """
        names, k = self._chain_mesh_names(), mesh
        n = len(names)
        require(isinstance(mesh, int) and 0 <= mesh < n, parameter, mesh,
                f"must be in 0 .. {n - 1} ({n} meshes)")
        for t in self.chains:
            if k < len(t.pairs):
                return t, k, names[mesh]
            k -= len(t.pairs)
        raise AssertionError(mesh)  # the names count every chain's meshes

    def _chain_mesh_names(self) -> tuple[str, ...]:
        """Names of the gears' meshes (those of a stage's result when there is a stage)."""
        if self.stage is None:
            return tuple(p.name for p in self.train.pairs)
        from gearsim.dynamics.stage import chain_mesh_names

        return chain_mesh_names(self.chains) if self.chains else ()

    # ---- parameter studies --------------------------------------------------------------

    def operating(self) -> tuple[float, float]:
        """Input speed [rad/s] and torque [N m] of the gearbox (its first part's input: the
        stage's input member, or gear 1 of gears ahead of a stage or without one).

        Returns
        -------
        tuple of float
        """
        op = (self.input_train or self.stage or self.train).operating
        return op.speed, op.torque

    def slowest_shaft(self) -> tuple[str, float]:
        """The rotating shaft (or stage member) with the lowest speed, and that speed [Hz].

        Returns
        -------
        tuple
            Name and absolute frequency [Hz].
        """
        f: dict[str, float] = {}
        for k, st in enumerate(self.stages):
            f.update({self.shaft_label(stage_prefix(k, len(self.stages)) + m):
                      abs(v) / (2.0 * math.pi) for m, v in st.speeds.items()
                      if m in ("sun", "carrier", "ring") and v != 0.0})
        for tr in self.chains:
            f.update({sh.name: abs(tr.shaft_frequency(tr.gear_index(sh.gears[0])))
                      for sh in tr.flow.shafts})
        m = min(f, key=f.get)
        return m, f[m]

    def check_run(self, harmonics: int = 1) -> None:
        """Refuse a run whose output rate aliases the mesh harmonics or whose cost is too
        large, before any work (:func:`gearsim.dynamics.simulate.check_cost` for gears).

        Parameters
        ----------
        harmonics : int, optional
            Highest mesh harmonic the output must resolve.

        Raises
        ------
        InputError
            ``dynamics.fs`` (aliasing) or the cost bounds.
        """
        if self.stage is None:
            from gearsim.dynamics.simulate import check_cost

            check_cost(self.train, self.dynamics, harmonics=harmonics)
            return
        f_m = max((*(s.mesh_frequency for s in self.stages),
                   *(f for t in self.chains for f in t.mesh_frequencies)))
        which = ("the mesh frequency f_m" if harmonics == 1 else
                 f"the highest analysed mesh harmonic {harmonics} f_m")
        require(self.dynamics.fs > 2.0 * harmonics * f_m, "dynamics.fs", self.dynamics.fs,
                f"must be > {2 * harmonics * f_m:.6g} Hz, twice {which} = "
                f"{harmonics * f_m:.6g} Hz, else the record is aliased")

    def signals(self) -> list[str]:
        """The records of :meth:`simulate` a study can analyse, in :meth:`select`'s form.

        Returns
        -------
        list of str
            Gears: ``mesh_force_i``, ``dte_i``, ``ste_i`` for each mesh ``i`` (1, 2, ...),
            then ``bearing_force[shaft,axis]`` and ``acceleration[shaft,axis]`` (LTA
            model: x, y, z; the seed's 3-DOF model: y; the torsional model has no
            bearing coordinates, so none), then, but for the seed's model,
            ``angular_acceleration[rotation]`` of each rotation coordinate (a shaft, or a
            gear of a shaft that twists between its gears) and ``shaft_torque[shaft:a-b]``
            of each such shaft's spring between its gears a and b. A stage: ``sensor`` (the ring's fixed
            transducer), ``mesh_force[sun-planet-1]``, ``mesh_force[ring-planet-1]``,
            ... and ``ring_acceleration[x]``, ``ring_acceleration[y]``; with stages in
            series ``stage_shaft_torque[shaft]`` of each shaft between two stages (two
            with gears between); with gears also ``chain_mesh_force[I]``, ...,
            ``shaft_torque`` (the shaft between the stages and the gears at an end) and
            ``chain_acceleration[shaft,axis]`` (LTA model).

        Examples
        --------
        >>> import gearsim as gs
        >>> names = gs.example("idler-table1").signals()
        >>> names[:3], "acceleration[input,y]" in names
        (['mesh_force_1', 'dte_1', 'ste_1'], True)
        >>> gs.example("nrel-grc").signals()[:3]
        ['sensor', 'mesh_force[sun-planet-1]', 'mesh_force[ring-planet-1]']
        """
        if self.stage is not None:
            out, n = ["sensor"], len(self.stages)
            for k, st in enumerate(self.stages):
                for j in range(st.stage.planets):
                    out += [f"mesh_force[{stage_prefix(k, n)}{m}-{planet_name(j)}]"
                            for m in ("sun", "ring")]
            out += [f"ring_acceleration[{a}]" for a in ("x", "y")]
            out += [f"stage_shaft_torque[{name}]" for k in range(1, n)
                    for name in stage_shaft_names(stage_prefix(k - 1, n), self.stages[k - 1],
                                                  stage_prefix(k, n), self.next_stages[k - 1])]
            if self.chains:  # the gears the stages drive, those driving them or between
                out += [f"chain_mesh_force[{name}]" for name in self._chain_mesh_names()]
                ends = [t for t in (self.input_train, self.train) if t is not None]
                out += ["shaft_torque"] if ends else []
                if len(ends) > 1:
                    out.append("input_shaft_torque")
                axes = LTA_AXES if self.dynamics.model == "lta" else ()
                out += [f"chain_acceleration[{sh.name},{a}]"
                        for t in self.chains for sh in t.flow.shafts for a in axes]
            return out
        out = []
        for i in range(len(self.train.pairs)):
            out += [f"mesh_force_{i + 1}", f"dte_{i + 1}", f"ste_{i + 1}"]
        model = self.dynamics.model
        axes = LTA_AXES if model == "lta" else ("y",) if model == "seed" else ()
        for var in ("bearing_force", "acceleration"):
            out += [f"{var}[{sh.name},{a}]" for sh in self.train.flow.shafts for a in axes]
        out += [f"angular_acceleration[{r}]" for r in self._rotations()]
        return out + ([] if model == "seed" else [  # the springs of twisting shafts
            f"shaft_torque[{sh.name}:{a}-{b}]" for sh in self.train.flow.shafts
            if sh.torsional_stiffness is not None
            for a, b in zip(sh.gears, sh.gears[1:], strict=False)])

    def _rotations(self) -> list[str]:
        """Labels of the rotation coordinates of a gear train's model (none: seed's)."""
        if self.dynamics.model == "seed":
            return []
        labels, _, _ = dof_map(self.train, self.dynamics.model)
        return [lab[:-len(".theta")] for lab in labels if lab.endswith(".theta")]

    @property
    def default_signal(self) -> str:
        """The record a study analyses by default: what a test rig measures.

        The y acceleration of the input shaft's bearing; in the torsional model, which
        has no bearing coordinates, the input's angular acceleration; the ring's fixed
        transducer (``sensor``) of a planetary stage.
        """
        if self.stage is not None:
            return "sensor"
        if self.dynamics.model == "torsional":
            return f"angular_acceleration[{self._rotations()[0]}]"
        return f"acceleration[{self.train.flow.shafts[0].name},y]"

    @property
    def default_bearings(self) -> bool:
        """Whether some bearing takes ``dynamics.bearing_stiffness`` (has none of its own):
        a stage member's or a shaft's of the gears."""
        members = (self.members, *(s.members for s in self.next_stages)) if self.stages else ()
        return (any(m not in d.bearings for d in members for m in _BEARING_MEMBERS)
                or any(sh.bearing_stiffness is None for t in self.chains for sh in t.flow.shafts))

    def _bearing_sites(self) -> dict[str, list[tuple[int, str]]]:
        """Shaft name -> what carries its bearings: ``(-1, shaft)`` a shaft of the gears,
        ``(k, member)`` a member of stage k (from 0); a stage member is named by the
        shaft it sits on (:meth:`shaft_label`), its planets ``planet`` (with stages in
        series ``stage<k>-planet``)."""
        sites: dict[str, list[tuple[int, str]]] = {}
        for t in self.chains:
            for sh in t.flow.shafts:
                sites.setdefault(sh.name, []).append((-1, sh.name))
        for k in range(len(self.stages)):
            pre = stage_prefix(k, len(self.stages))
            for m in _BEARING_MEMBERS:
                name = pre + m if m == "planet" else self.shaft_label(pre + m)
                sites.setdefault(name, []).append((k, m))
        return sites

    def bearing_names(self) -> tuple[str, ...]:
        """The bearings :meth:`with_bearing` can set, by the name of their shaft.

        Returns
        -------
        tuple of str
            Every shaft of the gears, and each stage member by the shaft it sits on
            (its own name when it sits on none; the planets' bearings ``planet``).

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("two-stage-reducer").bearing_names()
        ('input', 'intermediate', 'output')
        >>> gs.example("wind-turbine-grc").bearing_names()
        ('low-speed', 'intermediate', 'high-speed', 'planet', 'ring', 'rotor')
        """
        return tuple(self._bearing_sites())

    def with_bearing(self, shaft: str, stiffness: float) -> Gearbox:
        """The gearbox with the radial bearing stiffness of one shaft set.

        A shaft of the gears takes it as its ``bearing_stiffness`` (its axial stiffness
        follows it when not given, as in :func:`gearsim.dynamics.lta.build_lta`); a stage
        member as its translational bearing stiffness (planets: radial and tangential,
        Lin & Parker 1999). A shaft that carries a stage member and gears (the sun's shaft
        of a wind-turbine box) sets both.

        Parameters
        ----------
        shaft : str
            A name of :meth:`bearing_names`.
        stiffness : float
            Radial bearing stiffness [N/m], in the bounds of
            :class:`gearsim.system.graph.Shaft` (checked where it is set).

        Returns
        -------
        Gearbox

        Raises
        ------
        InputError
            ``bearing_stiffness[shaft]`` names no shaft, or the stiffness is out of bounds.

        Examples
        --------
        >>> import gearsim as gs
        >>> gb = gs.example("two-stage-reducer").with_bearing("intermediate", 2e8)
        >>> [sh.bearing_stiffness for sh in gb.train.flow.shafts]
        [None, 200000000.0, None]
        """
        sites = self._bearing_sites()
        require(shaft in sites, f"bearing_stiffness[{shaft}]", stiffness,
                "names no shaft of the gearbox; one of " + ", ".join(sites))
        gb = self
        for k, name in sites[shaft]:
            if k < 0:
                gb = gb._with_chains(tuple(dataclasses.replace(t, shafts=tuple(
                    dataclasses.replace(sh, bearing_stiffness=stiffness) if sh.name == name
                    else sh for sh in t.shafts)) for t in gb.chains))
            elif k == 0:
                gb = dataclasses.replace(gb, members=dataclasses.replace(
                    gb.members, bearings={**gb.members.bearings, name: stiffness}))
            else:
                nxt = list(gb.next_stages)
                d = nxt[k - 1].members
                nxt[k - 1] = dataclasses.replace(nxt[k - 1], members=dataclasses.replace(
                    d, bearings={**d.bearings, name: stiffness}))
                gb = dataclasses.replace(gb, next_stages=tuple(nxt))
        return gb

    def _with_chains(self, chains: tuple[GearTrain, ...]) -> Gearbox:
        """The gearbox with its gears (:attr:`chains`, in that order) replaced."""
        it = iter(chains)
        inp = None if self.input_train is None else next(it)
        nexts = tuple(s if s.input_train is None else dataclasses.replace(
            s, input_train=next(it)) for s in self.next_stages)
        return dataclasses.replace(self, input_train=inp, next_stages=nexts,
                                   train=None if self.train is None else next(it))

    @staticmethod
    def signal_key(spec: str) -> str | None:
        """``spec`` in the form of :meth:`signals` (blanks removed); ``None``: not a name.

        Parameters
        ----------
        spec : str
            As written, e.g. ``" acceleration[ input , y ]"``.

        Returns
        -------
        str or None
        """
        m = _SIGNAL.fullmatch(spec)
        if m is None:
            return None
        labels = [g for g in m.groups()[1:] if g]
        return f"{m.group(1)}[{','.join(labels)}]" if labels else m.group(1)

    def select(self, ds, spec: str) -> np.ndarray:
        """The record ``spec`` (a name of :meth:`signals`) of a result of :meth:`simulate`.

        Parameters
        ----------
        ds : xarray.Dataset
            The result.
        spec : str
            ``variable`` or ``variable[label]`` / ``variable[shaft,axis]``.

        Returns
        -------
        ndarray
            The record (float).

        Raises
        ------
        InputError
            ``study.signal``: not a variable, or not one record.
        """
        m = _SIGNAL.fullmatch(spec)
        if m is None or m.group(1) not in ds:
            raise InputError("study.signal", spec, "must name a simulated variable ("
                             + ", ".join(ds.data_vars) + "), with [label] where needed")
        da = ds[m.group(1)]
        labels = [g for g in m.groups()[1:] if g]
        dims = [d for d in da.dims if d != "time"]
        if len(labels) != len(dims):
            raise InputError("study.signal", spec, "select one record: variable["
                             + ",".join(dims) + "]" if dims else "has no labels")
        try:
            da = da.sel(dict(zip(dims, labels, strict=True)))
        except (KeyError, ValueError):
            raise InputError("study.signal", spec, "label not in the simulation") from None
        return np.asarray(da.values, dtype=float)

    def reference(self, shafts: str = "all", signal: str | None = None
                  ) -> tuple[str, float, list[int]]:
        """Reference shaft, its frequency and the tooth counts for the analysis.

        Gears: the input gear's shaft and every gear's teeth (``f_m = f_r1 Z_1``). A
        stage: ring or sun held, the carrier with ``Z_1 = z_r`` (ring held) or ``z_s``
        (sun held); carrier held, the ring with ``Z_1 = z_r``; then the other two tooth
        counts, so that ``f_m / Z_j`` are the member rotations relative to the carrier.
        Of stages in series, the stage the record belongs to (a mesh of stage k,
        ``mesh_force[stage<k>-...]``, and the shaft driving it, ``stage_shaft_torque``:
        stage k's member, named ``stage<k>-carrier`` as its tacho, teeth and speeds; the
        sensor and the ring's acceleration: the first stage's). A record of the gears
        beside a stage (``chain_...``, ``shaft_torque``, and the ``stage_shaft_torque``
        of the shaft from a stage to gears between two stages, which drives them): the
        gears' first shaft and teeth. Of gears whose power branches (alone, or after the
        last stage), the teeth on the path from their first shaft to the record's shaft
        (:meth:`GearTrain.path_kinematics`).

        Parameters
        ----------
        shafts : {"all", "reference"}
            Every tooth count, or the reference's only.
        signal : str, optional
            The analysed record (a name of :meth:`signals`); default: a stage's record.

        Returns
        -------
        member : str
            The reference shaft or member.
        frequency : float
            Its speed [Hz] (absolute value), ``f_r1`` of the analysis.
        teeth : list of int

        Examples
        --------
        >>> import gearsim as gs
        >>> member, f, teeth = gs.example("nrel-grc").reference()
        >>> member, teeth
        ('carrier', [99, 21, 39])
        """
        tr = self.train if self.stage is None else self._gears_record(signal)
        if tr is not None:
            path = self.record_path(signal)
            teeth = ([g.teeth for g in tr.gears] if path is None else list(
                path["teeth"] if "teeth" in path else [z for st in path["stages"] for z in st]))
            member, freq = tr.flow.shafts[0].name, tr.shaft_frequency(0)
        else:
            k = self._stage_record(signal)
            member, freq, teeth = self.stages[k].analysis_reference()
            member = self.shaft_label(stage_prefix(k, len(self.stages)) + member)  # the tacho's
        return member, freq, teeth[:1] if shafts == "reference" else teeth

    def record_path(self, signal: str | None) -> dict[str, tuple] | None:
        """Of gears whose power branches (alone, or those the last stage drives), the
        kinematics of the path to the shaft ``signal`` is a record of, else None (a
        record of the gears beside a stage naming no shaft or mesh, ``shaft_torque``: their
        first shaft).

        Parameters
        ----------
        signal : str or None
            A record's name (:meth:`gearsim.system.GearTrain.record_shaft`).

        Returns
        -------
        dict or None
            ``stages`` or ``teeth`` of :meth:`gearsim.system.GearTrain.path_kinematics`;
            None for a gearbox whose power does not branch, or a name of no shaft.
        """
        tr = self.train if self.stage is None else self._gears_record(signal)
        if tr is None or signal is None or len(tr.flow.outputs) < 2:
            return None
        if self.stage is None:
            k = tr.record_shaft(signal)
            return None if k is None else tr.path_kinematics(k)
        names, k = self._chain_mesh_names(), 0  # the gears the last stage drives
        for t in self.chains[:-1]:
            k += len(t.pairs)
        m = _SIGNAL.fullmatch(signal)  # a record of them: the mesh or shaft it names
        label = m.group(2) or tr.flow.shafts[0].name  # q[shaft.axis]: its shaft's
        path = chain_record_paths(tr, names[k:]).get(
            label.rpartition(".")[0] if m.group(1) == "q" else label)
        return None if path is None else {key: tuple(map(tuple, v)) if key == "stages"
                                          else tuple(v) for key, v in path.items()}

    def _stage_record(self, signal: str | None) -> int:
        """Index (from 0) of the stage ``signal`` is a record of: stage k for a mesh of
        stage k (``mesh_force[stage<k>-...]``) and the shaft driving it
        (``stage_shaft_torque[shaft-stage<k-1>-...-stage<k>-...]``), else the first."""
        m = None if signal is None else _SIGNAL.fullmatch(signal)
        if m is None or m.group(1) not in ("mesh_force", "stage_shaft_torque"):
            return 0
        return stage_of_label(m.group(2) or "", len(self.stages))

    def _gears_record(self, signal: str | None) -> GearTrain | None:
        """The gears beside a stage that ``signal`` is a record of, else None: the chain
        holding the shaft or mesh it names; ``shaft_torque`` the stage's output shaft's
        (else its input's), ``input_shaft_torque`` the input chain's, the
        ``stage_shaft_torque`` of the shaft from a stage to gears between two stages
        theirs (:func:`~gearsim.dynamics.compose.chain_of_record`)."""
        if self.stage is None or not self.chains or signal is None:
            return None
        m = _SIGNAL.fullmatch(signal)
        if m is None:
            return None
        names, k, meshes = self._chain_mesh_names(), 0, []
        for t in self.chains:
            meshes.append(list(names[k:k + len(t.pairs)]))
            k += len(t.pairs)
        n = len(self.stages)  # a chain between two stages: the shaft driving it
        between = [False] * (self.input_train is not None) + [
            stage_shaft_names(stage_prefix(k, n), self.stages[k], stage_prefix(k + 1, n), s)[0]
            for k, s in enumerate(self.next_stages) if s.input_train is not None
        ] + [False] * (self.train is not None)
        j = chain_of_record(m.group(1), m.group(2),
                            [[sh.name for sh in t.flow.shafts] for t in self.chains], meshes,
                            between)
        return None if j is None else self.chains[j]

    def analysis_stages(self, signal: str | None = None) -> tuple[tuple[int, int], ...] | None:
        """The stages of a compound gear train for the signal analysis, or None.

        A train whose meshes form one serial path from the input shaft, at least one of
        whose intermediate shafts carries two gears (the driven gear of one mesh and the
        driving gear of the next, e.g. the two-stage reducer), has one mesh frequency per
        stage: ``(driving teeth, driven teeth)`` of each mesh in power-flow order, for
        :func:`gearsim.signals.analysis.analyze` (``stages=``) with the reference shaft
        and frequency of :meth:`reference`. Shaft ``k + 1`` then turns at
        ``f_k z_k^d / z_k^n`` and stage ``k`` meshes at ``f_k z_k^d`` [Hz].

        Parameters
        ----------
        signal : str, optional
            The analysed record; a record of the gears beside a stage takes their stages.

        Returns
        -------
        tuple of (int, int) or None
            The stages; None when the simple-train analysis of :meth:`reference` applies
            (a planetary stage, a chain of idlers sharing one mesh frequency). Of a train
            whose power branches, the stages of the path from the input to the shaft of
            ``signal`` (:meth:`GearTrain.path_kinematics`; None without ``signal``).

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("two-stage-reducer").analysis_stages()
        ((32, 80), (48, 64))
        >>> gs.example("idler-table1").analysis_stages() is None
        True
        """
        tr = self.train if self.stage is None else self._gears_record(signal)
        if tr is None:
            return None
        path = self.record_path(signal)  # power that branches: the record's path
        if path is not None:
            return path.get("stages")
        return tr.compound_stages()  # the rule the results' attribute follows

    def measured_kinematics(self, parameter: str = "config") -> dict[str, Any]:
        """What the analysis of a measured record of this gearbox takes from it.

        A record measured on the input shaft of gears: their teeth or stages
        (:meth:`analysis_train`); of a lone planetary stage with the ring held, measured
        at the carrier: the stage (``--stage`` of ``gearsim analyze``).

        Parameters
        ----------
        parameter : str, optional
            Named in the refusal (``"--config"``).

        Returns
        -------
        dict
            ``speed`` [Hz] (the nominal input speed, or the carrier's), and ``teeth``
            (tuple of int), ``stages`` (tuple of (int, int)) or ``stage``
            ``(z_s, z_p, z_r, N)``.

        Raises
        ------
        InputError
            For stages with other parts, or a stage whose ring turns: no one record
            kinematics (analyse the part measured with its own stages or stage).

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("nrel-grc").measured_kinematics()["stage"]
        (21, 39, 99, 3)
        """
        if not self.stages:
            fl = self.train.flow
            if len(fl.outputs) > 1:  # no one compound train: each output its own path
                paths = "; ".join(
                    f"{fl.shafts[k].name}: " + ",".join(
                        f"{a}/{b}" for a, b in _path_stages(self.train.path_kinematics(k)))
                    for k in fl.outputs)
                raise InputError(parameter, self.name, "its power branches, so the stages "
                                 "depend on the shaft measured: give --stages of its path "
                                 f"({paths})")
            kin = self.analysis_train()
            what = ({"stages": kin["stages"]} if "stages" in kin
                    else {"teeth": tuple(kin["teeth"])})
            return {"speed": kin["shaft_frequency"], **what}
        tr = self.stage
        require(len(self.stages) == 1 and not self.chains and tr.operating.fixed == "ring",
                parameter, self.name, "the records of a gearbox with a planetary stage and "
                "other parts, or of a stage whose ring turns, are analysed with --stages or "
                "--stage for the part measured (a lone stage with the ring held is read "
                "from --config)")
        st = tr.stage
        _, f_carrier, _ = tr.analysis_reference()  # the carrier, with the ring held
        return {"speed": f_carrier,
                "stage": (st.sun_teeth, st.planet_teeth, st.ring_teeth, st.planets)}

    def analysis_train(self, shafts: str = "all", signal: str | None = None) -> dict[str, Any]:
        """The train and speed arguments of the analysis of a record of this gearbox.

        Parameters
        ----------
        shafts : {"all", "reference"}
            Every stage and shaft, or the reference gear's mesh only.
        signal : str, optional
            The analysed record (:meth:`reference`).

        Returns
        -------
        dict
            ``shaft_frequency`` [Hz] of :meth:`reference`, and ``stages``
            (:meth:`analysis_stages`, a compound train with ``shafts="all"``) or ``teeth``
            (:meth:`reference`'s tooth counts): keywords of
            :func:`gearsim.signals.analysis.analyze` and
            :func:`gearsim.signals.analysis.kinematics`.

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("two-stage-reducer").analysis_train()["stages"]
        ((32, 80), (48, 64))
        >>> gs.example("spur-19-48").analysis_train("reference")["teeth"]
        [19]
        """
        _, f_ref, teeth = self.reference(shafts, signal)
        stages = self.analysis_stages(signal) if shafts != "reference" else None
        return {"shaft_frequency": f_ref,
                **({"stages": stages} if stages is not None else {"teeth": teeth})}

    def at(self, *, speed: float, torque: float) -> Gearbox:
        """The gearbox at another input speed [rad/s] and torque [N m] (checked).

        Parameters
        ----------
        speed, torque : float
            Of the input (:meth:`operating`: the stage's input member, or gear 1 of gears
            ahead of a stage or without one).

        Returns
        -------
        Gearbox
        """
        if self.stage is None:
            return self._parts(None, dataclasses.replace(
                self.train, operating=Operating(speed=speed, torque=torque)))
        op = self.stage.operating
        inp = self.input_train
        if inp is not None:  # the gears take the input, the stage their output
            inp = dataclasses.replace(inp, operating=Operating(speed=speed, torque=torque))
            last = stage_operating(inp, op.fixed, op.input)
            speed, torque = last.speed, last.torque
        stage = dataclasses.replace(self.stage, operating=StageOperating(
            fixed=op.fixed, input=op.input, speed=speed, torque=torque))
        nexts, last = [], stage
        for s in self.next_stages:  # each stage at the previous one's output (or that of
            o, mid = s.train.operating, s.input_train  # the gears between, at its output)
            if mid is not None:
                mid = dataclasses.replace(mid, operating=chain_operating(last))
            last = dataclasses.replace(s.train, operating=next_operating(
                last, o.fixed, o.input) if mid is None else stage_operating(mid, o.fixed, o.input))
            nexts.append(dataclasses.replace(s, train=last, input_train=mid))
        train = self.train
        if train is not None:  # the gears run at the last stage output's speed and torque
            train = dataclasses.replace(train, operating=chain_operating(last))
        return dataclasses.replace(self._parts(stage, train, inp), next_stages=tuple(nexts))


def _stage_crack(stage: PlanetaryTrain, flank: str | None, depth: float | None,
                 closure: str | None) -> PlanetaryTrain:
    """``stage`` with its cracks moved to ``flank`` (``"none"``: removed) and ``depth``
    [m], its crack-face model ``closure`` (:meth:`Gearbox.with_crack`)."""
    cracks = stage.cracks
    if flank not in (None, "none") and cracks:
        constant = (stage.sun_mesh_stiffness is not None
                    and (stage.ring_mesh_stiffness is not None
                         or not any(c.gear.startswith("planet-") for c in cracks)))
        require(not constant, "crack", flank, "changes nothing: the meshes of the "
                "cracked member have constant stiffnesses (stage.sun_mesh_stiffness, "
                "stage.ring_mesh_stiffness); leave them out to compute the tables")
        cracks = tuple(dataclasses.replace(c, flank=flank) for c in cracks)
    if depth is not None and flank != "none":
        cracks = tuple(dataclasses.replace(c, depth=depth) for c in cracks)
    settings = stage.settings if closure is None else dataclasses.replace(
        stage.settings, closure=closure)
    return dataclasses.replace(stage, settings=settings,
                               cracks=() if flank == "none" else cracks)


def _path_stages(kin: dict[str, tuple]) -> tuple[tuple[int, int], ...]:
    """The stages of :meth:`GearTrain.path_kinematics`: its ``stages``, or consecutive
    pairs of its ``teeth`` (an idler chain: the same speeds and mesh frequencies)."""
    z = kin.get("teeth")
    return kin["stages"] if z is None else tuple(zip(z, z[1:], strict=False))
