"""The notebook API: one function per task, on the typed :class:`~gearsim.model.Gearbox`.

These are thin, documented entry points over the layers below; the CLI verbs do the
same work. Every function refuses bad input with :class:`gearsim.errors.InputError`
before any work starts. Results are xarray objects (units in attributes) or result
objects with ``to_dict()`` / ``plot()``.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gearsim.io.measured import MeasuredSignal, read_signal
from gearsim.model import Gearbox, load
from gearsim.signals.analysis import Analysis
from gearsim.signals.analysis import analyze as _analyze
from gearsim.studies.reproduce import ReproduceOptions, Reproduction, run_reproduction
from gearsim.studies.sweep import load_study
from gearsim.studies.sweep_run import SweepResult, run_study

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = ["Analysis", "MeasuredSignal", "analyze", "read_signal", "reproduce", "simulate",
           "sweep"]


def _gearbox(model: Gearbox | str | Path) -> Gearbox:
    return model if isinstance(model, Gearbox) else load(model)


def analyze(x: Any, fs: float, *, gearbox: Gearbox | str | Path | None = None,
            signal: str | None = None, **options: Any) -> Analysis:
    """Analyse a record (:func:`gearsim.signals.analysis.analyze`), optionally of a gearbox.

    Parameters
    ----------
    x : array_like or xarray.DataArray
        The record (any units, e.g. a mesh force [N] of :func:`simulate`).
    fs : float
        Sampling rate [Hz].
    gearbox : Gearbox, str or Path, optional
        The simulated gearbox (or a TOML file or example name): what ``options`` do not
        give is taken from it, the reference shaft frequency (``shaft_frequency`` [Hz],
        unless a ``tacho`` is given), the train (:meth:`~gearsim.model.Gearbox.
        analysis_stages` for a compound train, every stage's mesh analysed; else the
        tooth counts of :meth:`~gearsim.model.Gearbox.reference`, as for a simple
        train or a planetary stage) and the ``[analysis]`` settings.
    signal : str, optional
        Which record of ``gearbox`` ``x`` is (a name of :meth:`~gearsim.model.Gearbox.
        signals`, e.g. ``"mesh_force[stage2-sun-planet-1]"``): its part's kinematics
        (a stage in series, the gears beside a stage); default the gearbox's input part.
    **options
        Keywords of :func:`gearsim.signals.analysis.analyze`: ``teeth`` or ``stages``,
        ``shaft_frequency`` or ``tacho``, ``baseline``, ``settings``, analysis options.

    Returns
    -------
    Analysis
        Every result; ``to_dict()`` for JSON, ``plot(kind)`` for figures.

    Raises
    ------
    InputError
        As :func:`gearsim.signals.analysis.analyze`.

    Examples
    --------
    >>> import gearsim as gs
    >>> gb = gs.example("two-stage-reducer")
    >>> run = gs.simulate(gb, duration=0.5, fs=20e3)  # doctest: +SKIP
    >>> a = gs.analyze(run["mesh_force_1"], 20e3, gearbox=gb)  # doctest: +SKIP
    >>> [s["mesh_frequency_hz"] for s in a.to_dict()["train"]["stages"]]  # doctest: +SKIP
    [960.0, 576.0]
    """
    values = getattr(x, "values", x)
    if gearbox is not None:
        gb = _gearbox(gearbox)
        train = gb.analysis_train(signal=signal)
        f_ref = train.pop("shaft_frequency")
        if "teeth" not in options and "stages" not in options:
            options |= train
        if "shaft_frequency" not in options and options.get("tacho") is None:
            options["shaft_frequency"] = f_ref
        options.setdefault("settings", gb.analysis)
    return _analyze(values, fs, **options)


def simulate(gearbox: Gearbox | str | Path, /, *, crack: str | None = None,
             **dynamics: Any) -> xr.Dataset:
    """Simulate the vibration of a gearbox.

    Parameters
    ----------
    gearbox : Gearbox, str or Path
        A gearbox (:func:`gearsim.load`), a TOML file or a built-in example name
        (positional: ``model`` is the dynamics option, e.g. ``model="torsional"``);
        :meth:`gearsim.model.Gearbox.simulate` runs it.
    crack : {"none", "working", "non-working"}, optional
        Fault variant (:meth:`gearsim.system.GearTrain.with_crack`); default as given.
    **dynamics
        Changes to the ``[dynamics]`` settings, SI values (e.g. ``duration=0.2``,
        ``fs=20e3``, ``model="seed"``).

    Returns
    -------
    xarray.Dataset
        Mesh forces [N], dynamic transmission errors [m], bearing forces [N],
        accelerations [m/s^2] over ``time`` [s]; the effective configuration and the
        gearsim version in the attributes.

    Examples
    --------
    >>> import gearsim as gs
    >>> ds = gs.simulate("spur-19-48", duration=0.05, fs=10e3)  # doctest: +SKIP
    >>> ds["mesh_force_1"].attrs["units"]  # doctest: +SKIP
    'N'
    """
    gb = _gearbox(gearbox)
    if crack is not None:
        gb = gb.with_crack(crack)
    return gb.simulate(**dynamics)


def reproduce(out: str | Path, *, progress: Callable[[str], None] | None = None,
              **options: Any) -> Reproduction:
    """Run the source paper's study and write its report into ``out``.

    Parameters
    ----------
    out : str or Path
        Output folder (report.html, claims.json, figures/, dynamic_load.nc).
    progress : callable, optional
        Called with a short message before each step.
    **options
        Fields of :class:`gearsim.studies.reproduce.ReproduceOptions` (SI units), e.g.
        ``revolutions=16, fe=False, depth=6e-3``.

    Returns
    -------
    Reproduction
        Every number of the report (claims, findings, metrics, stiffness curves).
    """
    return run_reproduction(out, ReproduceOptions(**options), progress=progress)


def sweep(study: str | Path, out: str | Path, *, workers: int = 2,
          scheduler: str | None = None, progress: bool = False,
          batch: int | None = None) -> SweepResult:
    """Run a parameter study (TOML file, ``"diagnostic"`` or ``"faults"``) on Dask into a
    NetCDF store.

    Parameters
    ----------
    study : str or Path
        Study file, or the name of a built-in study.
    out : str or Path
        The store (``.nc``); finished cases are kept in ``out.parts/`` for resuming.
    workers : int, optional
        Local worker processes (ignored with ``scheduler``).
    scheduler : str, optional
        Address of a running Dask scheduler.
    progress : bool, optional
        Show a progress bar.
    batch : int, optional
        Simulation groups per Dask task (default: about ten tasks per worker, at most
        32 groups a task; :func:`gearsim.studies.sweep_run.plan_batch`). The store is the
        same whatever the batch; a size that cannot work (< 1, not an integer) is
        refused with :class:`gearsim.errors.InputError`, as ``gearsim sweep --batch``.

    Returns
    -------
    SweepResult
        The store path and how many cases were computed, skipped and failed; open the
        store with :func:`xarray.open_dataset`.
    """
    return run_study(load_study(study), out, workers=workers, scheduler=scheduler,
                     progress=progress, batch=batch)
